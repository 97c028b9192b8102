//! Robustness over seeded random poses and proportions (noise-free shapes,
//! so the true element is known), and probe-radius compensation.
mod fit_support;

use cmm::fit::{
    compensate_probe, fit, Element, ElementKind, FitError, FitOptions, FitReport, Method, Side,
};
use cmm::math::{rotation_xyz_deg, Point3, Vec3};
use fit_support::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

const TOL: f64 = 1e-9;
const CASES: usize = 25;

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let angles = [0, 1, 2].map(|_| rng.random_range(-180.0..180.0));
    let shift = Vec3::new(
        rng.random_range(-500.0..500.0),
        rng.random_range(-500.0..500.0),
        rng.random_range(-500.0..500.0),
    );
    Pose {
        rot: rotation_xyz_deg(angles),
        shift,
    }
}

fn lsq(kind: ElementKind, pts: &[Point3]) -> FitReport {
    match fit(kind, Method::Lsq, pts, &FitOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("{} fit failed: {e}", kind.name()),
    }
}

#[test]
fn random_partial_cylinders() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for case in 0..CASES {
        let pose = random_pose(&mut rng);
        let rad = rng.random_range(1.0..100.0);
        let len = rad * rng.random_range(0.05..4.0);
        let span = rng.random_range(30.0f64..360.0).to_radians();
        let pts = cylinder_points(
            &pose,
            rad,
            (0.0, len),
            (rng.random_range(0.0..6.0), span),
            (3, 9),
            |_, _| 0.0,
        );
        let Element::Cylinder(c) = lsq(ElementKind::Cylinder, &pts).element else {
            panic!("not a cylinder")
        };
        let what = format!(
            "case {case}: r {rad:.3} len {len:.3} span {:.1} deg",
            span.to_degrees()
        );
        close(
            &what,
            dir_error(&c.axis_direction, &pose.dir(Vec3::z())),
            0.0,
            TOL,
        );
        close(
            &what,
            line_distance(&pose.origin(), &c.axis_point, &c.axis_direction),
            0.0,
            TOL,
        );
        close(&what, c.radius, rad, TOL);
    }
}

#[test]
fn random_partial_cones() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for case in 0..CASES {
        let pose = random_pose(&mut rng);
        let psi = rng.random_range(2.0f64..70.0).to_radians();
        let z0 = rng.random_range(1.0..50.0);
        let zs = [z0, z0 * 1.2, z0 * 1.5];
        let span = rng.random_range(60.0f64..360.0).to_radians();
        let pts = cone_points(
            &pose,
            psi,
            &zs,
            (rng.random_range(0.0..6.0), span),
            8,
            |_, _| 0.0,
        );
        let Element::Cone(c) = lsq(ElementKind::Cone, &pts).element else {
            panic!("not a cone")
        };
        let what = format!(
            "case {case}: psi {:.2} deg z0 {z0:.2} span {:.0} deg",
            psi.to_degrees(),
            span.to_degrees()
        );
        // The apex lies far from short, slender data: allow for its leverage.
        close(
            &what,
            (c.apex - pose.origin()).norm() / (1.0 + 1.0 / psi.tan()),
            0.0,
            TOL,
        );
        close(
            &what,
            (c.axis_direction - pose.dir(Vec3::z())).norm(),
            0.0,
            TOL,
        );
        close(&what, c.half_angle_rad, psi, TOL);
    }
}

#[test]
fn random_arcs_and_caps() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for case in 0..CASES {
        let pose = random_pose(&mut rng);
        let rad = rng.random_range(0.5..200.0);
        let span = rng.random_range(20.0f64..360.0).to_radians();
        let a0 = rng.random_range(0.0..6.0);
        let arc: Vec<Point3> = (0..12)
            .map(|k| a0 + span * k as f64 / 11.0)
            .map(|a| pose.point(rad * a.cos(), rad * a.sin(), 0.0))
            .collect();
        let Element::Circle(c) = lsq(ElementKind::Circle, &arc).element else {
            panic!("not a circle")
        };
        close(
            &format!("circle case {case}"),
            (c.center - pose.origin()).norm() / rad,
            0.0,
            TOL,
        );
        let cap: Vec<Point3> = (0..20)
            .map(|k| {
                (
                    0.02 + 0.5 * span / 6.0 * (k % 4) as f64,
                    a0 + 1.3 * k as f64,
                )
            })
            .map(|(pol, az)| Vec3::new(pol.sin() * az.cos(), pol.sin() * az.sin(), pol.cos()) * rad)
            .map(|v| pose.point(v.x, v.y, v.z))
            .collect();
        let Element::Sphere(s) = lsq(ElementKind::Sphere, &cap).element else {
            panic!("not a sphere")
        };
        close(
            &format!("sphere case {case}"),
            (s.center - pose.origin()).norm() / rad,
            0.0,
            TOL,
        );
        close(&format!("sphere case {case}"), s.radius / rad, 1.0, TOL);
    }
}

