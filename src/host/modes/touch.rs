//! Touch-point measurement: approach along the nominal normal until the
//! deflection reaches the trigger, record, retract.
use super::approach_standoff;
use super::motion::travel;
use super::{reposition, Attempt, FreeSpace, HostProbe, ModeOptions, Outcome, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::math::{Point3, Vec3};

/// Measures one point near `nominal` (machine coordinates) with outward
/// normal `normal`. Contact is searched up to `search_mm` past the nominal.
pub fn touch_point(
    cmm: &mut dyn Machine,
    (probe, free): (HostProbe, Option<&dyn FreeSpace>),
    nominal: Point3,
    normal: Vec3,
    search_mm: f64,
    opts: &ModeOptions,
) -> Attempt {
    let mut tr = Tracker::new(cmm, probe).avoiding(free).escaping(opts);
    let start = touch_start(probe, nominal, normal, free, opts);
    let standoff = (start - nominal).norm() - probe.tip_radius_mm;
    let outcome = reposition(cmm, &mut tr, start, normal, opts)
        .and_then(|_| approach(cmm, &mut tr, (start, normal), standoff + search_mm, opts))
        .and_then(|_| {
            tr.points.extend(tr.measured());
            tr.retract_from_surface(cmm);
            travel(cmm, &mut tr, &[start], opts.rapid_speed_mm_s, 0.0, opts)
        });
    finish(tr, outcome)
}

/// Where the approach of a touch point at `nominal` starts (ball centre,
/// the standoff outside the nominal surface; a shorter one where `free`
/// says the probe would not fit, [`approach_standoff`]).
pub fn touch_start(
    probe: HostProbe,
    nominal: Point3,
    normal: Vec3,
    free: Option<&dyn FreeSpace>,
    opts: &ModeOptions,
) -> Point3 {
    let touching = nominal + normal * probe.tip_radius_mm;
    touching + normal * approach_standoff(free, touching, normal, opts)
}

/// Gain of the touch approach's hold on its line, 1/s: that of the last
/// millimetre of a positioning move (below the critical gain of the
/// servo's 5 ms lag).
pub(super) const LINE_GAIN: f64 = 50.0;

/// Where the approach's line starts: `start` when the ball stands on the
/// line through it along `normal` (within the servo's lag of it), else
/// where the ball stands (a start moved for want of room).
pub(super) fn line_start(tr: &Tracker, start: Point3, normal: Vec3) -> Point3 {
    let off = tr.ball_undeflected() - start;
    if (off - normal * off.dot(&normal)).norm() <= LINE_REACH_MM {
        start
    } else {
        tr.ball_undeflected()
    }
}

/// How far beside the line of a touch approach the ball may stand at its
/// start for the approach to take it to the line, mm.
const LINE_REACH_MM: f64 = 0.5;

/// Moves along `-normal` from `start` until the deflection reaches the
/// trigger.
fn approach(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    (start, normal): (Point3, Vec3),
    reach: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    tr.enter(cmm, Phase::Touch);
    let from = line_start(tr, start, normal);
    let v = -normal * opts.approach_speed_mm_s;
    for _ in 0..opts.max_cycles {
        if tr.deflection() >= opts.trigger_mm {
            return Ok(());
        }
        let off = tr.ball_undeflected() - from;
        if off.norm() > reach {
            return Err(Outcome::LostContact);
        }
        // Held on the line of the approach: what the move before left of
        // the servo's following error sideways is taken out.
        let sideways = off - normal * off.dot(&normal);
        if let Some(o) = tr.step(cmm, v - sideways * LINE_GAIN) {
            return Err(o);
        }
    }
    Err(Outcome::Aborted)
}

pub(super) fn finish(tr: Tracker, result: Result<(), Outcome>) -> Attempt {
    Attempt {
        outcome: result.err().unwrap_or(super::Outcome::Completed),
        machine_time_s: tr.elapsed(),
        collision: tr.collision,
        points: tr.points,
        max_trajectory_error_mm: 0.0,
    }
}
