//! Plane sections along the edges where a surface is split into faces:
//! cylinders, cones and tori split in half at a plane through their axis
//! (as STEP files routinely store them), cut by that plane, a plane just
//! off it and planes across the split. The stretch along the shared edge
//! comes once, stitched with its neighbours.
mod common;

use cmm::geometry::{Plane, SectionCurve, SectionOptions};
use cmm::math::{Point3, Vec3};
use cmm::workpiece::{section_faces, SurfaceSpec, TrimSpec, Workpiece, WorkpieceFile};
use common::*;
use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2};

fn plane(o: [f64; 3], n: [f64; 3]) -> Plane {
    Plane::try_new(Point3::from(o), Vec3::from(n)).unwrap()
}

fn total(curves: &[SectionCurve]) -> f64 {
    curves.iter().map(SectionCurve::length).sum()
}

/// NIST CTC 05's column: two half cylinders (r 31.75, z 285.75 to 476.25)
/// and two half cones (to r 25.4 at z 482.6) split at y = 0, and the flat
/// top (faces 129 to 133).
fn ctc05_column() -> (Workpiece, Vec<usize>) {
    let wp = Workpiece::from_path(&repo("workpieces/nist-ctc05.stp")).expect("CTC 05 imports");
    let ids = (129..=133)
        .map(|k| wp.face_index(&format!("face{k}")).expect("column face"))
        .collect();
    (wp, ids)
}

const R_COLUMN: f64 = 31.75;
const R_TOP: f64 = 25.4;
const CYLINDER_HEIGHT: f64 = 476.25 - 285.75;

/// The column's profile in a plane through its axis: both cylinder lines,
/// both cone slants (6.35 mm by 6.35 mm) and the top's diameter.
fn axial_profile_mm() -> f64 {
    2.0 * CYLINDER_HEIGHT + 2.0 * (R_COLUMN - R_TOP) * SQRT_2 + 2.0 * R_TOP
}

/// Checks one open curve of the axial profile's length, every point on the
/// plane.
fn assert_axial_profile(curves: &[SectionCurve], pl: &Plane, tol: f64, what: &str) {
    let lengths: Vec<f64> = curves.iter().map(SectionCurve::length).collect();
    assert_eq!(
        curves.len(),
        1,
        "{what}: one curve, got lengths {lengths:?}"
    );
    assert!(!curves[0].closed, "{what}: the column's profile is open");
    let len = total(curves);
    assert!(
        (len - axial_profile_mm()).abs() < tol,
        "{what}: length {len}, want {}",
        axial_profile_mm()
    );
    for p in &curves[0].points {
        assert!(pl.signed_distance(p.point).abs() < 1e-6, "{what}: {p:?}");
    }
}

#[test]
fn the_column_cut_along_its_split_plane_is_its_whole_profile() {
    let (wp, ids) = ctc05_column();
    let opts = SectionOptions::default();
    for n in [[0., 1., 0.], [0., -1., 0.]] {
        let pl = plane([0., 0., 0.], n);
        let curves = section_faces(&wp, &ids, &pl, &opts);
        assert_axial_profile(&curves, &pl, 1e-6, &format!("y = 0, normal {n:?}"));
        // Both cylinder halves appear: the lines at x = +r and x = -r.
        for x in [R_COLUMN, -R_COLUMN] {
            let on_line = curves[0]
                .points
                .iter()
                .filter(|p| (p.point.x - x).abs() < 1e-6)
                .count();
            assert!(on_line > 2, "the line at x = {x}");
        }
    }
}

#[test]
fn a_plane_just_off_the_split_or_across_it_gives_the_same_profile() {
    let (wp, ids) = ctc05_column();
    let opts = SectionOptions::default();
    for (o, n) in [
        ([0., 0.01, 0.], [0., 1., 0.]),
        ([0., -0.01, 0.], [0., 1., 0.]),
        ([0., 0., 0.], [1., 0., 0.]),
        ([0., 0., 0.], [1., 1., 0.]),
    ] {
        let pl = plane(o, n);
        let curves = section_faces(&wp, &ids, &pl, &opts);
        assert_axial_profile(&curves, &pl, 1e-4, &format!("plane {o:?} {n:?}"));
    }
}

