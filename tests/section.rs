//! Plane sections against analytic circles and lines.
mod common;

use cmm::geometry::section::section_surface;
use cmm::geometry::{Plane, SectionOptions};
use cmm::math::{Point3, Vec3};
use cmm::workpiece::section_faces;
use common::*;

fn plane(o: [f64; 3], n: [f64; 3]) -> Plane {
    Plane::try_new(Point3::from(o), Vec3::from(n)).unwrap()
}

fn all_faces(wp: &cmm::workpiece::Workpiece) -> Vec<usize> {
    (0..wp.faces.len()).collect()
}

/// Largest sagitta between consecutive points of a circle of radius r.
fn max_sagitta(points: &[Point3], centre: Point3, r: f64, closed: bool) -> f64 {
    let n = points.len();
    let pairs = if closed { n } else { n - 1 };
    (0..pairs)
        .map(|k| {
            let (a, b) = (points[k] - centre, points[(k + 1) % n] - centre);
            let angle = a.angle(&b);
            r * (1.0 - (0.5 * angle).cos())
        })
        .fold(0.0, f64::max)
}

#[test]
fn oblique_section_of_the_sphere_is_one_closed_circle() {
    let wp = example("sphere");
    let opts = SectionOptions::default();
    for (o, n) in [
        ([0., 0., 5.], [0., 0., 1.]),
        ([1., 2., 3.], [0.3, -0.4, 0.8]),
        ([0., 0., 0.], [1., 0., 0.]),
        ([0., 0., -12.], [0., 0., 1.]),
    ] {
        let pl = plane(o, n);
        let curves = section_faces(&wp, &all_faces(&wp), &pl, &opts);
        assert_eq!(curves.len(), 1, "plane {o:?} {n:?}");
        let c = &curves[0];
        assert!(c.closed, "plane {o:?} {n:?}");
        let d = pl.signed_distance(Point3::origin());
        let centre = Point3::origin() - pl.normal() * d;
        let r = (12.5f64 * 12.5 - d * d).sqrt();
        let pts: Vec<Point3> = c.points.iter().map(|p| p.point).collect();
        for sp in &c.points {
            assert!(pl.signed_distance(sp.point).abs() < 1e-10);
            assert!(((sp.point - centre).norm() - r).abs() < 1e-10);
            let ne = (sp.normal - sp.point.coords / 12.5).norm();
            assert!(
                ne < 1e-9,
                "normal error {ne} at {:?} uv {:?}",
                sp.point,
                sp.uv
            );
        }
        let sag = max_sagitta(&pts, centre, r, true);
        assert!(
            sag <= opts.chord_tol_mm * 1.0001,
            "sagitta {sag} for plane {o:?} {n:?}"
        );
        // Counter-clockwise about the plane normal.
        let turn = (pts[1] - centre)
            .cross(&(pts[2] - centre))
            .dot(&pl.normal());
        assert!(turn > 0.0, "orientation for plane {o:?} {n:?}");
        let len = c.length();
        assert!(
            (len - std::f64::consts::TAU * r).abs() < 2e-3 * r,
            "length {len}"
        );
    }
}

#[test]
fn bore_sections_across_the_seam_and_in_two_branches() {
    let wp = example("bore");
    let opts = SectionOptions::default();
    let ring = section_faces(&wp, &[0], &plane([0., 0., 10.], [0., 0., 1.]), &opts);
    assert_eq!(ring.len(), 1);
    assert!(ring[0].closed, "the seam at u = 0/1 is stitched");
    assert!(ring[0]
        .points
        .iter()
        .all(|p| ((p.point.x.hypot(p.point.y)) - 25.0).abs() < 1e-10));
    let lines = section_faces(&wp, &[0], &plane([10., 0., 0.], [1., 0., 0.]), &opts);
    assert_eq!(lines.len(), 2, "a plane through the bore wall twice");
    let y = (25.0f64 * 25.0 - 100.0).sqrt();
    for c in &lines {
        assert!(!c.closed);
        let ends = (c.points[0].point, c.points[c.points.len() - 1].point);
        assert!(
            (ends.0.z - ends.1.z).abs() > 20.0 - 1e-9,
            "runs over the full height"
        );
        for p in &c.points {
            assert!((p.point.x - 10.0).abs() < 1e-10 && (p.point.y.abs() - y).abs() < 1e-10);
        }
    }
}

#[test]
fn blade_section_closes_over_both_surfaces() {
    let wp = example("blade");
    let opts = SectionOptions::default();
    for z in [0.0, 12.5, 50.0, 99.0] {
        let pl = plane([0., 0., z], [0., 0., 1.]);
        let curves = section_faces(&wp, &all_faces(&wp), &pl, &opts);
        assert_eq!(curves.len(), 1, "z = {z}");
        assert!(curves[0].closed, "z = {z}");
        let faces: std::collections::BTreeSet<usize> =
            curves[0].points.iter().map(|p| p.face).collect();
        assert_eq!(faces.len(), 2);
        for p in &curves[0].points {
            assert!((p.point.z - z).abs() < 1e-10);
            assert!(wp.closest_point(p.point).unwrap().projection.distance < 1e-10);
        }
        // Single surfaces give open branches, oriented consistently.
        let single = section_surface(&wp.faces[0].surface, 0, &pl, &opts);
        assert_eq!(single.len(), 1);
        assert!(!single[0].closed);
    }
}

#[test]
fn a_plane_missing_the_part_gives_nothing() {
    let wp = example("blade");
    let curves = section_faces(
        &wp,
        &all_faces(&wp),
        &plane([0., 0., 150.], [0., 0., 1.]),
        &SectionOptions::default(),
    );
    assert!(curves.is_empty());
}

#[test]
fn panel_section_is_one_open_curve_edge_to_edge() {
    let wp = example("panel");
    let curves = section_faces(
        &wp,
        &[0],
        &plane([0., 75., 0.], [0., 1., 0.]),
        &SectionOptions::default(),
    );
    assert_eq!(curves.len(), 1);
    let c = &curves[0];
    assert!(!c.closed);
    let xs = (c.points[0].point.x, c.points[c.points.len() - 1].point.x);
    assert!(
        (xs.0.min(xs.1)).abs() < 1e-9 && (xs.0.max(xs.1) - 200.0).abs() < 1e-9,
        "{xs:?}"
    );
}
