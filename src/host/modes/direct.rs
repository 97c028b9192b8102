//! Direct moves between measurements: straight from where the stylus comes
//! free to the next probing start point when that line is clear of the
//! part, instead of the detour over the clearance height.
use super::motion::{free_stylus, travel};
use super::{HostProbe, ModeOptions, Outcome, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::math::{Point3, Vec3};
use crate::seam::ProbePart;

/// Free space around the part, as the measuring software knows it.
pub trait FreeSpace {
    /// Whether the probe (ball and stylus) can move in a straight line
    /// with its ball centre going from `from` to `to` (machine
    /// coordinates) without touching the part.
    fn segment_clear(&self, from: Point3, to: Point3) -> bool;

    /// The same with the full clearance margin, or with the tight one
    /// (`tight`) that routes through narrow openings use.
    fn segment_clear_with(&self, from: Point3, to: Point3, tight: bool) -> bool {
        let _ = tight;
        self.segment_clear(from, to)
    }

    /// The part of the probe (other than the ball) that would strike the
    /// part with the ball centre at `ball` (machine coordinates), if any.
    fn posture(&self, ball: Point3) -> Option<ProbePart> {
        let _ = ball;
        None
    }
}

/// Fewest halvings of the standoff tried by [`approach_standoff`].
const STANDOFF_HALVINGS: usize = 4;

/// The standoff (mm) of an approach along `normal` to where the ball
/// centre just touches at `touching` (machine coordinates): the configured
/// one when the probe is clear there (with the tight margin), else the
/// largest of its halves (down to a sixteenth) that is. An approach into a
/// hole narrower than the ball plus the standoff thus starts inside the
/// hole, not in its far wall. With no free space to ask, or none clear,
/// the configured standoff (the route planning then says no).
pub fn approach_standoff(
    free: Option<&dyn FreeSpace>,
    touching: Point3,
    normal: Vec3,
    opts: &ModeOptions,
) -> f64 {
    let Some(free) = free else {
        return opts.standoff_mm;
    };
    (0..=STANDOFF_HALVINGS)
        .map(|k| opts.standoff_mm / f64::from(1u32 << k))
        .find(|&s| {
            let at = touching + normal * s;
            free.segment_clear_with(at, at, true)
        })
        .unwrap_or(opts.standoff_mm)
}

/// Moves straight to `target` (ball centre, ending at rest) when the line
/// from where the stylus is free to `target` is clear; returns whether it
/// did. When it is not, the probe is left free of the part, for the
/// measuring mode's own repositioning.
pub fn direct_move(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    target: Point3,
    free: &dyn FreeSpace,
    opts: &ModeOptions,
) -> Result<bool, Outcome> {
    let mut tr = Tracker::new(cmm, probe).escaping(opts);
    let away = free_stylus(cmm, &mut tr, opts)?;
    let from = away.unwrap_or_else(|| tr.ball_undeflected());
    let clear = free.segment_clear(from, target);
    let mut waypoints: Vec<Point3> = away.into_iter().collect();
    if clear {
        waypoints.push(target);
    }
    tr.enter(cmm, Phase::Position);
    travel(cmm, &mut tr, &waypoints, opts.rapid_speed_mm_s, 0.0, opts)?;
    Ok(clear)
}
