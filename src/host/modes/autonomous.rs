//! Autonomous scanning (no design path): move sideways to the measured
//! deflection direction within the scanning plane, hold the deflection,
//! stay in the plane. Closes on its start for a closed section; stops at the
//! section end for an open one.
use super::approach_standoff;
use super::touch::finish;
use super::{reposition, Attempt, FreeSpace, HostProbe, ModeOptions, Outcome, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::math::{Point3, Vec3};

/// Where and how an autonomous scan runs (machine coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutonomousTask {
    /// Nominal start point on the surface.
    pub start: Point3,
    /// Outward normal there.
    pub start_normal: Vec3,
    /// Initial scanning direction (tangent of the nominal section).
    pub direction: Vec3,
    /// Scanning plane: a point and unit normal.
    pub plane: (Point3, Vec3),
    /// Nominal end point of an open section (`None` = closed section).
    pub end: Option<(Point3, Vec3)>,
    /// The nominal section's last stretch, for the test of a ball rolled
    /// over the part's end ([`EndPath`]).
    pub end_path: EndPath,
    /// Nominal section length, mm (bounds the scan at three times it).
    pub nominal_length_mm: f64,
    /// Wanted deflection, mm.
    pub deflection_mm: f64,
    /// Reported point spacing, mm.
    pub pitch_mm: f64,
}

/// Most points an [`EndPath`] holds.
const END_PATH_POINTS: usize = 16;

/// Points of an open section's nominal path near its end (machine
/// coordinates, mm) with the path's unit tangent there, in the scanning
/// direction: a ball rolled over the part's end has a measured normal that
/// leans towards the path's own tangent where it is, while on a floor
/// that curves up into the wall the section ends on, the normal leans
/// towards the end tangent but stays across the path's tangent.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EndPath {
    points: [(Point3, Vec3); END_PATH_POINTS],
    len: usize,
}

impl EndPath {
    /// The path through `points` (in scanning order, the last at the end),
    /// each with its tangent from its neighbours; at most
    /// [`END_PATH_POINTS`] of them, spread over the stretch.
    pub fn new(points: &[Point3]) -> EndPath {
        let mut out = EndPath::default();
        let n = points.len();
        let every = n.div_ceil(END_PATH_POINTS).max(1);
        for k in (0..n).rev().step_by(every).take(END_PATH_POINTS) {
            let (a, b) = (points[k.saturating_sub(1)], points[(k + 1).min(n - 1)]);
            if let Some(t) = (b - a).try_normalize(1e-12) {
                out.points[out.len] = (points[k], t);
                out.len += 1;
            }
        }
        out
    }

    /// The tangent at the path's point nearest `p`, if it has any.
    fn tangent_near(&self, p: Point3) -> Option<Vec3> {
        let near = |a: &&(Point3, Vec3), b: &&(Point3, Vec3)| {
            (a.0 - p)
                .norm_squared()
                .total_cmp(&(b.0 - p).norm_squared())
        };
        self.points[..self.len].iter().min_by(near).map(|e| e.1)
    }
}

impl AutonomousTask {
    /// How far the scan runs before it gives up (outcome aborted): three
    /// times the nominal section's length and 10 mm, mm.
    pub fn longest_mm(&self) -> f64 {
        3.0 * self.nominal_length_mm + 10.0
    }
}

/// Runs an autonomous scan; with the attempt, where its ball centre
/// stalled (machine coordinates) when it did
/// ([`ModeOptions::autonomous_stall_mm`]; the attempt is then `aborted`).
pub fn autonomous_scan(
    cmm: &mut dyn Machine,
    (probe, free): (HostProbe, Option<&dyn FreeSpace>),
    task: &AutonomousTask,
    opts: &ModeOptions,
) -> (Attempt, Option<Point3>) {
    let mut tr = Tracker::new(cmm, probe).avoiding(free).escaping(opts);
    let above = autonomous_start(probe, task, tr.free(), opts);
    let mut stalled = None;
    let result = reposition(cmm, &mut tr, above, task.start_normal, opts)
        .and_then(|_| touch_down(cmm, &mut tr, task, opts))
        .and_then(|_| follow(cmm, &mut tr, task, opts, &mut stalled));
    // A scan that followed a part lying off its design by more than the
    // ball's radius ends where the design has material, however it ended.
    if !matches!(result, Err(Outcome::Collision)) {
        tr.back_out_of_design(cmm);
    }
    (finish(tr, result), stalled)
}

