//! Direct moves between measurements: straight from where the stylus comes
//! free to the next probing start point when that line is clear of the
//! part, instead of the detour over the clearance height.
use super::motion::{free_stylus, travel};
use super::route::{grid_point, mount_inside_soft_travel};
use super::{Collision, HostProbe, ModeOptions, Outcome, Tracker};
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

    /// Whether an approach may start with the ball centre at `at`
    /// (machine coordinates): the probe keeps the tight margin with some
    /// room to spare, so that the route down to it, checked with the tight
    /// margin, is not refused by the rounding of a margin met exactly.
    /// Without a finer check, the tight segment check of the point.
    fn start_clear(&self, at: Point3) -> bool {
        self.segment_clear_with(at, at, true)
    }

    /// Whether the ball centre can move straight from `from` to `to`
    /// (machine coordinates) without crossing into the part: an approach's
    /// measuring move, which ends touching, so no clearance margin; `to`
    /// must keep some distance from the part. Without a finer check, the
    /// segment check.
    fn approach_clear(&self, from: Point3, to: Point3) -> bool {
        self.segment_clear(from, to)
    }

    /// The full clearance margin segments are checked with, mm (`None`:
    /// not known, taken as ample for blended moves).
    fn margin_mm(&self) -> Option<f64> {
        None
    }

    /// The part of the probe (other than the ball) that would strike the
    /// part with the ball centre at `ball` (machine coordinates), if any.
    fn posture(&self, ball: Point3) -> Option<ProbePart> {
        let _ = ball;
        None
    }

    /// Whether the probe body keeps its margin from the part with the
    /// ball centre at `ball` (machine coordinates), whatever the shaft
    /// does. Without a finer check, when [`Self::posture`] names no body
    /// strike.
    fn body_clear(&self, ball: Point3) -> bool {
        self.posture(ball) != Some(ProbePart::Body)
    }

    /// Whether the point `p` (machine coordinates) lies inside the
    /// design's material. Without a finer check, never.
    fn in_material(&self, p: Point3) -> bool {
        let _ = p;
        false
    }

    /// The design's signed distance from `p` (machine coordinates, mm,
    /// positive outside the material) and its outward unit normal at the
    /// nearest point, machine coordinates. Without a finer check, `None`.
    fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
        let _ = p;
        None
    }

    /// Notes a positioning move's route (ball centres, machine
    /// coordinates): from `from` through `waypoints`. Without a memory of
    /// the way in, nothing.
    fn note_way(&self, from: Point3, waypoints: &[Point3]) {
        let _ = (from, waypoints);
    }

    /// The ball centres of the positioning moves noted so far, oldest
    /// first (the way the probe came in, [`Self::note_way`]).
    fn way_in(&self) -> Vec<Point3> {
        Vec::new()
    }
}

/// Fewest halvings of the standoff tried by [`approach_standoff`].
const STANDOFF_HALVINGS: usize = 4;

/// The standoff (mm) of an approach along `normal` to where the ball
/// centre just touches at `touching` (machine coordinates): the configured
/// one when the probe is clear there (with the tight margin) and the
/// approach line from there to the touch does not enter the part, else
/// the largest of its halves (down to a sixteenth) that is. An approach
/// into a hole narrower than the ball plus the standoff thus starts inside
/// the hole, not in its far wall or beyond it. In a hole too small for a
/// sixteenth, the halves go on down to [`ModeOptions::min_standoff_mm`].
/// A touch inside the design (the design's signed distance,
/// [`FreeSpace::in_material`], where the approach line's check finds no
/// standoff) takes the nearest clear standoff beyond the design's surface.
/// With no free space to ask, the configured standoff; with none clear (a
/// hole narrower than the ball and the tight margin), a sixteenth: the
/// approach then starts in the hole, where the route planning says no,
/// rather than beyond its far wall, from where the approach would drive
/// through the part.
pub fn approach_standoff(
    free: Option<&dyn FreeSpace>,
    touching: Point3,
    normal: Vec3,
    opts: &ModeOptions,
) -> f64 {
    let Some(free) = free else {
        return opts.standoff_mm;
    };
    let at = |s: f64| touching + normal * s;
    let ratio = opts.standoff_mm / opts.min_standoff_mm.max(f64::MIN_POSITIVE);
    let most = (ratio
        .log2()
        .floor()
        .clamp(0.0, MAX_STANDOFF_HALVINGS as f64)) as usize;
    let halvings = [STANDOFF_HALVINGS, most.max(STANDOFF_HALVINGS)];
    (halvings.iter())
        .find_map(|&h| clear_standoff(free, &at, opts.standoff_mm, h))
        .unwrap_or(opts.standoff_mm / f64::from(1u32 << STANDOFF_HALVINGS))
}

/// Most halvings of the standoff (a twenty-thousandth of it).
const MAX_STANDOFF_HALVINGS: usize = 14;

