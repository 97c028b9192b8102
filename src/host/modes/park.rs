//! The end of a program: the stylus comes free of the part and the probe
//! rises to the clearance height and stops there, as a part program ends
//! on a CMM (the next part is put on the table under a probe that stands
//! clear, and a machine is never left with its stylus pressed on a part).
use super::direct::{FreeSpace, MoveStop};
use super::motion::{free_stylus, travel};
use super::route::plan_route_from;
use super::{HostProbe, ModeOptions, Outcome, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::math::{Point3, Vec3};

/// Frees the stylus when it touches, then moves up to the clearance height
/// ([`ModeOptions::clearance_z_mm`]) when the probe is below it, and comes
/// to rest: straight up when that line is clear of the part (`free`, when
/// known), else by a clear route to the point above (out of a pocket
/// under an overhang first, say), stopping at each of its corners. With
/// no clear way up, the probe stops where it came free and the move ends
/// [`Outcome::Blocked`] (reported as `aborted`).
pub fn park(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    free: Option<&dyn FreeSpace>,
    opts: &ModeOptions,
) -> Result<(), MoveStop> {
    let mut tr = Tracker::new(cmm, probe).avoiding(free).escaping(opts);
    let away = free_stylus(cmm, &mut tr, opts).map_err(|o| MoveStop::of(&tr, o))?;
    let here = away.unwrap_or_else(|| tr.ball_undeflected());
    let mut waypoints: Vec<Point3> = away.into_iter().collect();
    let (up, legs) = match (rise(here, free, opts), free) {
        (Some(top), _) => (vec![top], Vec::new()),
        (None, Some(free)) => (Vec::new(), route_up(free, (here, probe.probe_vector), opts)),
        (None, None) => (Vec::new(), Vec::new()),
    };
    let stuck = up.is_empty() && legs.is_empty() && above(here, opts).is_some();
    waypoints.extend(up);
    if waypoints.is_empty() {
        waypoints.push(here);
    }
    tr.enter(cmm, Phase::Position);
    let speed = opts.rapid_speed_mm_s;
    travel(cmm, &mut tr, &waypoints, speed, 0.0, opts).map_err(|o| MoveStop::of(&tr, o))?;
    for w in legs {
        travel(cmm, &mut tr, &[w], speed, 0.0, opts).map_err(|o| MoveStop::of(&tr, o))?;
    }
    if stuck {
        return Err(MoveStop::of(&tr, Outcome::Blocked));
    }
    Ok(())
}

/// The legs of a clear route from `here` (ball centre, with the probe
/// vector) up to the clearance height above it, when one is needed and
/// found.
fn route_up(free: &dyn FreeSpace, (here, pv): (Point3, Vec3), opts: &ModeOptions) -> Vec<Point3> {
    (above(here, opts))
        .and_then(|top| plan_route_from(free, (here, pv), top, Vec3::z(), opts))
        .map_or(Vec::new(), |r| r.waypoints)
}

/// The point straight above `here` at the clearance height, when `here`
/// is below it and the line up is clear.
fn rise(here: Point3, free: Option<&dyn FreeSpace>, opts: &ModeOptions) -> Option<Point3> {
    above(here, opts).filter(|&top| free.is_none_or(|f| f.segment_clear(here, top)))
}

/// The point straight above `here` at the clearance height, when `here`
/// is below it.
fn above(here: Point3, opts: &ModeOptions) -> Option<Point3> {
    let z = opts.clearance_z_mm?;
    (z > here.z + opts.arrive_tol_mm).then(|| Point3::new(here.x, here.y, z))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wall at x >= 1 from z = 0 to z = 10 (free space for a point
    /// probe, sampled).
    struct Wall;

    impl FreeSpace for Wall {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            (0..=100).all(|k| {
                let p = from + (to - from) * (k as f64 / 100.0);
                !(p.x >= 1.0 && (0.0..=10.0).contains(&p.z))
            })
        }
    }

    fn opts() -> ModeOptions {
        ModeOptions {
            clearance_z_mm: Some(50.0),
            ..ModeOptions::default()
        }
    }

    #[test]
    fn the_probe_rises_to_the_clearance_height_when_the_way_up_is_clear() {
        let here = Point3::new(0.0, 0.0, 5.0);
        assert_eq!(
            rise(here, Some(&Wall), &opts()),
            Some(Point3::new(0.0, 0.0, 50.0))
        );
        assert_eq!(rise(here, None, &opts()), Some(Point3::new(0.0, 0.0, 50.0)));
    }

    #[test]
    fn the_probe_stays_where_the_way_up_is_blocked_or_it_is_high_enough() {
        let inside = Point3::new(2.0, 0.0, -5.0);
        assert_eq!(rise(inside, Some(&Wall), &opts()), None);
        assert_eq!(
            rise(Point3::new(0.0, 0.0, 60.0), Some(&Wall), &opts()),
            None
        );
        let no_height = ModeOptions::default();
        assert_eq!(rise(Point3::origin(), None, &no_height), None);
    }
}
