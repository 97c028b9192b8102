//! Collision-free routes between measurements, from the design data.
//!
//! A route from where the probe is to a probing start point (ball centre)
//! that arrives along the approach direction is a list of straight legs,
//! each checked with the probe's ball, stylus and body against the nominal
//! part ([`FreeSpace`]). The candidates, tried in order, the first whose
//! every leg is clear taken:
//! 1. straight to the target, when it is within the standoff;
//! 2. straight to an entry point outside the target, then in;
//! 3. up to the clearance height, across, down to an entry point and in,
//!    for entry points farther and nearer along the approach direction
//!    (a bore or a pocket is entered inside its opening: the entry point
//!    sits over the target, not beyond the wall) and finally right above
//!    the target.
//!
//! All candidates are tried first with the full clearance margin, then with
//! the tight one (narrow openings); a route found with the tight margin
//! only is driven with a stop at each corner, so the move keeps to its
//! legs (a blended corner and the servo's lag would leave them by more
//! than that margin). When none is clear the move is refused
//! ([`Outcome::Blocked`](super::Outcome::Blocked)): the software never
//! drives the probe on a path it knows to hit the part.
use super::{FreeSpace, ModeOptions};
use crate::math::{Point3, Vec3};

mod escape;

/// Distances of the entry points from the target along the approach
/// direction, mm, farthest first (0: straight above the target).
const ENTRY_MM: [f64; 5] = [15.0, 10.0, 5.0, 2.0, 0.0];

/// Waypoints (after `here`, ending on `target`) of a clear route, or `None`
/// when no candidate is clear. `clearance_z` is the machine z of the
/// clearance height (`None`: straight moves only).
pub fn plan(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Vec<Point3>> {
    plan_route(free, (here, probe_vector), target, approach, opts).map(|r| r.waypoints)
}

/// A clear route and the margin it was found with.
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    /// The waypoints after the start, ending on the target.
    pub waypoints: Vec<Point3>,
    /// Whether its legs are clear with the tight margin only: a move
    /// along it must keep to the legs (no corner cut short, no servo
    /// overshoot past a corner), so it stops at every waypoint.
    pub tight: bool,
}

