//! Minimum-zone, minimum-circumscribed and maximum-inscribed fits against
//! constructions whose Chebyshev solution is known (convex-hull widths,
//! lobed profiles whose extremes form symmetric triangles).
mod fit_support;

use cmm::fit::{fit, Element, ElementKind, FitError, FitOptions, FitReport, Method};
use cmm::math::{Point3, Vec3};
use fit_support::*;

const TOL: f64 = 1e-9;

fn run(kind: ElementKind, method: Method, pts: &[Point3]) -> FitReport {
    match fit(kind, method, pts, &FitOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("{} {} fit failed: {e}", kind.name(), method.name()),
    }
}

#[test]
fn straightness_2d_is_hull_width() {
    // Hull triangle (0,0), (3,0), (10,1): narrowest along the edge (0,0)-(10,1),
    // width 3 / sqrt(101); least squares gives a wider zone.
    let pts: Vec<Point3> = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (10.0, 1.0)]
        .iter()
        .map(|&(x, y)| Point3::new(x, y, 0.0))
        .collect();
    let want = 3.0 / 101f64.sqrt();
    let lsq = run(ElementKind::Line2d, Method::Lsq, &pts);
    assert!(
        lsq.form_mm > want + 1e-3,
        "lsq zone {} should exceed {want}",
        lsq.form_mm
    );
    let r = run(ElementKind::Line2d, Method::MinimumZone, &pts);
    close("straightness", r.form_mm, want, TOL);
    let Element::Line2d(l) = r.element else {
        panic!("not a 2-D line")
    };
    close(
        "direction",
        dir_error(&l.direction, &Vec3::new(10.0, 1.0, 0.0)),
        0.0,
        TOL,
    );
    close("symmetric zone", r.residuals.max, -r.residuals.min, TOL);
}

#[test]
fn straightness_3d_is_cylinder_diameter() {
    let pose = Pose::generic();
    let e = 0.05;
    let pts: Vec<Point3> = (0..12)
        .map(|i| {
            let (a, s) = (turn(i % 3, 3) + 0.4, if i % 4 == 1 { 0.0 } else { e });
            pose.point(s * a.cos(), s * a.sin(), i as f64 * 2.0)
        })
        .collect();
    let r = run(ElementKind::Line, Method::MinimumZone, &pts);
    close("straightness", r.form_mm, 2.0 * e, TOL);
    let Element::Line(l) = r.element else {
        panic!("not a line")
    };
    close(
        "direction",
        dir_error(&l.direction, &pose.dir(Vec3::z())),
        0.0,
        1e-8,
    );
}

#[test]
fn flatness_is_hull_width() {
    // Corners of a square at +-h in a saddle, interior points inside the zone,
    // and one point pulling the least-squares plane.
    let h = 0.01;
    let mut pts: Vec<Point3> = [
        (1.0, 1.0, h),
        (-1.0, -1.0, h),
        (1.0, -1.0, -h),
        (-1.0, 1.0, -h),
    ]
    .iter()
    .map(|&(x, y, z)| Point3::new(x * 50.0, y * 50.0, z))
    .collect();
    pts.extend((0..9).map(|i| Point3::new(-40.0 + 10.0 * i as f64, 5.0, 0.9 * h)));
    let lsq = run(ElementKind::Plane, Method::Lsq, &pts);
    assert!(lsq.form_mm > 2.0 * h + 1e-4, "lsq flatness {}", lsq.form_mm);
    let r = run(ElementKind::Plane, Method::MinimumZone, &pts);
    close("flatness", r.form_mm, 2.0 * h, TOL);
}

/// A three-lobe circle `R + a cos(3t)` sampled every 15 degrees in the pose.
fn three_lobe(pose: &Pose, rad: f64, a: f64, z: f64) -> Vec<Point3> {
    (0..24)
        .map(|i| turn(i, 24))
        .map(|t| (t, rad + a * (3.0 * t).cos()))
        .map(|(t, r)| pose.point(r * t.cos(), r * t.sin(), z))
        .collect()
}

fn circle_of(r: &FitReport) -> cmm::fit::Circle {
    match r.element {
        Element::Circle(c) => c,
        other => panic!("not a circle: {other:?}"),
    }
}

#[test]
fn roundness_three_lobes() {
    let pose = Pose::generic();
    let (rad, a) = (30.0, 0.02);
    let pts = three_lobe(&pose, rad, a, 0.0);
    let cases = [
        (Method::MinimumZone, rad, 2.0 * a),
        (Method::MinCircumscribed, rad + a, 2.0 * a),
        (Method::MaxInscribed, rad - a, 2.0 * a),
    ];
    for (method, want_r, want_form) in cases {
        let r = run(ElementKind::Circle, method, &pts);
        let c = circle_of(&r);
        close_pt(method.name(), &c.center, &pose.origin(), TOL);
        close(method.name(), c.radius, want_r, TOL);
        close(method.name(), r.form_mm, want_form, TOL);
    }
}