/// Where the approach of an autonomous scan starts (ball centre, the
/// standoff outside the nominal start point).
pub fn autonomous_start(
    probe: HostProbe,
    task: &AutonomousTask,
    free: Option<&dyn FreeSpace>,
    opts: &ModeOptions,
) -> Point3 {
    let n = task.start_normal;
    let touching = task.start + n * probe.tip_radius_mm;
    touching + n * approach_standoff(free, touching, n, opts)
}

fn touch_down(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    task: &AutonomousTask,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    tr.enter_approach(cmm, Phase::Autonomous);
    // As far as a design-value scan's approach looks for its surface.
    let (from, reach) = (
        tr.ball_undeflected(),
        2.0 * (task.deflection_mm + opts.standoff_mm) + 2.0,
    );
    for _ in 0..opts.max_cycles {
        if tr.deflection() >= task.deflection_mm {
            return Ok(());
        }
        if (tr.ball_undeflected() - from).norm() > reach {
            return Err(Outcome::LostContact);
        }
        if let Some(o) = tr.step(cmm, -task.start_normal * opts.approach_speed_mm_s) {
            return Err(o);
        }
    }
    Err(Outcome::Aborted)
}

/// Gain pulling the ball back into the scanning plane, 1/s.
const PLANE_GAIN: f64 = 30.0;

fn follow(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    task: &AutonomousTask,
    opts: &ModeOptions,
    stalled: &mut Option<Point3>,
) -> Result<(), Outcome> {
    tr.enter(cmm, Phase::Autonomous);
    let (o, pn) = task.plane;
    let mut dir = task.direction;
    let start = tr.ball_undeflected();
    let mut mark = (start, 0.0);
    let (mut travelled, mut lost, mut speed) = (0.0, 0usize, 0.0f64);
    let dt = cmm.cycle_s();
    for _ in 0..opts.max_cycles {
        let d = tr.now.deflection;
        let n = d.try_normalize(1e-9).unwrap_or(task.start_normal);
        let t = pn.cross(&n).try_normalize(1e-12).unwrap_or(dir);
        dir = if t.dot(&dir) >= 0.0 { t } else { -t };
        speed = (speed + opts.tangential_accel_mm_s2 * dt).min(opts.autonomous_speed_mm_s);
        let a0 = tr.ball_undeflected();
        // The measured point held in the plane while the stylus touches
        // (on a surface inclined to the plane the ball centre stands off
        // it by the radius times the normal's lean), else the ball centre.
        let touching = d.norm() >= opts.contact_mm;
        let held = tr.measured().filter(|_| touching).map_or(a0, |m| m.point);
        let off_plane = (held - o).dot(&pn);
        let v = dir * speed
            - n * ((task.deflection_mm - d.norm()) * opts.gain_deflection)
            - pn * (off_plane * PLANE_GAIN);
        if let Some(out) = tr.step(cmm, v) {
            return Err(out);
        }
        travelled += speed * dt;
        lost = if tr.deflection() < opts.contact_mm {
            lost + 1
        } else {
            0
        };
        if lost >= opts.lost_contact_cycles {
            return Err(Outcome::LostContact);
        }
        tr.sample(task.pitch_mm);
        if finished(task, tr, (start, travelled, dir), opts) {
            return Ok(());
        }
        if travelled > task.longest_mm() {
            return Err(Outcome::Aborted);
        }
        if travelled - mark.1 >= opts.autonomous_stall_mm {
            let here = tr.ball_undeflected();
            if (here - mark.0).norm() < STALL_MOVE_SHARE * opts.autonomous_stall_mm {
                *stalled = Some(here);
                return Err(Outcome::Aborted);
            }
            mark = (here, travelled);
        }
    }
    Err(Outcome::Aborted)
}