/// [`approach_standoff`] among `standoff` and its halves down to
/// `halvings` halvings; `None` when none is clear.
fn clear_standoff(
    free: &dyn FreeSpace,
    at: &dyn Fn(f64) -> Point3,
    standoff: f64,
    halvings: usize,
) -> Option<f64> {
    let shortest = standoff / f64::from(1u32 << halvings);
    let standoffs = (0..=halvings).map(|k| standoff / f64::from(1u32 << k));
    // The approach line is checked to a quarter of the shortest standoff
    // short of the touch (where the ball is that much clear of the part).
    let near_end = at(APPROACH_END_SHARE * shortest);
    if free.approach_clear(near_end, near_end) {
        let found = (standoffs.clone())
            .find(|&s| free.start_clear(at(s)) && free.approach_clear(at(s), near_end));
        // A touch deeper in the design than the approach's check looks
        // (the distance alone keeps it) is inside it as well.
        if found.is_some() || !free.in_material(near_end) {
            return found;
        }
    }
    // The touch lies inside the design (the true part stands out of it,
    // the ball backing off it, or a correction of the design moved it
    // there): the design says nothing of the line's
    // end, only that it must be clear down to the nearest clear standoff.
    let nearest = (standoffs.clone())
        .filter(|&s| free.start_clear(at(s)))
        .last()?;
    standoffs
        .take_while(|&s| s >= nearest)
        .find(|&s| free.segment_clear_with(at(s), at(nearest), true))
        .or(Some(nearest))
}

/// Where the check of an approach line ends, as a share of the shortest
/// standoff short of the touch.
const APPROACH_END_SHARE: f64 = 0.25;

/// Moves straight to `target` (ball centre, ending at rest) when the line
/// from where the stylus is free to `target` is clear (by way of the
/// nearest point of the planning grid, [`ModeOptions::plan_grid_mm`], as
/// routes are planned); returns whether it did. When it is not, the probe is left free of the part, for the
/// measuring mode's own repositioning.
pub fn direct_move(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    target: Point3,
    free: &dyn FreeSpace,
    opts: &ModeOptions,
) -> Result<bool, MoveStop> {
    let mut tr = Tracker::new(cmm, probe).avoiding(Some(free)).escaping(opts);
    let away = free_stylus(cmm, &mut tr, opts).map_err(|o| MoveStop::of(&tr, o))?;
    let from = away.unwrap_or_else(|| tr.ball_undeflected());
    let home = grid_point(from, opts.plan_grid_mm);
    let via_home = home != from;
    let clear = if via_home {
        mount_inside_soft_travel(home - probe.probe_vector, opts)
            && free.segment_clear(home, target)
            && free.segment_clear(from, home)
    } else {
        free.segment_clear(from, target)
    };
    let mut waypoints: Vec<Point3> = away.into_iter().collect();
    if clear {
        waypoints.extend(via_home.then_some(home));
        waypoints.push(target);
        free.note_way(from, &waypoints[usize::from(away.is_some())..]);
    }
    tr.enter(cmm, Phase::Position);
    travel(cmm, &mut tr, &waypoints, opts.rapid_speed_mm_s, 0.0, opts)
        .map_err(|o| MoveStop::of(&tr, o))?;
    Ok(clear)
}

/// How a move between measurements ended when it stopped short.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveStop {
    /// Why it stopped.
    pub outcome: Outcome,
    /// Where the probe struck the part, for a collision.
    pub collision: Option<Collision>,
}

impl MoveStop {
    /// The stop of a move driven through `tr` that ended with `outcome`
    /// (with the collision `tr` recorded, if any).
    pub(super) fn of(tr: &Tracker, outcome: Outcome) -> MoveStop {
        MoveStop {
            outcome,
            collision: tr.collision,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Free space round a tube along z (bore radius 1, outside radius 2)
    /// for a point probe: an independent analytic obstacle, sampled.
    struct Tube;

    impl FreeSpace for Tube {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            (0..=400).all(|k| {
                let p = from + (to - from) * (k as f64 / 400.0);
                let r = p.xy().coords.norm();
                !(1.0..=2.0).contains(&r)
            })
        }
    }

    #[test]
    fn an_approach_across_a_bore_starts_inside_it_not_beyond_its_far_wall() {
        let opts = ModeOptions::default();
        // Touching the bore's wall at x = -1 from inside (ball centre on
        // the wall for a point probe), approaching along -x: 5 mm out along
        // +x lies outside the tube, clear, but the line crosses its far
        // wall.
        let touching = Point3::new(-1.0, 0.0, 0.0);
        let s = approach_standoff(Some(&Tube), touching, Vec3::x(), &opts);
        let start = touching + Vec3::x() * s;
        assert!(
            Tube.segment_clear(start, touching + Vec3::x() * 1e-3),
            "{s}"
        );
        assert_eq!(s, opts.standoff_mm / 4.0);
        // A bore too narrow for a sixteenth of the standoff (radius 0.1,
        // the tube's wall to 2): the largest of the further halves that
        // starts inside the bore, not in or beyond its far wall.
        struct Narrow;
        impl FreeSpace for Narrow {
            fn segment_clear(&self, from: Point3, to: Point3) -> bool {
                (0..=400).all(|k| {
                    let p = from + (to - from) * (k as f64 / 400.0);
                    !(0.1..=2.0).contains(&p.xy().coords.norm())
                })
            }
        }
        let touching = Point3::new(-0.1, 0.0, 0.0);
        let s = approach_standoff(Some(&Narrow), touching, Vec3::x(), &opts);
        assert_eq!(s, opts.standoff_mm / 32.0);
        assert!((touching.x + s).abs() < 0.1, "{s}");
        // Outside the tube the whole standoff is clear.
        let outside = Point3::new(2.0, 0.0, 0.0);
        assert_eq!(
            approach_standoff(Some(&Tube), outside, Vec3::x(), &opts),
            opts.standoff_mm
        );
    }
}
