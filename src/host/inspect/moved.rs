//! Free space around a section that a geometric correction found moved:
//! the design's free space carried along by the correction's rigid part,
//! so that the moves to the corrected section's scan (its positioning,
//! approach and retracts) go round the part where it stands, not where
//! the design puts it.
//!
//! Only the turn and the translation are carried: the scales and the
//! offset change the section's size by a fraction of a millimetre, which
//! the clearance margins cover. The probe's posture is checked with the
//! stylus standing as it does on the machine; the correction turns the
//! part about the section plane's normal by a few degrees at most, which
//! leaves the stylus in the checks within that of its true direction.
use super::correction::DesignPoint;
use super::{CurveCtx, CurveResult, Learned};
use crate::host::modes::{park, FreeSpace};
use crate::math::{Mat3, Point3, Vec3};
use crate::program::Pose;
use crate::seam::ProbePart;

/// A rigid motion of the machine frame: `x -> rotation x + shift`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMap {
    rotation: Mat3,
    shift: Vec3,
}

impl RigidMap {
    /// The motion `(r, t)` of the part frame (`p -> r p + t`, as
    /// [`super::correction::Correction::rigid`] gives it) seen in the
    /// machine frame of `pose`.
    pub fn of_part_motion(pose: &Pose, (r, t): (Mat3, Vec3)) -> RigidMap {
        let (p, big_t) = (pose.rotation, pose.translation);
        let rotation = p * r * p.transpose();
        RigidMap {
            rotation,
            shift: big_t + p * t - rotation * big_t,
        }
    }

    /// This motion after `first`.
    pub fn after(&self, first: &RigidMap) -> RigidMap {
        RigidMap {
            rotation: self.rotation * first.rotation,
            shift: self.rotation * first.shift + self.shift,
        }
    }

    /// Where the motion takes `p`.
    pub fn forward(&self, p: Point3) -> Point3 {
        Point3::from(self.rotation * p.coords + self.shift)
    }

    /// The point the motion takes to `p`.
    pub fn back(&self, p: Point3) -> Point3 {
        Point3::from(self.rotation.transpose() * (p.coords - self.shift))
    }
}

/// The free space `inner` moved by `map` (see the module docs).
pub struct Moved<'f> {
    inner: &'f dyn FreeSpace,
    map: RigidMap,
}

impl<'f> Moved<'f> {
    /// `inner` moved by `map`.
    pub fn new(inner: &'f dyn FreeSpace, map: RigidMap) -> Moved<'f> {
        Moved { inner, map }
    }
}

impl FreeSpace for Moved<'_> {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        let back = |p| self.map.back(p);
        self.inner.segment_clear(back(from), back(to))
    }

    fn segment_clear_with(&self, from: Point3, to: Point3, tight: bool) -> bool {
        let back = |p| self.map.back(p);
        self.inner.segment_clear_with(back(from), back(to), tight)
    }

    fn start_clear(&self, at: Point3) -> bool {
        self.inner.start_clear(self.map.back(at))
    }

    fn approach_clear(&self, from: Point3, to: Point3) -> bool {
        let back = |p| self.map.back(p);
        self.inner.approach_clear(back(from), back(to))
    }

    fn margin_mm(&self) -> Option<f64> {
        self.inner.margin_mm()
    }

    fn posture(&self, ball: Point3) -> Option<ProbePart> {
        self.inner.posture(self.map.back(ball))
    }

    fn body_clear(&self, ball: Point3) -> bool {
        self.inner.body_clear(self.map.back(ball))
    }

    fn in_material(&self, p: Point3) -> bool {
        self.inner.in_material(self.map.back(p))
    }

    fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
        let (d, n) = self.inner.design_foot(self.map.back(p))?;
        Some((d, self.map.rotation * n))
    }

    /// The way in is where the probe went: kept as it is.
    fn note_way(&self, from: Point3, waypoints: &[Point3]) {
        self.inner.note_way(from, waypoints);
    }

    fn way_in(&self) -> Vec<Point3> {
        self.inner.way_in()
    }
}

/// The motion `before` followed by the rigid part of `learned`, in
/// machine coordinates (`before` as it is when `learned` has none).
pub(super) fn moved_by(
    ctx: &CurveCtx,
    learned: &Learned,
    before: Option<RigidMap>,
) -> Option<RigidMap> {
    let Some(part_motion) = learned.rigid() else {
        return before;
    };
    let map = RigidMap::of_part_motion(&ctx.pose, part_motion);
    Some(before.map_or(map, |b| map.after(&b)))
}

