//! After the probe strikes the part the software backs it out the way it
//! came and stops it in free air, so the moves that follow start clear of
//! the part: checked on a block with a pocket (trimmed planes) against its
//! analytic geometry, for the stylus shaft striking the pocket's rim and
//! for the ball running into the top face during a positioning move.
mod common;

use cmm::host::modes::{move_to, HostProbe, ModeOptions, Outcome, Tracker};
use cmm::host::observe::Unobserved;
use cmm::math::{Point3, Vec3};
use cmm::program::Pose;
use cmm::seam::{Cmm, MachineStatus, ProbePart};
use cmm::workpiece::Workpiece;
use cmm::world::as_machined::AsMachined;
use cmm::world::cmm::SimulatedCmm;
use common::*;

const POSE: Pose = POCKET_POSE;

/// Ball radius, shaft radius (a 3 mm ball on a 2 mm shaft).
const R: f64 = 1.5;
const RS: f64 = 1.0;

/// An ideal machine with the probe `pv` (mount to ball) and the ball
/// centre at `ball` (part frame).
fn machine<'a>(wp: &'a Workpiece, am: &'a AsMachined, pv: Vec3, ball: Point3) -> SimulatedCmm<'a> {
    pocket_machine((wp, am), (pv, R, RS), ball)
}

/// Ball centre (part frame) of `sim`'s scales.
fn ball(sim: &SimulatedCmm<'_>, pv: Vec3) -> Point3 {
    POSE.to_part(sim.readings().scales + pv)
}

/// Whether the machine is at rest with every probe part clear of the part
/// over the next cycle at rest (no collision, no deflection).
fn at_rest_and_clear(sim: &mut SimulatedCmm<'_>) -> bool {
    let before = sim.readings().scales;
    let r = sim.step(Vec3::zeros());
    let still = (r.scales - before).norm() < 1e-3;
    still && r.status == MachineStatus::Ok && r.deflection.norm() == 0.0
}

/// A stylus leaning 45 degrees over the pocket's rim, the ball deep in the
/// pocket, sent down 20 mm at 10 mm/s: the shaft strikes the rim edge
/// (x = 25, z = 50) once the ball is 15 mm from the wall; the software
/// then backs it up and stops it with the stylus axis clear of the edge
/// by the shaft radius plus the escape's clearance, and a move away
/// afterwards runs without a collision.
#[test]
fn the_shaft_is_backed_out_of_the_pockets_rim() {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let pv = Vec3::new(50.0 * s, 0.0, -50.0 * s);
    let start = Point3::new(40.0, 50.0, 40.0);
    let mut sim = machine(&wp, &am, pv, start);
    let opts = ModeOptions {
        approach_speed_mm_s: 10.0,
        rapid_speed_mm_s: 10.0,
        ..ModeOptions::default()
    };
    let probe = HostProbe::nominal(pv, R);
    // The stylus axis's distance from the rim edge (25, y, 50), less the
    // shaft radius.
    let clearance = |b: Point3| ((25.0 - b.x) + (50.0 - b.z)).abs() * s - RS;
    let down = POSE.to_machine(start + Vec3::new(0.0, 0.0, -20.0));
    let outcome = {
        let mut m = Unobserved(&mut sim);
        let mut tr = Tracker::new(&m, probe).escaping(&opts);
        let o = move_to(&mut m, &mut tr, down, 10.0, &opts);
        let c = tr.collision.expect("a collision is recorded");
        assert_eq!(c.probe_part, ProbePart::Shaft);
        o
    };
    assert_eq!(outcome, Err(Outcome::Collision));
    let b = ball(&sim, pv);
    let clear = opts.escape.clear_mm;
    assert!(
        clearance(b) > 0.5 * clear && clearance(b) < clear + 1.0,
        "stylus {} mm clear of the rim at {b}",
        clearance(b)
    );
    assert!(b.z > 40.0 - 20.0, "backed up, not on down: {b}");
    assert!(at_rest_and_clear(&mut sim), "at rest and clear at {b}");
    let mut m = Unobserved(&mut sim);
    let mut tr = Tracker::new(&m, probe).escaping(&opts);
    let up = POSE.to_machine(start + Vec3::new(0.0, 0.0, 10.0));
    assert_eq!(move_to(&mut m, &mut tr, up, 10.0, &opts), Ok(()));
    assert!(tr.collision.is_none());
}

/// A vertical stylus sent 10 mm down onto the top face (z = 50) from 3 mm
/// above it at 100 mm/s: the ball strikes the face during the positioning
/// move; the software backs it up until the stylus is free plus the
/// escape's clearance, and stops it above the face.
#[test]
fn the_ball_is_backed_off_the_face_it_ran_into() {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let start = Point3::new(10.0, 50.0, 50.0 + R + 3.0);
    let mut sim = machine(&wp, &am, pv, start);
    let opts = ModeOptions::default();
    let probe = HostProbe::nominal(pv, R);
    let down = POSE.to_machine(start + Vec3::new(0.0, 0.0, -10.0));
    {
        let mut m = Unobserved(&mut sim);
        let mut tr = Tracker::new(&m, probe).escaping(&opts);
        let o = move_to(&mut m, &mut tr, down, 100.0, &opts);
        assert_eq!(o, Err(Outcome::Collision));
        let c = tr.collision.expect("a collision is recorded");
        assert_eq!(c.probe_part, ProbePart::Ball);
    }
    let b = ball(&sim, pv);
    let gap = b.z - R - 50.0;
    let clear = opts.escape.clear_mm;
    assert!(
        gap > 0.5 * clear && gap < clear + 1.0,
        "ball {gap} mm above the face at {b}"
    );
    assert!(at_rest_and_clear(&mut sim), "at rest and clear at {b}");
}

/// The ball runs into a wall of a pocket 4 mm wide, so backing out of it
/// takes the ball to the pocket's far wall (1 mm away, before it is the
/// escape's clear distance out): the escape stops there, at rest beside
/// that wall, instead of driving the probe on through the block.
#[test]
fn backing_out_of_a_narrow_pocket_stops_at_its_far_wall() {
    let wp = block_with_pocket(48.0, 52.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let start = Point3::new(50.0, 50.0, 40.0);
    let mut sim = machine(&wp, &am, pv, start);
    let opts = ModeOptions::default();
    let probe = HostProbe::nominal(pv, R);
    let across = POSE.to_machine(start + Vec3::new(10.0, 0.0, 0.0));
    {
        let mut m = Unobserved(&mut sim);
        let mut tr = Tracker::new(&m, probe).escaping(&opts);
        let o = move_to(&mut m, &mut tr, across, 100.0, &opts);
        assert_eq!(o, Err(Outcome::Collision));
    }
    let b = ball(&sim, pv);
    assert!(b.x > 48.0 + R - 0.5 && b.x < 52.0 - R, "ball at {b}");
}
