//! A rational torus (held-back-style shape): global closest distances for
//! points within 15 mm of the surface, against the analytic torus distance.
mod common;

use cmm::math::Point3;
use cmm::workpiece::WorkpieceFile;
use common::*;

const MAJOR: f64 = 30.0;
const MINOR: f64 = 10.0;

/// Torus about z: u around the axis, v around the tube (the tube's circle
/// revolved like the shipped sphere and bore).
fn torus() -> WorkpieceFile {
    let (circle, weights, knots) = cmm::workpiece::examples::unit_circle();
    let profile: Vec<[f64; 2]> = circle
        .iter()
        .map(|[a, b]| [MAJOR + MINOR * a, MINOR * b])
        .collect();
    let spec = cmm::workpiece::examples::revolve("torus", &profile, &weights, knots, false);
    WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "torus".into(),
        units: "mm".into(),
        surfaces: vec![spec],
    }
}

#[test]
fn torus_distances_are_the_global_minimum() {
    let wp = from_file(&torus());
    let mut r = rng(51);
    let mut checked = 0;
    while checked < 3000 {
        let p = Point3::new(
            uniform(&mut r, -55.0, 55.0),
            uniform(&mut r, -55.0, 55.0),
            uniform(&mut r, -25.0, 25.0),
        );
        let rho = p.x.hypot(p.y);
        let tube = ((rho - MAJOR).powi(2) + p.z * p.z).sqrt();
        let want = tube - MINOR;
        if want.abs() > 15.0 {
            continue;
        }
        checked += 1;
        let got = wp.closest_point(p).unwrap().projection;
        assert!(
            (got.distance - want.abs()).abs() < 1e-9,
            "{p}: {} vs {}",
            got.distance,
            want.abs()
        );
        if want.abs() > 1e-6 {
            let outward_expected = want > 0.0;
            let normal_side = (p - got.point).dot(&got.normal) > 0.0;
            assert_eq!(normal_side, outward_expected, "sign at {p}");
        }
    }
    // The tube's centre circle and the axis: every tube point / the inner
    // equator is equally close.
    for p in [
        Point3::new(MAJOR, 0.0, 0.0),
        Point3::new(0.0, -MAJOR, 0.0),
        Point3::origin(),
        Point3::new(0.0, 0.0, 3.0),
    ] {
        let rho = p.x.hypot(p.y);
        let want = (((rho - MAJOR).powi(2) + p.z * p.z).sqrt() - MINOR).abs();
        let got = wp.closest_point(p).unwrap().projection.distance;
        assert!((got - want).abs() < 1e-9, "{p}: {got} vs {want}");
    }
}
