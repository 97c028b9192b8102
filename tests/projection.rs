//! Closest-point projection against analytic oracles (sphere, finite
//! cylinder), against dense brute-force sampling, and its own inverse.
mod common;

use cmm::geometry::projection::{project_from, project_warm, WarmStart};
use cmm::geometry::ProjectionOptions;
use cmm::math::{Point3, Vec2, Vec3};
use common::*;

#[test]
fn sphere_distances_are_exact_including_poles_and_seam() {
    let wp = example("sphere");
    let mut r = rng(21);
    let mut dirs: Vec<Vec3> = (0..3000).map(|_| random_direction(&mut r)).collect();
    // Poles, seam (u = 0 at +x, y = 0) and near-pole directions.
    dirs.extend([
        Vec3::z(),
        -Vec3::z(),
        Vec3::x(),
        Vec3::new(1.0, 1e-9, 0.3).normalize(),
        Vec3::new(1e-7, 0.0, 1.0).normalize(),
    ]);
    for (k, dir) in dirs.iter().enumerate() {
        let rho = uniform(&mut r, 0.3, 27.5);
        let p = Point3::from(dir * rho);
        let fp = wp.closest_point(p).unwrap();
        let want = rho - 12.5;
        assert!(
            (fp.projection.signed_distance - want).abs() < 1e-9,
            "case {k}: {} vs {want} at {p}",
            fp.projection.signed_distance
        );
        let foot_err = (fp.projection.point - Point3::from(dir * 12.5)).norm();
        assert!(
            foot_err < 1e-6 * (1.0 + 12.5 / rho),
            "foot of case {k}: error {foot_err} at rho {rho}"
        );
    }
}

#[test]
fn finite_cylinder_distances_including_beyond_the_ends() {
    let wp = example("bore");
    let mut r = rng(22);
    for k in 0..3000 {
        let phi = uniform(&mut r, 0.0, std::f64::consts::TAU);
        let rho = uniform(&mut r, 10.0, 40.0);
        let z = uniform(&mut r, -15.0, 35.0);
        let p = Point3::new(rho * phi.cos(), rho * phi.sin(), z);
        let dz = (z - 20.0).max(-z).max(0.0);
        let want = ((rho - 25.0).powi(2) + dz * dz).sqrt();
        let pr = wp.closest_point(p).unwrap().projection;
        assert!(
            (pr.distance - want).abs() < 1e-9,
            "case {k}: {} vs {want} at {p}",
            pr.distance
        );
        // The normal points into the hole: inside the hole is positive.
        if dz == 0.0 && (rho - 25.0).abs() > 1e-6 {
            assert_eq!(pr.signed_distance > 0.0, rho < 25.0, "sign at {p}");
        }
    }
}

#[test]
fn projecting_an_offset_point_recovers_its_parameters() {
    for stem in ["panel", "blade"] {
        let wp = example(stem);
        let mut r = rng(23);
        for face in &wp.faces {
            let s = &face.surface;
            for k in 0..300 {
                let (u, v) = (uniform(&mut r, 0.05, 0.95), uniform(&mut r, 0.05, 0.95));
                let curv = s.curvature(u, v);
                let radius = 1.0 / curv.k_min.abs().max(curv.k_max.abs()).max(1e-9);
                // Outward offsets stay clear of the other side of the blade.
                let d = uniform(
                    &mut r,
                    0.0,
                    (0.5 * radius).min(if stem == "blade" { 5.0 } else { 15.0 }),
                );
                let base = s.point(u, v);
                let p = base + s.normal(u, v) * d;
                let pr =
                    project_from(s, p, Vec2::new(0.5, 0.5), &ProjectionOptions::default()).unwrap();
                assert!(
                    (pr.signed_distance - d).abs() < 1e-9,
                    "{stem} case {k}: {} vs {d}",
                    pr.signed_distance
                );
                assert!(
                    (pr.uv - Vec2::new(u, v)).norm() < 1e-8,
                    "{stem} case {k}: {:?} vs ({u}, {v})",
                    pr.uv
                );
                let cold = wp.closest_point(p).unwrap().projection;
                assert!(
                    cold.distance <= d + 1e-9,
                    "{stem} case {k}: cold {} > {d}",
                    cold.distance
                );
            }
        }
    }
}

/// Dense sampling (400 x 400 per face) gives an upper bound that the global
/// search must never exceed.
#[test]
fn cold_search_is_never_beaten_by_dense_sampling() {
    for stem in ["blade", "panel"] {
        let wp = example(stem);
        let samples: Vec<Point3> = wp
            .faces
            .iter()
            .flat_map(|f| {
                let s = &f.surface;
                (0..=400).flat_map(move |i| {
                    (0..=400).map(move |j| s.point(i as f64 / 400.0, j as f64 / 400.0))
                })
            })
            .collect();
        let (lo, hi) = bounds(&samples);
        let mut r = rng(24);
        for k in 0..150 {
            let p = Point3::new(
                uniform(&mut r, lo.x - 15.0, hi.x + 15.0),
                uniform(&mut r, lo.y - 15.0, hi.y + 15.0),
                uniform(&mut r, lo.z - 15.0, hi.z + 15.0),
            );
            let brute = samples
                .iter()
                .map(|s| (s - p).norm())
                .fold(f64::INFINITY, f64::min);
            let cold = wp.closest_point(p).unwrap().projection.distance;
            assert!(
                cold <= brute + 1e-9,
                "{stem} case {k}: cold {cold} > sampled {brute} at {p}"
            );
        }
    }
}

