//! Ball-centre paths against analytic circles and lines.

use cmm::host::path::{BallPath, EndCondition, PathError, PathOptions};
use cmm::math::{rotation_xyz_deg, Mat3, Point3, Vec3};

/// Nominal radius of the test circle, mm.
const R: f64 = 20.0;
/// Ball-centre offset `r - Ep`, mm.
const OFFSET: f64 = 1.5;

/// A circle of radius `r` about `centre` in the plane rotated by `rot`,
/// with about `spacing` mm between points and radial outward normals.
fn circle(centre: Point3, rot: &Mat3, r: f64, spacing: f64) -> Vec<(Point3, Vec3)> {
    let n = (2.0 * std::f64::consts::PI * r / spacing).ceil() as usize;
    (0..n)
        .map(|k| {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let radial = rot * Vec3::new(phi.cos(), phi.sin(), 0.0);
            (centre + radial * r, radial)
        })
        .collect()
}

fn tilted() -> (Point3, Mat3) {
    (
        Point3::new(5.0, -3.0, 7.0),
        rotation_xyz_deg([30.0, 20.0, 10.0]),
    )
}

fn circle_path() -> BallPath {
    let (c, rot) = tilted();
    BallPath::from_section(
        &circle(c, &rot, R, 0.5),
        true,
        OFFSET,
        PathOptions::default(),
    )
    .unwrap()
}

/// Evenly spaced arc lengths over `[0, len]` (`n + 1` of them).
fn stations(len: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| len * k as f64 / n as f64)
}

#[test]
fn circle_offset_path_lies_on_the_offset_circle() {
    let (c, rot) = tilted();
    let axis = rot * Vec3::z();
    let path = circle_path();
    let (mut worst_r, mut worst_k) = (0.0f64, 0.0f64);
    for s in stations(path.length(), 20_000) {
        let d = path.position(s) - c;
        worst_r = worst_r.max((d.norm() - (R + OFFSET)).abs());
        assert!(d.dot(&axis).abs() < 1e-9, "off the plane at s = {s}");
        let rel = (path.curvature(s) * (R + OFFSET) - 1.0).abs();
        worst_k = worst_k.max(rel);
    }
    assert!(worst_r < 1e-6, "radial error {worst_r:e} mm");
    assert!(worst_k < 1e-3, "relative curvature error {worst_k:e}");
}

#[test]
fn circle_arc_length_is_two_pi_r() {
    let path = circle_path();
    let exact = 2.0 * std::f64::consts::PI * (R + OFFSET);
    assert!(
        (path.length() - exact).abs() < 1e-5,
        "{} vs {exact}",
        path.length()
    );
    assert!(path.is_closed());
}

#[test]
fn circle_tangent_is_perpendicular_to_radius_and_normal_is_radial() {
    let (c, _) = tilted();
    let path = circle_path();
    for s in stations(path.length(), 997) {
        let radial = (path.position(s) - c).normalize();
        assert!(path.tangent(s).dot(&radial).abs() < 1e-6);
        assert!((path.tangent(s).norm() - 1.0).abs() < 1e-12);
        let n = path.normal(s);
        assert!((n.norm() - 1.0).abs() < 1e-12);
        assert!(n.dot(&radial) > 1.0 - 1e-3, "normal not radial at s = {s}");
    }
}

#[test]
fn samples_keep_their_nominal_points_and_normals() {
    let (c, rot) = tilted();
    let pts = circle(c, &rot, R, 0.5);
    let path = circle_path();
    assert_eq!(path.samples().len(), pts.len());
    for (sample, (p, n)) in path.samples().iter().zip(&pts) {
        assert_eq!(sample.nominal, *p);
        assert!((sample.normal - n).norm() < 1e-15);
        assert!((path.position(sample.s) - sample.centre).norm() < 1e-9);
        assert!((sample.centre - (p + n * OFFSET)).norm() < 1e-12);
        assert!((path.normal(sample.s) - n).norm() < 1e-9);
    }
}

/// Points along a line with uneven spacing and a normal perpendicular to it.
fn line_points() -> Vec<(Point3, Vec3)> {
    let dir = Vec3::new(1.0, 2.0, -0.5).normalize();
    let normal = dir.cross(&Vec3::z()).normalize();
    let start = Point3::new(-3.0, 4.0, 1.0);
    (0..60)
        .map(|k| {
            let t = 0.5 * k as f64 + 0.2 * (k as f64 * 1.3).sin();
            (start + dir * t, normal)
        })
        .collect()
}