#[test]
fn each_half_cylinder_alone_includes_its_edges_in_the_split_plane() {
    let (wp, ids) = ctc05_column();
    let pl = plane([0., 0., 0.], [0., 1., 0.]);
    for &face in &ids[..2] {
        let curves = section_faces(&wp, &[face], &pl, &SectionOptions::default());
        assert_eq!(curves.len(), 2, "face {face}: the lines at x = +-r");
        for c in &curves {
            assert!(
                (c.length() - CYLINDER_HEIGHT).abs() < 1e-6,
                "{}",
                c.length()
            );
        }
    }
}

/// Perimeter of the ellipse with semi-axes `a` and `b` (Simpson's rule).
fn ellipse_perimeter(a: f64, b: f64) -> f64 {
    let n = 20_000;
    let f = |t: f64| (a * a * t.sin().powi(2) + b * b * t.cos().powi(2)).sqrt();
    let h = 2.0 * PI / n as f64;
    let sum: f64 = (0..=n)
        .map(|k| {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(k as f64 * h)
        })
        .sum();
    sum * h / 3.0
}

#[test]
fn a_tilted_plane_through_the_split_cylinder_is_one_closed_ellipse() {
    let (wp, ids) = ctc05_column();
    for deg in [20.0f64, 45.0] {
        let (s, c) = deg.to_radians().sin_cos();
        let pl = plane([0., 0., 380.], [0., s, c]);
        let curves = section_faces(&wp, &ids, &pl, &SectionOptions::default());
        assert_eq!(curves.len(), 1, "{deg} deg: {curves:?}");
        assert!(curves[0].closed, "{deg} deg: the halves meet at the split");
        // Every point on its own half, the ends at the split exactly on it
        // (not slid past the edge along the plane).
        for p in &curves[0].points {
            let side = if p.face == ids[0] { 1.0 } else { -1.0 };
            assert!(p.point.y * side > -1e-9, "{deg} deg: {p:?} off its face");
        }
        let on_split: Vec<f64> = (curves[0].points.iter())
            .filter(|p| p.point.y.abs() < 1e-9)
            .map(|p| p.point.x)
            .collect();
        assert!(
            on_split.len() == 2 && (on_split[0] * on_split[1] + R_COLUMN * R_COLUMN).abs() < 1e-6,
            "{deg} deg: the curve passes the split at x = +-r: {on_split:?}"
        );
        let want = ellipse_perimeter(R_COLUMN, R_COLUMN / c);
        let len = curves[0].length();
        assert!((len - want).abs() < 5e-3, "{deg} deg: {len} vs {want}");
    }
}

#[test]
fn a_plane_along_the_edge_between_cylinder_and_cone_is_one_circle() {
    let (wp, ids) = ctc05_column();
    for z in [476.25, 285.75] {
        let pl = plane([0., 0., z], [0., 0., 1.]);
        let curves = section_faces(&wp, &ids, &pl, &SectionOptions::default());
        assert_eq!(curves.len(), 1, "z = {z}");
        assert!(curves[0].closed, "z = {z}");
        let len = curves[0].length();
        assert!((len - 2.0 * PI * R_COLUMN).abs() < 5e-3, "z = {z}: {len}");
    }
}

const R: f64 = 25.0;
const H: f64 = 20.0;

