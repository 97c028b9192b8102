//! Free space around the nominal part for direct moves between
//! measurements ([`crate::host::modes::direct_move`]).
//!
//! A straight move is clear when every sampled position of the ball and of
//! the stylus shaft along it keeps the ball radius plus a margin from every
//! nominal surface. The move's two ends lie outside the material, so the
//! line can only enter it by crossing a surface, which the samples would
//! come too close to (their spacing is below the required distance). Only
//! the design data's surfaces are obstacles: fixtures and faces missing
//! from the design data are not known to the software.
use crate::host::modes::FreeSpace;
use crate::math::{Point3, Vec3};
use crate::program::Pose;
use crate::workpiece::Workpiece;

/// Margins of the direct-move check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceOptions {
    /// Free distance kept between the ball (or stylus) and the nominal
    /// surfaces, mm. Covers the as-machined part's deviation from the
    /// design data (the trajectory tolerance and more).
    pub margin_mm: f64,
    /// Spacing of the samples along the move and along the stylus, mm
    /// (must stay below the ball radius plus the margin).
    pub step_mm: f64,
}

impl Default for ClearanceOptions {
    fn default() -> Self {
        ClearanceOptions {
            margin_mm: 4.0,
            step_mm: 2.0,
        }
    }
}

/// The nominal part on the machine, with the probe's ball and stylus.
pub struct PartClearance<'w> {
    /// Design data.
    pub workpiece: &'w Workpiece,
    /// Part to machine.
    pub pose: Pose,
    /// Ball centre to probe mount along the stylus, machine coordinates, mm.
    pub stylus: Vec3,
    /// Ball radius, mm.
    pub tip_radius_mm: f64,
    /// Margins.
    pub opts: ClearanceOptions,
}

impl PartClearance<'_> {
    /// A lower bound of the distance from the ball centre at `p` (machine)
    /// to the part: the distance to the nearest leaf box of the faces'
    /// search trees (each face's search starts from its nearest leaf of
    /// the previous sample, `hints`), exact (a projection) once that comes
    /// closer than `need`; projection failures count as touching (0).
    fn distance_bound(&self, p: Point3, need: f64, hints: &mut [Option<usize>]) -> f64 {
        let q = self.pose.to_part(p);
        let bound = self
            .workpiece
            .faces
            .iter()
            .zip(hints.iter_mut())
            .map(|(f, hint)| {
                let (d, nearest) = f.index.box_distance_near(q, *hint);
                *hint = nearest;
                d
            })
            .fold(f64::INFINITY, f64::min);
        if bound >= need {
            return bound;
        }
        self.workpiece
            .closest_point(q)
            .map_or(0.0, |fp| fp.projection.distance)
    }

    /// Whether every point of the straight line `a -> b` keeps `need` from
    /// the part, marching by sphere tracing: a sample at distance `d` clears
    /// the next `d - need` of the line outright; shorter skips fall back to
    /// `step`, below `need`, so a surface crossing between two samples
    /// would come closer than `need` to one of them.
    fn line_clear(
        &self,
        (a, b): (Point3, Point3),
        need: f64,
        step: f64,
        hints: &mut [Option<usize>],
    ) -> bool {
        let len = (b - a).norm();
        let dir = (b - a).try_normalize(0.0).unwrap_or_else(Vec3::zeros);
        let mut t: f64 = 0.0;
        loop {
            let d = self.distance_bound(a + dir * t, need, hints);
            if d < need {
                return false;
            }
            if t >= len {
                return true;
            }
            t = (t + (d - need).max(step)).min(len);
        }
    }
}

impl FreeSpace for PartClearance<'_> {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        let step = self.opts.step_mm.max(1e-3);
        let need = self.tip_radius_mm + self.opts.margin_mm;
        let up = (self.stylus.norm() / step).ceil() as usize;
        let mut hints = vec![None; self.workpiece.faces.len()];
        (0..=up).all(|j| {
            let shaft = if up == 0 { 0.0 } else { j as f64 / up as f64 };
            let lift = self.stylus * shaft;
            self.line_clear((from + lift, to + lift), need, step, &mut hints)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;
    use crate::workpiece::examples::reference_sphere;
    use std::path::Path;

    /// The d25 sphere at the origin, ball radius 1.5 mm, margin 4 mm, a
    /// 10 mm stylus pointing up: a move along x at height 0 and offset `y0`
    /// keeps `y0 - 12.5` from the sphere (closest at x = 0, at the ball),
    /// so it is clear exactly when `y0 >= 18`.
    fn sphere_clearance(wp: &Workpiece) -> PartClearance<'_> {
        PartClearance {
            workpiece: wp,
            pose: Pose {
                rotation: Mat3::identity(),
                translation: Vec3::zeros(),
            },
            stylus: Vec3::new(0.0, 0.0, 10.0),
            tip_radius_mm: 1.5,
            opts: ClearanceOptions::default(),
        }
    }

    #[test]
    fn moves_past_a_sphere_are_clear_exactly_beyond_the_margin() {
        let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
            Ok(wp) => wp,
            Err(e) => panic!("{e}"),
        };
        let c = sphere_clearance(&wp);
        for (y0, clear) in [(18.2, true), (17.8, false), (30.0, true), (0.0, false)] {
            let (a, b) = (Point3::new(-60.0, y0, 0.0), Point3::new(60.0, y0, 0.0));
            assert_eq!(c.segment_clear(a, b), clear, "y0 = {y0}");
        }
        // A move that ends far away but dips past the sphere's side.
        let (a, b) = (Point3::new(-40.0, 40.0, 0.0), Point3::new(40.0, -40.0, 0.0));
        assert!(!c.segment_clear(a, b), "diagonal through the centre");
        // Only the stylus comes close: the ball passes 20 mm below the
        // sphere's bottom, the shaft's top 10 mm higher is 15 mm from it.
        let (a, b) = (
            Point3::new(-60.0, 0.0, -32.5),
            Point3::new(60.0, 0.0, -32.5),
        );
        assert!(c.segment_clear(a, b));
        let (a, b) = (
            Point3::new(-60.0, 0.0, -25.0),
            Point3::new(60.0, 0.0, -25.0),
        );
        assert!(
            !c.segment_clear(a, b),
            "the shaft's top passes 2.5 mm from the sphere"
        );
    }
}
