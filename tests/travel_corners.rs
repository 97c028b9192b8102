//! A blended positioning move follows the route the clearance checks
//! passed: through a right-angle corner at rapid speed the ball cuts the
//! corner by at most the blend the route planner allows for and then runs
//! on the next leg's line, instead of swinging wide of the corner and back
//! across the leg (which drove a 5 mm ball into a boss beside a flange's
//! face). Measured on the ideal simulated machine, every cycle, against
//! the polyline of the route itself.
mod common;

use cmm::host::modes::{move_through, HostProbe, ModeOptions, Tracker};
use cmm::host::observe::{Observe, Unobserved};
use cmm::math::{Point3, Vec3};
use cmm::seam::{Cmm, HeadCommandError, Readings};
use cmm::world::as_machined::AsMachined;
use cmm::world::cmm::SimulatedCmm;
use common::*;

/// A machine that keeps the ball centre (part frame) of every cycle.
struct Recorder<'a, 'b> {
    sim: &'a mut SimulatedCmm<'b>,
    pv: Vec3,
    path: Vec<Point3>,
}

impl Observe for Recorder<'_, '_> {}

impl Cmm for Recorder<'_, '_> {
    fn cycle_s(&self) -> f64 {
        self.sim.cycle_s()
    }

    fn readings(&self) -> Readings {
        self.sim.readings()
    }

    fn step(&mut self, velocity: Vec3) -> Readings {
        let r = self.sim.step(velocity);
        self.path.push(POCKET_POSE.to_part(r.scales + self.pv));
        r
    }

    fn head_axes(&self) -> usize {
        self.sim.head_axes()
    }

    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        self.sim.index_head(angles_rad)
    }
}

/// Distance from `p` to the segment `a..b`, mm.
fn to_segment(p: Point3, a: Point3, b: Point3) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (a + d * t)).norm()
}

/// The ball centres of a move from `start` through `route` (part frame)
/// at the default positioning speed and acceleration, far above the
/// block.
fn travelled(start: Point3, route: &[Point3]) -> Vec<Point3> {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let mut sim = pocket_machine((&wp, &am), (pv, 1.5, 1.0), start);
    let opts = ModeOptions::default();
    let probe = HostProbe::nominal(pv, 1.5);
    let machine: Vec<Point3> = route.iter().map(|&w| POCKET_POSE.to_machine(w)).collect();
    let mut rec = Recorder {
        sim: &mut sim,
        pv,
        path: Vec::new(),
    };
    {
        let m = Unobserved(&mut rec);
        let mut m = m;
        let mut tr = Tracker::new(&m, probe);
        let speed = opts.rapid_speed_mm_s;
        assert_eq!(
            move_through(&mut m, &mut tr, &machine, speed, &opts),
            Ok(())
        );
    }
    rec.path
}

/// Off the route by at most the corner blend (1 mm) and the servo's
/// lag at a corner, within the 2 mm of room the route planner keeps for a
/// blended route, mm.
const ROUTE_BAND_MM: f64 = 1.5;

/// Out 60 mm along x, a right angle, 40 mm along y: every ball centre
/// lies within [`ROUTE_BAND_MM`] of the route, and once 5 mm past the corner within 0.1 mm of the second
/// leg's line. The move ends on the last waypoint.
#[test]
fn a_right_angle_at_rapid_speed_stays_on_the_route() {
    let start = Point3::new(10.0, 20.0, 110.0);
    let corner = Point3::new(70.0, 20.0, 110.0);
    let end = Point3::new(70.0, 60.0, 110.0);
    let path = travelled(start, &[corner, end]);
    let off = |p: Point3| to_segment(p, start, corner).min(to_segment(p, corner, end));
    let worst = path.iter().map(|&p| off(p)).fold(0.0, f64::max);
    assert!(worst < ROUTE_BAND_MM, "{worst} mm off the route");
    let after = (path.iter())
        .filter(|p| p.y > corner.y + 5.0)
        .map(|p| (p.x - end.x).abs())
        .fold(0.0, f64::max);
    assert!(after < 0.1, "{after} mm off the second leg");
    let last = path.last().copied().unwrap_or(start);
    assert!((last - end).norm() < 0.01, "ends at {last}");
}

/// A route that turns back on itself at 135 degrees and then drops: the
/// same band holds at every corner.
#[test]
fn sharp_turns_and_a_drop_stay_on_the_route() {
    let start = Point3::new(0.0, 0.0, 120.0);
    let route = [
        Point3::new(80.0, 10.0, 120.0),
        Point3::new(40.0, 50.0, 120.0),
        Point3::new(40.0, 50.0, 90.0),
    ];
    let path = travelled(start, &route);
    let legs = [start, route[0], route[1], route[2]];
    let off = |p: Point3| {
        (legs.windows(2))
            .map(|w| to_segment(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let worst = path.iter().map(|&p| off(p)).fold(0.0, f64::max);
    assert!(worst < ROUTE_BAND_MM, "{worst} mm off the route");
}