#[test]
fn straight_line_stays_straight() {
    let pts = line_points();
    let (p0, n) = pts[0];
    let dir = (pts[1].0 - p0).normalize();
    for end in [EndCondition::Natural, EndCondition::NotAKnot] {
        let opts = PathOptions {
            end,
            ..PathOptions::default()
        };
        let path = BallPath::from_section(&pts, false, 2.0, opts).unwrap();
        let base = p0 + n * 2.0;
        for s in stations(path.length(), 5000) {
            let d = path.position(s) - base;
            assert!(
                (d - dir * d.dot(&dir)).norm() < 1e-9,
                "off the line at s = {s}"
            );
            assert!(
                path.curvature(s) < 1e-9,
                "curvature {} at s = {s}",
                path.curvature(s)
            );
            assert!(
                (d.dot(&dir) - s).abs() < 1e-9,
                "arc length is not distance at s = {s}"
            );
        }
    }
}

/// An open wavy 3-D curve with normals roughly perpendicular to it.
fn wave() -> Vec<(Point3, Vec3)> {
    (0..80)
        .map(|k| {
            let x = 0.6 * k as f64 + 0.1 * (k as f64).cos();
            let p = Point3::new(x, 3.0 * (0.3 * x).sin(), 0.5 * (0.2 * x).cos());
            let slope = 0.9 * (0.3 * x).cos();
            (p, Vec3::new(-slope, 1.0, 0.0))
        })
        .collect()
}

/// Jumps of the one-sided first and second finite differences at `s`
/// (step `delta`, mm) of a curve parameterised by arc length.
fn fd_jumps(p: impl Fn(f64) -> Vec3, s: f64, delta: f64) -> (f64, f64) {
    let q = |k: f64| p(s + k * delta);
    let left2 = (q(-2.0) - q(-1.0) * 2.0 + q(0.0)) / (delta * delta);
    let right2 = (q(0.0) - q(1.0) * 2.0 + q(2.0)) / (delta * delta);
    let left1 = (q(0.0) - q(-1.0)) / delta;
    let right1 = (q(1.0) - q(0.0)) / delta;
    ((left1 - right1).norm(), (left2 - right2).norm())
}

/// Largest finite-difference jump allowed at a C2 joint (the one-sided
/// second differences differ by about `2 delta |P'''|` even when smooth).
const FD_TOL: f64 = 2e-3;

#[test]
fn joints_are_c2_by_coefficients_and_finite_differences() {
    let path = BallPath::from_section(&wave(), false, 1.0, PathOptions::default()).unwrap();
    let segs = path.segments();
    for (i, pair) in segs.windows(2).enumerate() {
        let h = pair[0].param_len();
        assert!(
            (pair[0].position(h) - pair[1].position(0.0)).norm() < 1e-12,
            "C0 at {i}"
        );
        assert!(
            (pair[0].d1(h) - pair[1].d1(0.0)).norm() < 1e-10,
            "C1 at {i}"
        );
        assert!((pair[0].d2(h) - pair[1].d2(0.0)).norm() < 1e-9, "C2 at {i}");
    }
    for j in 1..segs.len() {
        let s = path.segment_start(j).unwrap();
        let (d1, d2) = fd_jumps(|x| path.position(x).coords, s, 1e-3);
        assert!(
            d1 < FD_TOL && d2 < FD_TOL,
            "joint {j}: jumps {d1:e}, {d2:e}"
        );
    }
}

#[test]
fn finite_difference_check_detects_a_curvature_jump() {
    // A line continued by a tangent arc of radius 5 mm is C1 but not C2:
    // the check used above must flag it.
    let line_arc = |s: f64| {
        if s <= 0.0 {
            Vec3::new(s, 0.0, 0.0)
        } else {
            Vec3::new(5.0 * (s / 5.0).sin(), 5.0 - 5.0 * (s / 5.0).cos(), 0.0)
        }
    };
    let (d1, d2) = fd_jumps(line_arc, 0.0, 1e-3);
    assert!(d1 < FD_TOL, "tangent is continuous: {d1:e}");
    assert!(d2 > 0.1, "curvature jump 0.2 /mm not seen: {d2:e}");
}

#[test]
fn spline_through_a_corner_has_high_curvature_there() {
    let pts = vec![
        (Point3::new(0.0, 0.0, 0.0), Vec3::y()),
        (Point3::new(1.0, 0.0, 0.0), Vec3::y()),
        (Point3::new(1.0, 1.0, 0.0), Vec3::y()),
    ];
    let path = BallPath::from_section(&pts, false, 0.0, PathOptions::default()).unwrap();
    let s = path.segment_start(1).unwrap();
    assert!(path.curvature(s) > 0.5, "{}", path.curvature(s));
}

