//! A ball that grazes the part on a move between measurements has struck
//! it: a controller's unexpected-contact check stops at a few micrometres
//! of deflection, not at the scanning contact threshold. The block with a
//! pocket on the ideal simulated machine: a positioning move inside the
//! pocket, all but parallel to its wall (x = 25, material at x < 25; the
//! move closes in on it by 0.3 mm over 20 mm, so the servo's overshoot at
//! its end carries the ball towards it by a fraction of a micrometre),
//! ends with the ball centre nearer the wall than the ball's 1.5 mm
//! radius by `graze` (mm).
mod common;

use cmm::host::modes::{move_to, HostProbe, ModeOptions, Tracker};
use cmm::host::observe::Unobserved;
use cmm::math::{Point3, Vec3};
use cmm::seam::ProbePart;
use cmm::world::as_machined::AsMachined;
use common::*;

/// The move's result and the collision the tracker recorded, if any.
fn graze(graze: f64) -> (bool, Option<ProbePart>) {
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let start = Point3::new(26.8, 40.0, 40.0);
    let mut sim = pocket_machine((&wp, &am), (pv, 1.5, 0.75), start);
    let opts = ModeOptions::default();
    let probe = HostProbe::nominal(pv, 1.5);
    let end = POCKET_POSE.to_machine(Point3::new(25.0 + 1.5 - graze, 60.0, 40.0));
    let mut m = Unobserved(&mut sim);
    let mut tr = Tracker::new(&m, probe);
    let moved = move_to(&mut m, &mut tr, end, 50.0, &opts);
    (moved.is_ok(), tr.collision.map(|c| c.probe_part))
}

/// Pressed 5 um into the wall at the end of the move (a quarter of the
/// 0.02 mm a scan counts as contact): a collision of the ball. Stopping
/// 5 um short of the wall: none.
#[test]
fn a_graze_of_a_few_micrometres_is_a_collision() {
    assert_eq!(graze(0.005), (false, Some(ProbePart::Ball)));
    assert_eq!(graze(-0.005), (true, None));
}

/// A ball driven into the pocket's wall at 200 mm/s, the machine braking
/// at its own acceleration limit once it reports the probe over its
/// range: the machine runs on by millimetres (200^2 / (2 x 2000) = 10 mm
/// at the default axes' limit), the stylus held at its stop on its crash
/// protection, so the sensor never reads more than the probe's 1 mm range
/// (it read the machine's whole run-on before).
#[test]
fn a_crash_reads_no_more_than_the_stylus_range() {
    use cmm::seam::{Cmm, MachineStatus};
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let mut sim = pocket_machine((&wp, &am), (pv, 1.5, 0.75), Point3::new(30.0, 50.0, 40.0));
    let (mut widest, mut over, mut run_on) = (0.0_f64, false, 0.0_f64);
    let mut command = Vec3::new(-200.0, 0.0, 0.0);
    for _ in 0..400 {
        let r = sim.step(command);
        widest = widest.max(r.deflection.norm());
        if matches!(r.status, MachineStatus::ProbeOverrange { .. }) {
            over = true;
            command = Vec3::zeros();
        }
        let ball_x = POCKET_POSE.to_part(r.scales + pv).x;
        run_on = run_on.max(26.5 - ball_x);
    }
    assert!(over, "never over range");
    assert!(run_on > 5.0, "ran on {run_on} mm");
    assert!(widest <= 1.0 + 1e-9, "read {widest} mm");
}