fn bounds(pts: &[Point3]) -> (Point3, Point3) {
    let lo = pts
        .iter()
        .fold(Point3::from([f64::INFINITY; 3]), |a, b| a.inf(b));
    let hi = pts
        .iter()
        .fold(Point3::from([f64::NEG_INFINITY; 3]), |a, b| a.sup(b));
    (lo, hi)
}

#[test]
fn warm_projection_follows_a_path_like_the_cold_one() {
    let wp = example("blade");
    let s = &wp.faces[0].surface;
    let opts = ProjectionOptions::default();
    let mut hint = wp.faces[0]
        .index()
        .project(s, s.point(0.1, 0.5) + Vec3::new(0.0, -1.5, 0.0))
        .unwrap()
        .uv;
    for k in 0..1500 {
        let t = 0.1 + 0.8 * k as f64 / 1500.0;
        let p = s.point(t, 0.5 + 0.1 * (6.0 * t).sin()) + s.normal(t, 0.5) * 1.2;
        let warm = project_from(s, p, hint, &opts).unwrap();
        let cold = wp.faces[0].index().project(s, p).unwrap();
        assert!((warm.distance - cold.distance).abs() < 1e-10, "step {k}");
        hint = warm.uv;
    }
}

/// The cached-table warm start (one query per control cycle) against the
/// analytic sphere: a random wandering path at 0.02-0.2 mm per query and
/// 0.5-5 mm off the surface, the foot and distance exact. Warm search is
/// local: a foot on the parameter boundary (the seam) is re-seeded by the
/// cold search, as the simulator does.
#[test]
fn warm_path_on_the_sphere_matches_the_analytic_foot() {
    let wp = example("sphere");
    let s = &wp.faces[0].surface;
    let mut r = rng(5);
    let mut dir = Vec3::new(1.0, 0.4, 0.2).normalize();
    let start = wp.faces[0]
        .index()
        .project(s, Point3::from(dir * 14.0))
        .unwrap();
    let mut warm = WarmStart::new(start.uv);
    for k in 0..4000 {
        let step = uniform(&mut r, 0.02, 0.2) / 12.5;
        let side = dir.cross(&random_direction(&mut r)).normalize();
        dir = (dir + side * step).normalize();
        if dir.z.abs() > 0.95 {
            dir = Vec3::new(dir.x, dir.y, 0.0).normalize();
            warm = WarmStart::new(
                wp.closest_point(Point3::from(dir * 14.0))
                    .unwrap()
                    .projection
                    .uv,
            );
        }
        let rho = 12.5 + uniform(&mut r, 0.5, 5.0) * if k % 2 == 0 { 1.0 } else { -0.2 };
        let p = Point3::from(dir * rho);
        let mut pr = project_warm(s, p, &mut warm, &ProjectionOptions::default()).unwrap();
        if pr.uv.x <= 0.0 || pr.uv.x >= 1.0 {
            pr = wp.faces[0].index().project(s, p).unwrap();
            warm = WarmStart::new(pr.uv);
        }
        assert!(
            (pr.signed_distance - (rho - 12.5)).abs() < 1e-9,
            "query {k}: {pr:?}"
        );
        assert!(
            (pr.point - Point3::from(dir * 12.5)).norm() < 1e-8,
            "foot of query {k}"
        );
    }
}

#[test]
fn points_beyond_the_boundary_project_onto_the_edge() {
    let wp = example("panel");
    let s = &wp.faces[0].surface;
    let mut r = rng(25);
    for k in 0..200 {
        let v = uniform(&mut r, 0.1, 0.9);
        let edge = s.point(0.0, v);
        let outward = -s.derivs(0.0, v, 1).su().normalize();
        let p = edge
            + outward * uniform(&mut r, 0.5, 15.0)
            + Vec3::new(0.0, 0.0, uniform(&mut r, -5.0, 5.0));
        // Reference: distance to the edge curve u = 0 by dense sampling and golden-section refinement.
        let want = edge_distance(|t| s.point(0.0, t), p);
        let pr = wp.closest_point(p).unwrap().projection;
        assert!(
            pr.uv.x == 0.0,
            "case {k}: foot should be on the u = 0 edge, got {:?}",
            pr.uv
        );
        assert!(
            (pr.distance - want).abs() < 1e-9,
            "case {k}: {} vs {want}",
            pr.distance
        );
    }
}

fn edge_distance(c: impl Fn(f64) -> Point3, p: Point3) -> f64 {
    let n = 4000;
    let best = (0..=n)
        .min_by(|&a, &b| {
            (c(a as f64 / n as f64) - p)
                .norm()
                .total_cmp(&(c(b as f64 / n as f64) - p).norm())
        })
        .unwrap();
    let (mut a, mut b) = (
        ((best as f64) - 1.0).max(0.0) / n as f64,
        ((best as f64) + 1.0).min(n as f64) / n as f64,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (x1, x2) = (b - g * (b - a), a + g * (b - a));
        if (c(x1) - p).norm() < (c(x2) - p).norm() {
            b = x2
        } else {
            a = x1
        }
    }
    (c(0.5 * (a + b)) - p).norm()
}

#[test]
fn non_finite_queries_are_errors() {
    let wp = example("sphere");
    assert!(wp.closest_point(Point3::new(f64::NAN, 0.0, 0.0)).is_err());
}