#[test]
fn roundness_off_centre_start() {
    // Lobes plus a one-sided bulge: the least-squares centre is off, the
    // minimum-circumscribed circle is still through the three lobe peaks.
    let pose = Pose::generic();
    let (rad, a) = (10.0, 0.05);
    let mut pts = three_lobe(&pose, rad, a, 0.0);
    pts.extend((0..5).map(|i| {
        let t = std::f64::consts::PI + 0.1 * (i as f64 - 2.0);
        pose.point(9.9 * t.cos(), 9.9 * t.sin(), 0.0)
    }));
    let c = circle_of(&run(ElementKind::Circle, Method::MinCircumscribed, &pts));
    close_pt("center", &c.center, &pose.origin(), TOL);
    close("radius", c.radius, rad + a, TOL);
}

#[test]
fn sphericity_cube_octahedron() {
    let pose = Pose::generic();
    let (rad, e) = (15.0, 0.01);
    let mut pts = Vec::new();
    for s in 0..8 {
        let sign = |b: usize| if s & b == 0 { 1.0 } else { -1.0 };
        let v = Vec3::new(sign(1), sign(2), sign(4)).normalize() * (rad + e);
        pts.push(pose.point(v.x, v.y, v.z));
    }
    for axis in 0..6 {
        let mut v = Vec3::zeros();
        v[axis % 3] = if axis < 3 { rad - e } else { e - rad };
        pts.push(pose.point(v.x, v.y, v.z));
    }
    for (method, want_r) in [
        (Method::MinimumZone, rad),
        (Method::MinCircumscribed, rad + e),
        (Method::MaxInscribed, rad - e),
    ] {
        let r = run(ElementKind::Sphere, method, &pts);
        let Element::Sphere(s) = r.element else {
            panic!("not a sphere")
        };
        close_pt(method.name(), &s.center, &pose.origin(), TOL);
        close(method.name(), s.radius, want_r, TOL);
        close(method.name(), r.form_mm, 2.0 * e, TOL);
    }
}

#[test]
fn cylindricity_three_lobes() {
    let pose = Pose::generic();
    let (rad, a) = (12.0, 0.01);
    let pts: Vec<Point3> = [-20.0, -5.0, 10.0, 25.0]
        .iter()
        .flat_map(|&z| three_lobe(&pose, rad, a, z))
        .collect();
    for (method, want_r) in [
        (Method::MinimumZone, rad),
        (Method::MinCircumscribed, rad + a),
        (Method::MaxInscribed, rad - a),
    ] {
        let r = run(ElementKind::Cylinder, method, &pts);
        let Element::Cylinder(c) = r.element else {
            panic!("not a cylinder")
        };
        close(
            method.name(),
            dir_error(&c.axis_direction, &pose.dir(Vec3::z())),
            0.0,
            TOL,
        );
        close(
            method.name(),
            line_distance(&pose.origin(), &c.axis_point, &c.axis_direction),
            0.0,
            TOL,
        );
        close(method.name(), c.radius, want_r, TOL);
        close(method.name(), r.form_mm, 2.0 * a, TOL);
    }
}

#[test]
fn cone_minimum_zone_balanced() {
    let pose = Pose::generic();
    let psi = 20f64.to_radians();
    let e = 0.004;
    let pts = cone_points(
        &pose,
        psi,
        &[8.0, 12.0, 16.0],
        (0.0, std::f64::consts::TAU),
        6,
        |_, k| alt(k) * e,
    );
    let r = run(ElementKind::Cone, Method::MinimumZone, &pts);
    close("zone", r.form_mm, 2.0 * e, TOL);
    let Element::Cone(c) = r.element else {
        panic!("not a cone")
    };
    close("half angle", c.half_angle_rad, psi, 1e-8);
}

#[test]
fn unsupported_methods_are_refused() {
    let pts: Vec<Point3> = (0..6)
        .map(|i| Point3::new(i as f64, (i * i) as f64, 0.0))
        .collect();
    let e = fit(
        ElementKind::Plane,
        Method::MaxInscribed,
        &pts,
        &FitOptions::default(),
    );
    assert!(
        matches!(
            e,
            Err(FitError::UnsupportedMethod {
                element: "plane",
                ..
            })
        ),
        "{e:?}"
    );
}

#[test]
fn inscribed_circle_of_an_arc_is_unbounded() {
    let pts: Vec<Point3> = (0..10)
        .map(|i| (i as f64 * 5.0).to_radians())
        .map(|t| Point3::new(20.0 * t.cos(), 20.0 * t.sin(), 0.0))
        .collect();
    let r = fit(
        ElementKind::Circle,
        Method::MaxInscribed,
        &pts,
        &FitOptions::default(),
    );
    assert!(
        matches!(
            r,
            Err(FitError::Unbounded {
                element: "circle",
                ..
            })
        ),
        "{r:?}"
    );
}
