//! Trimmed faces: closest points stay on the face (on its boundary when the
//! unconstrained foot is off it), sections are clipped to it. Oracle: a flat
//! square face (x = 100 u, y = 100 v, z = 0) trimmed by polygons, where the
//! answer is plane geometry.
mod common;

use cmm::geometry::{Plane, SectionOptions};
use cmm::math::{Point3, Vec2, Vec3};
use cmm::workpiece::{section_faces, SurfaceSpec, TrimSpec, WorkpieceFile};
use common::*;

fn polygon(centre: [f64; 2], radius: f64, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
        })
        .collect()
}

fn hole() -> Vec<[f64; 2]> {
    vec![[0.4, 0.4], [0.4, 0.6], [0.6, 0.6], [0.6, 0.4]]
}

fn face() -> (cmm::workpiece::Workpiece, Vec<Vec<[f64; 2]>>) {
    let outer = polygon([0.5, 0.5], 0.3, 64);
    let spec = SurfaceSpec {
        name: "flat".into(),
        degree: [1, 1],
        knots_u: vec![0., 0., 1., 1.],
        knots_v: vec![0., 0., 1., 1.],
        control_points: vec![
            vec![[0., 0., 0.], [0., 100., 0.]],
            vec![[100., 0., 0.], [100., 100., 0.]],
        ],
        weights: None,
        reversed: false,
        trim: Some(TrimSpec {
            outer: outer.clone(),
            holes: vec![hole()],
        }),
    };
    let file = WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "t".into(),
        units: "mm".into(),
        surfaces: vec![spec],
    };
    (from_file(&file), vec![outer, hole()])
}

/// Distance in the plane from `q` to the trimmed region (polygons in mm).
fn region_distance(q: Vec2, loops: &[Vec<[f64; 2]>]) -> f64 {
    let scaled: Vec<Vec<Vec2>> = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|p| Vec2::new(100.0 * p[0], 100.0 * p[1]))
                .collect()
        })
        .collect();
    let crossings: usize = scaled
        .iter()
        .map(|l| {
            (0..l.len())
                .filter(|&k| {
                    let (a, b) = (l[k], l[(k + 1) % l.len()]);
                    (a.y > q.y) != (b.y > q.y)
                        && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x)
                })
                .count()
        })
        .sum();
    if crossings % 2 == 1 {
        return 0.0;
    }
    scaled
        .iter()
        .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
        .map(|(a, b)| {
            let t = ((q - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
            (q - (a + (b - a) * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn closest_points_stay_on_the_trimmed_face() {
    let (wp, loops) = face();
    let mut r = rng(41);
    for k in 0..2000 {
        let p = Point3::new(
            uniform(&mut r, -10.0, 110.0),
            uniform(&mut r, -10.0, 110.0),
            uniform(&mut r, -15.0, 15.0),
        );
        let planar = region_distance(Vec2::new(p.x, p.y), &loops);
        let want = (planar * planar + p.z * p.z).sqrt();
        let got = wp.closest_point(p).unwrap().projection;
        assert!(
            (got.distance - want).abs() < 1e-9,
            "case {k}: {} vs {want} at {p}",
            got.distance
        );
        let on_face = region_distance(Vec2::new(got.point.x, got.point.y), &loops);
        assert!(
            on_face < 1e-9,
            "case {k}: foot {} is off the face by {on_face}",
            got.point
        );
    }
}

#[test]
fn sections_are_clipped_to_the_face() {
    let (wp, _) = face();
    let plane = Plane::try_new(Point3::new(50.0, 0.0, 0.0), Vec3::x()).unwrap();
    let mut curves = section_faces(&wp, &[0], &plane, &SectionOptions::default());
    assert_eq!(curves.len(), 2, "the hole splits the line in two");
    curves.sort_by(|a, b| {
        a.points[0]
            .point
            .y
            .min(a.points[a.points.len() - 1].point.y)
            .total_cmp(
                &b.points[0]
                    .point
                    .y
                    .min(b.points[b.points.len() - 1].point.y),
            )
    });
    // The 64-gon's edge crossing x = 50 lies at its apothem-adjusted radius.
    let apothem = 30.0 * (std::f64::consts::PI / 64.0).cos();
    let outer_y = 30.0 * (std::f64::consts::TAU / 64.0 * 16.0).sin();
    let want = [
        (50.0 - apothem.max(outer_y).min(30.0), 40.0),
        (60.0, 50.0 + 30.0),
    ];
    for (c, (lo, hi)) in curves.iter().zip(want) {
        let ys: Vec<f64> = c.points.iter().map(|p| p.point.y).collect();
        let (a, b) = (
            ys.iter().cloned().fold(f64::INFINITY, f64::min),
            ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        );
        assert!(
            (a - lo).abs() < 1e-9 && (b - hi).abs() < 1e-9,
            "section from {a} to {b}, expected {lo} to {hi}"
        );
        assert!(c
            .points
            .iter()
            .all(|p| p.point.x == 50.0 || (p.point.x - 50.0).abs() < 1e-12));
    }
}