/// The half cylinder `x^2 + y^2 = R^2`, `0 <= z <= H`, on the side `side`
/// (1 or -1) of y = 0: two rational quarter arcs, u in [0, 1], its
/// parameter domain ending at y = 0.
fn half_cylinder(name: &str, side: f64) -> SurfaceSpec {
    let arc = [[R, 0.], [R, R], [0., R], [-R, R], [-R, 0.]];
    let w = [1., FRAC_1_SQRT_2, 1., FRAC_1_SQRT_2, 1.];
    SurfaceSpec {
        name: name.into(),
        degree: [2, 1],
        knots_u: vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.],
        knots_v: vec![0., 0., 1., 1.],
        control_points: arc
            .iter()
            .map(|&[x, y]| vec![[x * side, y * side, 0.], [x * side, y * side, H]])
            .collect(),
        weights: Some(w.iter().map(|&w| vec![w, w]).collect()),
        reversed: false,
        trim: None,
    }
}

/// The full cylinder (four quarter arcs, u in [0, 1], y = 0 at u = 0, 1/2
/// and 1) trimmed to `u0 <= u <= u1`.
fn trimmed_cylinder(name: &str, u0: f64, u1: f64) -> SurfaceSpec {
    let arc = [
        [R, 0.],
        [R, R],
        [0., R],
        [-R, R],
        [-R, 0.],
        [-R, -R],
        [0., -R],
        [R, -R],
        [R, 0.],
    ];
    let w = (0..9).map(|k| if k % 2 == 1 { FRAC_1_SQRT_2 } else { 1. });
    SurfaceSpec {
        name: name.into(),
        degree: [2, 1],
        knots_u: vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.],
        knots_v: vec![0., 0., 1., 1.],
        control_points: arc
            .iter()
            .map(|&[x, y]| vec![[x, y, 0.], [x, y, H]])
            .collect(),
        weights: Some(w.map(|w| vec![w, w]).collect()),
        reversed: false,
        trim: Some(TrimSpec {
            outer: vec![[u0, 0.], [u1, 0.], [u1, 1.], [u0, 1.]],
            holes: vec![],
        }),
    }
}

fn workpiece(surfaces: Vec<SurfaceSpec>) -> Workpiece {
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "split-cylinder".into(),
        units: "mm".into(),
        surfaces,
    })
}

/// Two lines of height H at x = +-R, each once.
fn assert_two_lines(curves: &[SectionCurve], what: &str) {
    let lengths: Vec<f64> = curves.iter().map(SectionCurve::length).collect();
    assert_eq!(curves.len(), 2, "{what}: {lengths:?}");
    for c in curves {
        assert!(!c.closed, "{what}");
        assert!((c.length() - H).abs() < 1e-6, "{what}: {lengths:?}");
    }
    let xs: Vec<f64> = curves.iter().map(|c| c.points[0].point.x).collect();
    assert!((xs[0] * xs[1] + R * R).abs() < 1e-3, "{what}: x = {xs:?}");
}

#[test]
fn half_cylinders_split_at_their_domain_or_trim_edges_give_each_line_once() {
    let untrimmed = workpiece(vec![half_cylinder("up", 1.), half_cylinder("down", -1.)]);
    let trimmed = workpiece(vec![
        trimmed_cylinder("up", 0., 0.5),
        trimmed_cylinder("down", 0.5, 1.),
    ]);
    let opts = SectionOptions::default();
    for (wp, what) in [(&untrimmed, "domain edges"), (&trimmed, "trim edges")] {
        for (o, n) in [([0., 0., 0.], [0., 1., 0.]), ([0., 0., 0.], [0., -1., 0.])] {
            let curves = section_faces(wp, &[0, 1], &plane(o, n), &opts);
            assert_two_lines(&curves, &format!("{what}, normal {n:?}"));
        }
        // Just off the split: one half gives both lines, the other none.
        let curves = section_faces(wp, &[0, 1], &plane([0., 1e-3, 0.], [0., 1., 0.]), &opts);
        assert_two_lines(&curves, &format!("{what}, y = 0.001"));
        // Across the split: one closed circle.
        let pl = plane([0., 0., 10.], [0., 0.3, 1.]);
        let curves = section_faces(wp, &[0, 1], &pl, &opts);
        assert_eq!(curves.len(), 1, "{what}: tilted");
        assert!(curves[0].closed, "{what}: tilted");
    }
}