/// Ball centres one probe radius outside (`Outside`) or inside a surface.
fn offset_cylinder(pose: &Pose, rad: f64, probe: f64, side: Side) -> Vec<Point3> {
    let sign = if side == Side::Outside { 1.0 } else { -1.0 };
    cylinder_points(
        pose,
        rad + sign * probe,
        (0.0, 20.0),
        (0.0, std::f64::consts::TAU),
        (3, 10),
        |_, _| 0.0,
    )
}

#[test]
fn probe_compensation_cylinder_cone_plane() {
    let pose = Pose::generic();
    let opts = FitOptions::default();
    for side in [Side::Inside, Side::Outside] {
        let pts = offset_cylinder(&pose, 10.0, 1.5, side);
        let r = fit(ElementKind::Cylinder, Method::Lsq, &pts, &opts)
            .and_then(|r| compensate_probe(r, 1.5, side));
        let Ok(FitReport {
            element: Element::Cylinder(c),
            ..
        }) = r
        else {
            panic!("{r:?}")
        };
        close(side.name(), c.radius, 10.0, TOL);
    }
    let psi = 25f64.to_radians();
    let centres = cone_points(
        &pose,
        psi,
        &[10.0, 15.0, 20.0],
        (0.0, std::f64::consts::TAU),
        8,
        |_, _| 2.0,
    );
    let r = fit(ElementKind::Cone, Method::Lsq, &centres, &opts)
        .and_then(|r| compensate_probe(r, 2.0, Side::Outside));
    let Ok(FitReport {
        element: Element::Cone(c),
        ..
    }) = r
    else {
        panic!("{r:?}")
    };
    close_pt("compensated apex", &c.apex, &pose.origin(), TOL);
    let plane: Vec<Point3> = (0..9)
        .map(|k| pose.point((k % 3) as f64, (k / 3) as f64, 0.5))
        .collect();
    let r = fit(ElementKind::Plane, Method::Lsq, &plane, &opts).map(|r| r.element);
    let Ok(Element::Plane(fitted)) = r else {
        panic!("{r:?}")
    };
    let side = if fitted.normal.dot(&pose.dir(Vec3::z())) > 0.0 {
        Side::Outside
    } else {
        Side::Inside
    };
    let r = fit(ElementKind::Plane, Method::Lsq, &plane, &opts)
        .and_then(|r| compensate_probe(r, 0.5, side));
    let Ok(FitReport {
        element: Element::Plane(p),
        ..
    }) = r
    else {
        panic!("{r:?}")
    };
    close(
        "plane offset",
        (p.point - pose.origin()).dot(&p.normal),
        0.0,
        TOL,
    );
}

#[test]
fn probe_compensation_errors() {
    let pose = Pose::generic();
    let pts = offset_cylinder(&pose, 1.0, 0.0, Side::Outside);
    let opts = FitOptions::default();
    let too_big = fit(ElementKind::Cylinder, Method::Lsq, &pts, &opts)
        .and_then(|r| compensate_probe(r, 1.5, Side::Outside));
    assert!(
        matches!(too_big, Err(FitError::CompensationTooLarge { .. })),
        "{too_big:?}"
    );
    let negative = fit(ElementKind::Cylinder, Method::Lsq, &pts, &opts)
        .and_then(|r| compensate_probe(r, -1.0, Side::Inside));
    assert!(
        matches!(negative, Err(FitError::BadProbeRadius { .. })),
        "{negative:?}"
    );
    let line = fit(ElementKind::Line, Method::Lsq, &pts, &opts)
        .and_then(|r| compensate_probe(r, 1.0, Side::Inside));
    assert!(
        matches!(line, Err(FitError::NoCompensation { element: "line" })),
        "{line:?}"
    );
}
