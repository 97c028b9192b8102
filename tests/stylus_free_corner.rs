//! Backing a stylus off a concave corner: the world deflects the stylus
//! along the normal of the nearer face only, so a ball pressed into a
//! pocket's wall and floor reads the wall first. Backed off along that
//! reading alone, the ball leaves the wall and then slides along the
//! floor, pressed on it, towards the far wall (a probe once dragged 36 mm
//! across a slot floor into its far wall this way). The stylus comes free
//! off both faces, near the corner, and backs off between them.
mod common;

use cmm::host::modes::{recover, HostProbe, ModeOptions, Tracker};
use cmm::host::observe::Unobserved;
use cmm::math::{Point3, Vec3};
use cmm::seam::Cmm;
use cmm::world::as_machined::AsMachined;
use common::*;

#[test]
fn a_ball_pressed_into_a_corner_comes_free_off_both_faces() {
    // The pocket's wall x = 25 and floor z = 30; a 1.5 mm ball pressed
    // 0.5 mm into the wall and 0.3 mm into the floor (part frame).
    let wp = block_with_pocket(25.0, 75.0, 30.0);
    let am = AsMachined::nominal();
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let ball = Point3::new(26.0, 50.0, 31.2);
    let mut sim = pocket_machine((&wp, &am), (pv, 1.5, 1.0), ball);
    let first = sim.readings().deflection;
    assert!(
        first.x > 0.4 && first.z.abs() < 1e-9,
        "reads the wall: {first}"
    );
    let opts = ModeOptions::default();
    let probe = HostProbe::nominal(pv, 1.5);
    let mut m = Unobserved(&mut sim);
    let mut tr = Tracker::new(&m, probe);
    assert_eq!(recover(&mut m, &mut tr, &opts), Ok(()));
    let r = sim.readings();
    assert!(
        r.deflection.norm() < 1e-3,
        "still pressed: {}",
        r.deflection
    );
    let at = POCKET_POSE.to_part(r.scales + pv);
    // Off the wall and up off the floor (then the standoff, 5 mm, on
    // the way it came free: between the two normals), not along the floor.
    let moved = at - ball;
    assert!(moved.z > 2.0 && moved.x > 2.0, "moved by {moved}");
    assert!((moved.norm() - 5.5).abs() < 0.5, "moved by {moved}");
}