#[test]
fn closest_s_recovers_s_warm_and_cold() {
    let (c, _) = tilted();
    let path = circle_path();
    let len = path.length();
    for k in 0..200 {
        let s0 = len * (k as f64 + 0.37) / 200.0;
        let p = path.position(s0);
        let q = p + (p - c).normalize() * (0.3 - 0.006 * k as f64);
        let warm = path
            .closest_s(&q, Some((s0 + 0.8).rem_euclid(len)))
            .unwrap();
        let cold = path.closest_s(&q, None).unwrap();
        for got in [warm, cold] {
            let err = (got - s0 + 0.5 * len).rem_euclid(len) - 0.5 * len;
            assert!(err.abs() < 1e-6, "s0 = {s0}: got {got} (err {err:e})");
        }
    }
}

#[test]
fn closest_s_wraps_around_the_closing_segment() {
    let path = circle_path();
    let len = path.length();
    let q = path.position(0.05) + path.normal(0.05) * 0.2;
    let got = path.closest_s(&q, Some(len - 0.4)).unwrap();
    assert!((got - 0.05).abs() < 1e-3, "{got}");
}

#[test]
fn closest_s_on_an_open_path_clamps_to_the_ends() {
    let path = BallPath::from_section(&line_points(), false, 0.0, PathOptions::default()).unwrap();
    let (p0, dir) = (path.position(0.0), path.tangent(0.0));
    let before = p0 - dir * 3.0 + Vec3::z() * 0.1;
    assert_eq!(path.closest_s(&before, None).unwrap(), 0.0);
    let end = path.position(path.length()) + path.tangent(path.length()) * 2.0;
    let got = path.closest_s(&end, Some(path.length() - 1.0)).unwrap();
    assert!((got - path.length()).abs() < 1e-12);
    let mid = path.position(7.3) + path.normal(7.3) * 0.4;
    assert!((path.closest_s(&mid, Some(5.0)).unwrap() - 7.3).abs() < 1e-9);
}

#[test]
fn degenerate_input_is_rejected_with_typed_errors() {
    let o = PathOptions::default();
    let p = |x: f64| (Point3::new(x, 0.0, 0.0), Vec3::y());
    let err = BallPath::from_section(&[p(0.0)], false, 1.0, o).unwrap_err();
    assert!(matches!(
        err,
        PathError::TooFewPoints {
            count: 1,
            min: 2,
            ..
        }
    ));
    let err = BallPath::from_section(&[p(0.0), p(1.0)], true, 1.0, o).unwrap_err();
    assert!(matches!(
        err,
        PathError::TooFewPoints {
            count: 2,
            min: 3,
            ..
        }
    ));
    let err = BallPath::from_section(&[p(0.0), p(1.0), p(1.0)], false, 1.0, o).unwrap_err();
    assert!(matches!(
        err,
        PathError::CoincidentPoints {
            index: 1,
            next: 2,
            ..
        }
    ));
    let err = BallPath::from_section(&[p(0.0), p(1.0), p(0.0)], true, 1.0, o).unwrap_err();
    assert!(matches!(
        err,
        PathError::CoincidentPoints {
            index: 2,
            next: 0,
            ..
        }
    ));
    let err = BallPath::from_section(&[p(0.0), p(f64::NAN)], false, 1.0, o).unwrap_err();
    assert_eq!(err, PathError::NonFinite { index: 1 });
    let zero = (Point3::new(2.0, 0.0, 0.0), Vec3::zeros());
    let err = BallPath::from_section(&[p(0.0), zero], false, 1.0, o).unwrap_err();
    assert!(matches!(err, PathError::ZeroNormal { index: 1, .. }));
    let err = BallPath::from_section(&[p(0.0), p(1.0)], false, f64::INFINITY, o).unwrap_err();
    assert!(matches!(err, PathError::NonFiniteOffset { .. }));
    let path = BallPath::from_section(&[p(0.0), p(1.0)], false, 1.0, o).unwrap();
    assert_eq!(
        path.closest_s(&Point3::new(f64::NAN, 0.0, 0.0), None),
        Err(PathError::NonFiniteQuery)
    );
}

#[test]
fn open_arc_with_not_a_knot_ends_stays_on_the_circle() {
    let (c, rot) = tilted();
    let mut pts = circle(c, &rot, R, 0.5);
    pts.truncate(pts.len() / 3);
    let opts = PathOptions {
        end: EndCondition::NotAKnot,
        ..PathOptions::default()
    };
    let path = BallPath::from_section(&pts, false, OFFSET, opts).unwrap();
    assert!(!path.is_closed());
    let worst = stations(path.length(), 5000)
        .map(|s| ((path.position(s) - c).norm() - (R + OFFSET)).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "radial error {worst:e} mm");
    // Natural ends force zero curvature at the ends: visibly off the circle.
    let opts = PathOptions {
        end: EndCondition::Natural,
        ..opts
    };
    let natural = BallPath::from_section(&pts, false, OFFSET, opts).unwrap();
    assert!(natural.curvature(0.0) < 1e-9);
    assert!((path.curvature(0.0) * (R + OFFSET) - 1.0).abs() < 1e-2);
}