/// Rises out of the section `design` (machine coordinates by `ctx`'s
/// pose) through the free space moved by `map` when `map` moves it by
/// more than [`super::supervisor::SupervisorOptions::leave_moved_mm`]; a move that stops
/// short is noted.
pub(super) fn leave_moved(
    ctx: &mut CurveCtx,
    (map, design): (RigidMap, &[DesignPoint]),
    res: &mut CurveResult,
) {
    let shift = |d: &DesignPoint| {
        let p = ctx.pose.to_machine(d.point);
        (p - map.back(p)).norm()
    };
    let most = design.iter().map(shift).fold(0.0, f64::max);
    let Some(inner) = ctx.free.filter(|_| most > ctx.supervisor.leave_moved_mm) else {
        return;
    };
    let free = Moved::new(inner, map);
    if let Err(stop) = park(ctx.cmm, ctx.probe, Some(&free), &ctx.modes) {
        let why = serde_json::to_value(stop.outcome).ok();
        let why = why.as_ref().and_then(|v| v.as_str()).unwrap_or("stopped");
        res.notes.push(format!(
            "the move up out of the section, found {most:.2} mm off its design place, ended {why}"
        ));
    }
}

/// `f` on `ctx` with its free space moved by `map` (as it is without one).
pub(super) fn in_moved<R>(
    ctx: &mut CurveCtx,
    map: Option<RigidMap>,
    f: impl FnOnce(&mut CurveCtx) -> R,
) -> R {
    let (Some(map), Some(inner)) = (map, ctx.free) else {
        return f(ctx);
    };
    let moved = Moved::new(inner, map);
    f(&mut ctx.with_free(Some(&moved)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotation_xyz_deg;

    /// A part motion seen in the machine frame of a turned, moved pose
    /// takes each machine point where the pose takes the moved part point.
    #[test]
    fn a_part_motion_in_the_machine_frame_commutes_with_the_pose() {
        let pose = Pose {
            rotation: rotation_xyz_deg([10.0, -20.0, 35.0]),
            translation: Vec3::new(300.0, 400.0, 50.0),
        };
        let r = rotation_xyz_deg([0.0, 0.0, 4.0]);
        let t = Vec3::new(1.5, -0.7, 0.2);
        let map = RigidMap::of_part_motion(&pose, (r, t));
        for p in [Point3::new(0.0, 0.0, 0.0), Point3::new(12.0, -40.0, 7.5)] {
            let moved = pose.to_machine(Point3::from(r * p.coords + t));
            assert!((map.forward(pose.to_machine(p)) - moved).norm() < 1e-9);
            assert!((map.back(moved) - pose.to_machine(p)).norm() < 1e-9);
        }
        let twice = map.after(&map);
        let p = Point3::new(3.0, 2.0, 1.0);
        assert!((twice.forward(p) - map.forward(map.forward(p))).norm() < 1e-9);
    }

    /// Material at x >= 1.
    struct Wall;

    impl FreeSpace for Wall {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            from.x < 1.0 && to.x < 1.0
        }
        fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
            Some((1.0 - p.x, -Vec3::x()))
        }
    }

    /// The wall moved 2 mm along x, or turned 90 degrees about z (its
    /// material then at y >= 1): the moved free space answers for the wall
    /// where it stands.
    #[test]
    fn moved_free_space_answers_for_the_moved_part() {
        let shifted = RigidMap {
            rotation: Mat3::identity(),
            shift: Vec3::new(2.0, 0.0, 0.0),
        };
        let free = Moved::new(&Wall, shifted);
        let (a, b) = (Point3::new(0.0, 0.0, 0.0), Point3::new(2.5, 0.0, 0.0));
        assert!(!Wall.segment_clear(a, b));
        assert!(free.segment_clear(a, b));
        assert!(!free.segment_clear(a, Point3::new(3.5, 0.0, 0.0)));
        let turned = RigidMap {
            rotation: rotation_xyz_deg([0.0, 0.0, 90.0]),
            shift: Vec3::zeros(),
        };
        let free = Moved::new(&Wall, turned);
        let (d, n) = free.design_foot(Point3::new(0.0, 0.5, 0.0)).unwrap();
        assert!((d - 0.5).abs() < 1e-12, "{d}");
        assert!((n - (-Vec3::y())).norm() < 1e-12, "{n:?}");
    }
}
