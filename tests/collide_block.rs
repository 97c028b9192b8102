//! The simulated machine's collision check of the stylus shaft and the
//! probe body on a block with a pocket made of trimmed planes, against the
//! analytic geometry: the shaft striking the pocket's rim, the body landing
//! on the top face round a deep pocket (at the expected cycle and place),
//! and a shaft parallel to a wall 0.5 mm away while the ball scans along
//! it (no collision, and no exact check every cycle); a short stylus
//! whose wide body stands a few millimetres above the top face (no exact
//! check of the body every cycle).
mod common;

use cmm::math::{Point3, Vec3};
use cmm::program::Pose;
use cmm::seam::{Cmm, MachineStatus, ProbePart, Readings};
use cmm::workpiece::Workpiece;
use cmm::world::as_machined::AsMachined;
use cmm::world::cmm::SimulatedCmm;
use cmm::world::contact::CollisionOptions;
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

/// The collision of `readings`, if any.
fn collision(readings: &Readings) -> Option<(ProbePart, Point3, f64)> {
    match readings.status {
        MachineStatus::Collision {
            probe_part,
            at,
            speed_mm_s,
        } => Some((probe_part, at, speed_mm_s)),
        _ => None,
    }
}

/// Steps `sim` at `v` until the first collision; checks `gap` (the
/// analytic clearance of the colliding part for the machine position,
/// negative inside the material) against it at every cycle: no collision
/// while the part is not in by the penetration tolerance, a collision the
/// first cycle it is. Returns the collision and the readings.
fn drive_to_collision(
    sim: &mut SimulatedCmm<'_>,
    v: Vec3,
    gap: impl Fn(Point3) -> f64,
    cycles: usize,
) -> ((ProbePart, Point3, f64), Readings) {
    let pen = CollisionOptions::default().penetration_mm;
    for _ in 0..cycles {
        let readings = sim.step(v);
        let g = gap(readings.scales);
        match collision(&readings) {
            None => {
                assert_eq!(readings.status, MachineStatus::Ok);
                assert!(g > -pen - 1e-6, "no collision at clearance {g}");
            }
            Some(c) => {
                assert!(g < -pen + 1e-6, "collision at clearance {g}: {c:?}");
                return (c, readings);
            }
        }
    }
    panic!("no collision in {cycles} cycles");
}

/// A stylus leaning 45 degrees over the pocket's rim, the ball deep in the
/// pocket, lowered at 10 mm/s: the shaft strikes the rim edge (x = 25,
/// z = 50) when the stylus axis comes within the shaft radius of it, the
/// ball still 15 mm from the wall and 5 mm above the floor.
#[test]
fn the_shaft_strikes_the_pockets_rim() {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let pv = Vec3::new(50.0 * s, 0.0, -50.0 * s);
    let mut sim = machine(&wp, &am, pv, Point3::new(40.0, 50.0, 40.0));
    // The stylus axis through the ball along (-1, 0, 1)/sqrt 2; its
    // distance from the edge (25, y, 50) is measured in the xz-plane.
    let clearance = |scales: Point3| {
        let ball = POSE.to_part(scales + pv);
        ((25.0 - ball.x) + (50.0 - ball.z)).abs() * s - RS
    };
    let v = Vec3::new(0.0, 0.0, -10.0);
    let ((part, at, speed), readings) = drive_to_collision(&mut sim, v, clearance, 2000);
    assert_eq!(part, ProbePart::Shaft);
    let rim = POSE.to_machine(Point3::new(25.0, 50.0, 50.0));
    assert!((at - rim).norm() < 0.1, "{at} vs {rim}");
    assert!(speed > 9.0 && speed < 10.5, "{speed}");
    assert_eq!(readings.deflection.norm(), 0.0);
    // Still in contact: still a collision.
    for _ in 0..5 {
        let readings = sim.step(v);
        let (part, _, _) = collision(&readings).expect("still colliding");
        assert_eq!(part, ProbePart::Shaft);
    }
}

