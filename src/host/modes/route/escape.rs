//! Routes out of a corner: the probe came to rest nearer the part than
//! the clearance margin (a scan that ran up to a wall in a concave corner
//! ends a few tenths of a millimetre from the wall and from its own
//! surface), so no route checked with a margin starts where it is; or
//! it came to rest in free air within a ball radius of the design's
//! surface (a scan stopped over a gouge in the true part), and leaves
//! along the design's normal.
use super::{mount_reachable, plan_route, Route};
use crate::host::modes::{FreeSpace, ModeOptions};
use crate::math::{Point3, Vec3};

/// How far an escape leg moves the ball, mm, shortest first.
const ESCAPE_MM: [f64; 3] = [1.0, 3.0, 6.0];

/// A route from `here` through one short escape leg: the ball moves
/// straight to a point an approach could start from (the leg checked as an
/// approach's measuring move is, so the ball crosses nothing; the point
/// keeps the tight margin), then on by a planned route. The escape
/// directions are the 26 of the axes, their face and space diagonals,
/// those up the stylus first, so a ball in a corner between a wall and a
/// floor leaves it away from both. The route counts as tight: a move along
/// it stops at each waypoint.
pub(super) fn plan_route_out(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Route> {
    let up = (-probe_vector).try_normalize(1e-9).unwrap_or_else(Vec3::z);
    let dirs = escape_directions(up);
    let outs = ESCAPE_MM
        .iter()
        .flat_map(|&d| dirs.iter().map(move |&u| here + u * d));
    let found = outs
        .filter(|&out| mount_reachable(out - probe_vector, opts))
        .filter(|&out| free.approach_clear(here, out) && free.start_clear(out))
        .find_map(|out| route_via(free, (out, probe_vector), target, approach, opts));
    found.or_else(|| {
        let (s, n) = free.design_foot(here).filter(|&(s, _)| s > 0.0)?;
        ESCAPE_MM
            .iter()
            .map(|&d| here + n * d)
            .filter(|&out| mount_reachable(out - probe_vector, opts))
            .filter(|&out| leaves_design(free, (here, s), out) && free.start_clear(out))
            .find_map(|out| route_via(free, (out, probe_vector), target, approach, opts))
    })
}

/// The route from `here` to `out` and on by a planned route, tight.
fn route_via(
    free: &dyn FreeSpace,
    (out, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Route> {
    let route = plan_route(free, (out, probe_vector), target, approach, opts)?;
    Some(Route {
        waypoints: std::iter::once(out).chain(route.waypoints).collect(),
        tight: true,
    })
}

/// A route back the way the probe came in ([`FreeSpace::way_in`], newest
/// first) to the first of its points from which a planned route starts:
/// the first leg checked as an approach (the probe came to rest near the
/// part), the others with the tight margin (a leg between the end of one
/// positioning move and the start of the next was a measuring move, not
/// a checked leg). The route counts as tight.
pub(super) fn plan_route_back(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Route> {
    let mut back = Vec::new();
    let mut at = here;
    for w in free.way_in().into_iter().rev() {
        let clear = if back.is_empty() {
            free.approach_clear(at, w) && free.start_clear(w)
        } else {
            free.segment_clear_with(at, w, true)
        };
        if !clear || !mount_reachable(w - probe_vector, opts) {
            return None;
        }
        back.push(w);
        at = w;
        if let Some(route) = plan_route(free, (w, probe_vector), target, approach, opts) {
            back.extend(route.waypoints);
            return Some(Route {
                waypoints: back,
                tight: true,
            });
        }
    }
    None
}

/// Steps (mm) at which a leg leaving the design is sampled.
const LEAVE_STEP_MM: f64 = 0.1;

/// Whether the ball centre, at the design's signed distance `s` (mm) at
/// `here`, leaves the design on the straight leg to `out`: the distance
/// grows at every step until the ball is clear as an approach's start is,
/// and from there the leg is clear as an approach is. A ball that stopped
/// in free air nearer the design than its radius (where the true part
/// lies deeper) backs off the way nothing of the design stands.
fn leaves_design(free: &dyn FreeSpace, (here, s): (Point3, f64), out: Point3) -> bool {
    let (len, dir) = ((out - here).norm(), (out - here).normalize());
    let mut last = s;
    let steps = (len / LEAVE_STEP_MM).ceil().min(1e4) as usize;
    for k in 1..=steps {
        let p = here + dir * (k as f64 * LEAVE_STEP_MM).min(len);
        if free.approach_clear(p, p) {
            return free.approach_clear(p, out);
        }
        match free.design_foot(p) {
            Some((d, _)) if d > last => last = d,
            _ => return false,
        }
    }
    false
}

/// The unit directions of the 26 neighbours of a cube's centre, ordered by
/// how far they lead up `up` (most first; ties in a fixed order).
fn escape_directions(up: Vec3) -> Vec<Vec3> {
    const STEPS: [f64; 3] = [-1.0, 0.0, 1.0];
    let mut dirs: Vec<Vec3> = (0..27)
        .map(|i| Vec3::new(STEPS[i / 9], STEPS[i / 3 % 3], STEPS[i % 3]))
        .filter_map(|d| d.try_normalize(1e-9))
        .collect();
    dirs.sort_by(|a, b| b.dot(&up).total_cmp(&a.dot(&up)));
    dirs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_escape_directions_are_the_26_neighbours_up_first() {
        let dirs = escape_directions(Vec3::z());
        assert_eq!(dirs.len(), 26);
        assert_eq!(dirs[0], Vec3::z());
        assert!(dirs.windows(2).all(|w| w[0].z >= w[1].z));
        assert_eq!(dirs[25], -Vec3::z());
    }

    /// The material below z = 0 (a floor) for a ball of radius 1, the
    /// clearance margins of [`FreeSpace`]'s answers analytic: a segment
    /// keeps 2 mm, a start 1.2 mm, an approach half the radius.
    struct Floor;

    impl Floor {
        fn lowest(from: Point3, to: Point3) -> f64 {
            from.z.min(to.z)
        }
    }

    impl FreeSpace for Floor {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            Floor::lowest(from, to) >= 2.0
        }
        fn start_clear(&self, at: Point3) -> bool {
            at.z >= 1.2
        }
        fn approach_clear(&self, from: Point3, to: Point3) -> bool {
            Floor::lowest(from, to) >= 0.5
        }
        fn design_foot(&self, p: Point3) -> Option<(f64, Vec3)> {
            Some((p.z, Vec3::z()))
        }
    }

    /// A ball that stopped in free air 0.44 mm over the design's floor
    /// (its radius 1: a gouge in the true part let it sink) leaves
    /// straight up the floor's normal, and then goes on to its target.
    #[test]
    fn a_ball_sunk_into_the_design_leaves_along_its_normal() {
        let opts = ModeOptions {
            clearance_z_mm: Some(30.0),
            ..ModeOptions::default()
        };
        let here = Point3::new(0.0, 0.0, 0.44);
        let probe_vector = Vec3::new(0.0, 0.0, -50.0);
        let target = Point3::new(20.0, 0.0, 6.0);
        let route = plan_route_out(&Floor, (here, probe_vector), target, Vec3::z(), &opts)
            .expect("a route out");
        let first = route.waypoints[0];
        assert!((first - here).xy().norm() < 1e-12, "{first:?}");
        assert!(first.z >= 1.2, "{first:?}");
        assert_eq!(route.waypoints.last(), Some(&target));
        // A ball whose centre is below the design's surface has nothing
        // to say it is in free air: no route.
        let under = Point3::new(0.0, 0.0, -0.1);
        assert!(plan_route_out(&Floor, (under, probe_vector), target, Vec3::z(), &opts).is_none());
    }
}