/// [`plan`] with the margin the route was found with.
pub fn plan_route(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Route> {
    let mut candidates = candidates(here, target, approach, opts);
    candidates.retain(|c| c.iter().all(|&w| mount_reachable(w - probe_vector, opts)));
    // Candidates share legs (the climb, the last leg in): each leg is
    // checked once per margin.
    let mut checked = Vec::new();
    [false, true].into_iter().find_map(|tight| {
        let c = candidates
            .iter()
            .find(|c| legs_clear(free, here, c, tight, &mut checked))?;
        Some(Route {
            waypoints: c.clone(),
            tight,
        })
    })
}

/// [`plan_route`] from where the probe came free, `here` (a point the
/// measurement decides): straight to a target within the standoff when
/// that is clear (between the touch points of a hole, a detour by the
/// grid or an entry point would take the ball towards the wall, where a
/// part set up off its design meets it); else first from the nearest
/// point of the planning grid
/// ([`ModeOptions::plan_grid_mm`]) with a first leg to it from `here`
/// (clear with the route's margin), so that the checks of the route's
/// legs are the same for every part of a batch whose probe comes free
/// within the same grid cell; else from `here` itself; else, when `here`
/// is too near the part for any route to start from it, out of the corner
/// by a short escape leg first; else back the way the probe came in (from
/// under an overhang, where no route goes straight up) to where a route
/// starts.
pub fn plan_route_from(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Option<Route> {
    if let Some(route) = straight(free, (here, probe_vector), target, opts) {
        return Some(route);
    }
    let home = grid_point(here, opts.plan_grid_mm);
    let via_home = (home != here).then(|| {
        let route = plan_route(free, (home, probe_vector), target, approach, opts)?;
        let reachable = mount_inside_soft_travel(home - probe_vector, opts);
        (reachable && free.segment_clear_with(here, home, route.tight)).then(|| Route {
            waypoints: std::iter::once(home).chain(route.waypoints).collect(),
            ..route
        })
    });
    via_home
        .flatten()
        .or_else(|| plan_route(free, (here, probe_vector), target, approach, opts))
        .or_else(|| escape::plan_route_out(free, (here, probe_vector), target, approach, opts))
        .or_else(|| escape::plan_route_back(free, (here, probe_vector), target, approach, opts))
}

/// The straight move from `here` to a `target` within the standoff and
/// the machine's travel, when it is clear (with the full margin, else the
/// tight one).
fn straight(
    free: &dyn FreeSpace,
    (here, probe_vector): (Point3, Vec3),
    target: Point3,
    opts: &ModeOptions,
) -> Option<Route> {
    let near = (here - target).norm() <= opts.standoff_mm;
    if !near || !mount_reachable(target - probe_vector, opts) {
        return None;
    }
    [false, true].into_iter().find_map(|tight| {
        free.segment_clear_with(here, target, tight).then(|| Route {
            waypoints: vec![target],
            tight,
        })
    })
}

/// The point of the grid of spacing `grid` (mm) nearest to `p`; `p` itself
/// for a grid of no positive spacing. A coordinate rounded to zero is +0
/// (the free-space answers are remembered by their inputs' bits).
pub fn grid_point(p: Point3, grid: f64) -> Point3 {
    if grid > 0.0 && grid.is_finite() {
        p.map(|x| (x / grid).round() * grid + 0.0)
    } else {
        p
    }
}

/// Whether the probe mount at `mount` (machine coordinates) lies inside
/// the machine's travel ([`ModeOptions::travel_mm`]; anywhere when it is
/// not known): a route whose waypoint the machine cannot reach is no route.
pub fn mount_reachable(mount: Point3, opts: &ModeOptions) -> bool {
    opts.travel_mm
        .is_none_or(|(lo, hi)| (0..3).all(|k| (lo[k]..=hi[k]).contains(&mount[k])))
}

/// Whether the probe mount at `mount` lies inside the travel less
/// [`ModeOptions::soft_limit_mm`] at each end, where the positioning moves
/// reach their waypoints exactly (anywhere when the travel is not known).
pub(super) fn mount_inside_soft_travel(mount: Point3, opts: &ModeOptions) -> bool {
    let m = opts.soft_limit_mm;
    opts.travel_mm
        .is_none_or(|(lo, hi)| (0..3).all(|k| mount[k] >= lo[k] + m && mount[k] <= hi[k] - m))
}

/// Whether a route comes to `target` from the clearance height straight
/// above it (the start of a feature's measuring, wherever the probe is
/// before it: every route goes over the clearance height at worst).
pub fn route_from_above(
    free: &dyn FreeSpace,
    (target, probe_vector): (Point3, Vec3),
    approach: Vec3,
    opts: &ModeOptions,
) -> bool {
    let z = opts.clearance_z_mm.unwrap_or(target.z).max(target.z);
    let above = Point3::new(target.x, target.y, z);
    plan(free, (above, probe_vector), target, approach, opts).is_some()
}

/// The candidate routes in the order they are tried.
fn candidates(
    here: Point3,
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Vec<Vec<Point3>> {
    let mut out = Vec::new();
    if (here - target).norm() <= opts.standoff_mm {
        out.push(vec![target]);
    }
    let entries = ENTRY_MM.map(|d| target + approach * d);
    out.extend(entries.iter().map(|&e| vec![e, target]));
    if let Some(z) = opts.clearance_z_mm {
        let top = z.max(here.z);
        let up = Point3::new(here.x, here.y, top);
        out.extend(entries.iter().map(|&e| {
            let over = Point3::new(e.x, e.y, top.max(e.z));
            vec![up, over, e, target]
        }));
    }
    for route in &mut out {
        route.dedup_by(|a, b| (*a - *b).norm() < 1e-9);
    }
    out
}

/// A leg (from, to, tight margin) already checked, and whether it is clear.
type Checked = ((Point3, Point3, bool), bool);

/// Whether every leg of `route` from `here` is clear, with the legs checked
/// before looked up in `checked` (and the new ones added).
fn legs_clear(
    free: &dyn FreeSpace,
    here: Point3,
    route: &[Point3],
    tight: bool,
    checked: &mut Vec<Checked>,
) -> bool {
    let mut from = here;
    route.iter().all(|&to| {
        let leg = (from, to, tight);
        from = to;
        if (leg.1 - leg.0).norm() < 1e-9 {
            return true;
        }
        if let Some(&(_, clear)) = checked.iter().find(|(l, _)| *l == leg) {
            return clear;
        }
        let clear = free.segment_clear_with(leg.0, leg.1, tight);
        checked.push((leg, clear));
        clear
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Free space outside a vertical hole of radius `r_hole` through a
    /// slab `z in [0, 10]`, for a point probe (no stylus): an independent
    /// analytic obstacle.
    struct Slab {
        r_hole: f64,
    }

    impl FreeSpace for Slab {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            (0..=200).all(|k| {
                let p = from + (to - from) * (k as f64 / 200.0);
                let inside_slab = (0.0..=10.0).contains(&p.z);
                !inside_slab || p.xy().coords.norm() < self.r_hole
            })
        }
    }

    fn opts() -> ModeOptions {
        ModeOptions {
            clearance_z_mm: Some(30.0),
            ..ModeOptions::default()
        }
    }

    #[test]
    fn enters_a_hole_inside_its_opening() {
        // Target on the hole's wall (r = 4 of a 6 mm hole), approach
        // towards the axis: the 15 mm and 10 mm entry points lie beyond
        // the far wall; the route comes down inside the hole.
        let free = Slab { r_hole: 6.0 };
        let target = Point3::new(4.0, 0.0, 5.0);
        let here = Point3::new(40.0, 0.0, 20.0);
        let route =
            plan(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts()).expect("a route");
        let entry = route[route.len() - 2];
        assert!(entry.xy().coords.norm() < 6.0, "entry {entry:?}");
        assert!(legs_clear(&free, here, &route, false, &mut Vec::new()));
        assert_eq!(route.last(), Some(&target));
    }

    #[test]
    fn refuses_a_target_inside_a_closed_cavity() {
        // A point under the slab with no hole: no route reaches it.
        let free = Slab { r_hole: 0.0 };
        let target = Point3::new(0.0, 0.0, -5.0);
        let here = Point3::new(40.0, 0.0, 20.0);
        assert_eq!(
            plan(&free, (here, Vec3::zeros()), target, -Vec3::z(), &opts()),
            None
        );
    }

    /// [`Slab`] that also refuses every segment touching the ball `r`
    /// round `blocked` (a point probe), counting the segments asked.
    struct Counting {
        slab: Slab,
        blocked: Option<(Point3, f64)>,
        asked: std::cell::Cell<usize>,
    }

    impl FreeSpace for Counting {
        fn segment_clear(&self, from: Point3, to: Point3) -> bool {
            self.asked.set(self.asked.get() + 1);
            let hits = |(c, r): (Point3, f64)| {
                let d = to - from;
                let t = ((c - from).dot(&d) / d.norm_squared().max(1e-300)).clamp(0.0, 1.0);
                (from + d * t - c).norm() < r
            };
            !self.blocked.is_some_and(hits) && self.slab.segment_clear(from, to)
        }
    }

    #[test]
    fn plans_from_the_nearest_grid_point() {
        // Two probes freed 0.2 mm apart in one grid cell: both routes go
        // by the same grid point, then the same waypoints.
        let free = Slab { r_hole: 6.0 };
        let target = Point3::new(4.0, 0.0, 5.0);
        let opts = opts();
        let plan = |here: Point3| {
            plan_route_from(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts)
                .expect("a route")
        };
        let (a, b) = (
            plan(Point3::new(40.3, 0.1, 20.2)),
            plan(Point3::new(40.1, -0.1, 19.9)),
        );
        assert_eq!(a.waypoints.first(), Some(&Point3::new(40.0, 0.0, 20.0)));
        assert_eq!(a, b);
        // The rest is the route planned from the grid point itself.
        let from_grid = plan_route(
            &free,
            (Point3::new(40.0, 0.0, 20.0), Vec3::zeros()),
            target,
            -Vec3::x(),
            &opts,
        );
        assert_eq!(
            a.waypoints.get(1..),
            from_grid.as_ref().map(|r| &r.waypoints[..])
        );
    }

    #[test]
    fn plans_from_the_probe_when_the_grid_point_is_blocked() {
        let here = Point3::new(40.3, 0.1, 20.2);
        let free = Counting {
            slab: Slab { r_hole: 6.0 },
            blocked: Some((Point3::new(40.0, 0.0, 20.0), 0.05)),
            asked: std::cell::Cell::new(0),
        };
        let target = Point3::new(4.0, 0.0, 5.0);
        let route = plan_route_from(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts())
            .expect("a route");
        let direct = plan_route(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts());
        assert_eq!(Some(route), direct);
    }

    #[test]
    fn plans_from_the_probe_without_a_grid() {
        let here = Point3::new(40.3, 0.1, 20.2);
        let free = Counting {
            slab: Slab { r_hole: 6.0 },
            blocked: None,
            asked: std::cell::Cell::new(0),
        };
        let opts = ModeOptions {
            plan_grid_mm: 0.0,
            ..opts()
        };
        let target = Point3::new(4.0, 0.0, 5.0);
        let route = plan_route_from(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts);
        let asked = free.asked.get();
        let direct = plan_route(&free, (here, Vec3::zeros()), target, -Vec3::x(), &opts);
        assert_eq!(route, direct);
        assert_eq!(free.asked.get(), 2 * asked, "planned once only");
        assert_eq!(grid_point(here, 0.0), here);
        assert_eq!(grid_point(here, 0.5), Point3::new(40.5, 0.0, 20.0));
    }

    #[test]
    fn goes_straight_when_nothing_is_in_the_way() {
        let free = Slab { r_hole: 100.0 };
        let target = Point3::new(4.0, 0.0, 5.0);
        let here = Point3::new(10.0, 0.0, 5.0);
        let route =
            plan(&free, (here, Vec3::zeros()), target, Vec3::x(), &opts()).expect("a route");
        assert_eq!(route.len(), 2, "{route:?}");
    }

    /// Between two touch points inside a hole (their starts 0.2 mm apart,
    /// 2 mm from the axis of a 3 mm hole), the move is the straight one:
    /// by the grid point (1 mm from the axis here the nearest is 2.24 mm
    /// from it) or an entry point the ball would swing towards the wall.
    #[test]
    fn goes_straight_between_near_starts_in_a_hole() {
        let free = Slab { r_hole: 3.0 };
        let here = Point3::new(2.0, 0.3, 5.3);
        let target = Point3::new(1.95, 0.5, 5.3);
        let approach = Vec3::new(-1.0, -0.25, 0.0).normalize();
        let route = plan_route_from(&free, (here, Vec3::zeros()), target, approach, &opts())
            .expect("a route");
        assert_eq!(route.waypoints, vec![target]);
        assert!(!route.tight);
    }
}