/// Closed: back near the start after most of a loop. Open: past the end
/// point's plane (perpendicular to the end tangent), or rolled over the
/// part's end near it ([`ModeOptions::autonomous_end_reach_mm`]: the
/// measured normal within 60 degrees of the nominal path's tangent at the
/// path point nearest, [`EndPath`], after most of the section,
/// [`END_SHARE`]).
fn finished(
    task: &AutonomousTask,
    tr: &Tracker,
    (start, travelled, dir): (Point3, f64, Vec3),
    opts: &ModeOptions,
) -> bool {
    let here = tr.ball_undeflected();
    match task.end {
        None => closed_again(task, start, here, travelled),
        Some((end, tangent)) => {
            let m = tr.measured();
            let past = m.is_some_and(|m| (m.point - end).dot(&tangent) >= 0.0);
            // Round most of the section first: on a tight arc the normal
            // turns towards the end tangent well before the end.
            let reach = opts.autonomous_end_reach_mm;
            let length = task.nominal_length_mm;
            let round = travelled >= (length - reach).max(END_SHARE * length);
            let over_end = m.is_some_and(|m| {
                let along = task.end_path.tangent_near(m.point).unwrap_or(tangent);
                round && (m.point - end).norm() <= reach && m.normal.dot(&along) >= END_FACE_COS
            });
            (past && dir.dot(&tangent) > 0.0) || over_end
        }
    }
}

/// A ball that moves less than this share of
/// [`ModeOptions::autonomous_stall_mm`] while driven that far has stalled.
pub const STALL_MOVE_SHARE: f64 = 0.1;

/// The measured normal of a ball rolled over the part's end leans towards
/// the end tangent by at least this (cos 60 degrees).
const END_FACE_COS: f64 = 0.5;

/// ... once the scan has gone this share of the section's length, and
/// all of it but [`ModeOptions::autonomous_end_reach_mm`].
const END_SHARE: f64 = 0.75;

/// Whether a closed section's scan, `travelled` mm along from `start`, is
/// back at it with the ball at `here` (ball centres, mm): after half the
/// section's length, within a pitch (at least 0.2 mm) of the start within
/// the scanning plane. A start the approach left off the plane (the plane
/// hold takes the ball to it on the way) is still come back to.
fn closed_again(task: &AutonomousTask, start: Point3, here: Point3, travelled: f64) -> bool {
    let pn = task.plane.1;
    let off = here - start;
    let in_plane = off - pn * off.dot(&pn);
    travelled > 0.5 * task.nominal_length_mm && in_plane.norm() < task.pitch_mm.max(0.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed section in the plane z = 3 whose scan started 0.575 mm
    /// above the plane (the approach came down off it).
    fn task() -> AutonomousTask {
        AutonomousTask {
            start: Point3::new(5.0, 0.0, 3.0),
            start_normal: Vec3::x(),
            direction: Vec3::y(),
            plane: (Point3::new(0.0, 0.0, 3.0), Vec3::z()),
            end: None,
            end_path: EndPath::default(),
            nominal_length_mm: 31.4,
            deflection_mm: 0.3,
            pitch_mm: 0.5,
        }
    }

    #[test]
    fn a_loop_closes_on_a_start_off_the_scanning_plane() {
        let start = Point3::new(6.5, 0.0, 3.575);
        // Back over the start in the plane, after a full loop.
        assert!(closed_again(
            &task(),
            start,
            Point3::new(6.5, 0.1, 3.0),
            31.0
        ));
        // Not before half the loop, nor a pitch away within the plane.
        assert!(!closed_again(
            &task(),
            start,
            Point3::new(6.5, 0.1, 3.0),
            10.0
        ));
        assert!(!closed_again(
            &task(),
            start,
            Point3::new(6.5, 0.6, 3.0),
            31.0
        ));
    }
}
