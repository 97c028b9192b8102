//! Routes out of a corner: the probe came to rest nearer the part than
//! the clearance margin (a scan that ran up to a wall in a concave corner
//! ends a few tenths of a millimetre from the wall and from its own
//! surface), so no route checked with a margin starts where it is.
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
    outs.filter(|&out| mount_reachable(out - probe_vector, opts))
        .filter(|&out| free.approach_clear(here, out) && free.start_clear(out))
        .find_map(|out| {
            let route = plan_route(free, (out, probe_vector), target, approach, opts)?;
            Some(Route {
                waypoints: std::iter::once(out).chain(route.waypoints).collect(),
                tight: true,
            })
        })
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
}