/// A vertical stylus 40 mm long lowered into a 20 mm square pocket 45 mm
/// deep: the body (25 mm across) lands on the top face round the pocket
/// when the mount reaches the top face, the ball 5 mm above the floor.
#[test]
fn the_body_lands_on_the_top_face_round_a_deep_pocket() {
    let wp = block_with_pocket(40.0, 60.0, 5.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -40.0);
    let mut sim = machine(&wp, &am, pv, Point3::new(50.0, 50.0, 20.0));
    // The mount is where the scales are: its height above the top face.
    let clearance = |scales: Point3| POSE.to_part(scales).z - 50.0;
    let v = Vec3::new(0.0, 0.0, -10.0);
    let ((part, at, speed), readings) = drive_to_collision(&mut sim, v, clearance, 3000);
    assert_eq!(part, ProbePart::Body);
    let at = POSE.to_part(at);
    let axis = POSE.to_part(readings.scales);
    assert!((at.z - 50.0).abs() < 1e-6, "{at}");
    let off = ((at.x - axis.x).powi(2) + (at.y - axis.y).powi(2)).sqrt();
    assert!(off <= 12.5 + 1e-6, "{at}: {off} from the axis");
    let outside = (at.x - 50.0).abs().max((at.y - 50.0).abs());
    assert!(outside >= 10.0 - 1e-6, "{at} over the pocket");
    assert!(speed > 9.0 && speed < 10.5, "{speed}");
    assert_eq!(readings.deflection.norm(), 0.0);
}

/// The ball pressed 0.3 mm into the pocket's wall x = 25 and scanning
/// along it at 10 mm/s for 30 mm: the shaft runs parallel to the wall
/// 0.5 mm from it (and from the rim): no collision, and an exact check
/// only every so many cycles.
#[test]
fn a_shaft_parallel_to_a_wall_does_not_collide() {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let mut sim = machine(&wp, &am, pv, Point3::new(25.0 + R + 0.05, 30.0, 40.0));
    let mut pressed = false;
    for _ in 0..2000 {
        let readings = sim.step(Vec3::new(-1.0, 0.0, 0.0));
        assert_eq!(readings.status, MachineStatus::Ok);
        if readings.deflection.norm() >= 0.3 {
            pressed = true;
            break;
        }
    }
    assert!(pressed);
    let before = sim.collision_checks();
    let cycles = 3000;
    let mut touching = 0;
    for _ in 0..cycles {
        let readings = sim.step(Vec3::new(0.0, 10.0, 0.0));
        assert_eq!(readings.status, MachineStatus::Ok, "{readings:?}");
        let d = readings.deflection.norm();
        if d > 0.29 && d < 0.4 {
            touching += 1;
        }
    }
    assert!(touching > cycles * 9 / 10, "{touching}");
    let checks = sim.collision_checks() - before;
    eprintln!("{checks} exact checks in {cycles} cycles");
    assert!(checks < cycles as u64 / 10, "{checks} exact checks");
}

/// A 10 mm stylus whose ball travels 2 mm above the top face: the body
/// (12.5 mm in radius) stands 12 mm above the face, nearer than its own
/// radius. Its flat bottom keeps 12 mm from the part: the exact checks
/// stay rare (a bound taking the body's end for a hemisphere reaching
/// 12.5 mm below its bottom would be negative every cycle and check it
/// exactly every cycle).
#[test]
fn a_short_stylus_body_above_the_part_is_checked_rarely() {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -10.0);
    let mut sim = machine(&wp, &am, pv, Point3::new(10.0, 10.0, 52.0));
    let cycles = 3000;
    let before = sim.collision_checks();
    for _ in 0..cycles {
        let readings = sim.step(Vec3::new(10.0, 0.0, 0.0));
        assert_eq!(readings.status, MachineStatus::Ok, "{readings:?}");
        assert_eq!(readings.deflection.norm(), 0.0);
    }
    let checks = sim.collision_checks() - before;
    assert!(checks < cycles as u64 / 10, "{checks} exact checks");
}
