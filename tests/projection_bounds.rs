//! Closest points near the parameter bounds of small patches whose bounds
//! do not round-trip (`x0 + (hi - x0) != hi`), such as an upper knot of
//! 1.0000000000000002 or 0.1 + 0.2, untrimmed and trimmed to rectangles,
//! against an independent reference: a dense grid of points evaluated from
//! the NURBS definition, refined by shrinking grids around the best point.
mod common;

use cmm::geometry::projection::SearchStatus;
use cmm::math::Point3;
use cmm::workpiece::{SurfaceSpec, TrimSpec, Workpiece, WorkpieceFile};
use common::*;

/// A small curved bicubic patch over `[u0, u1] x [v0, v1]` (one Bezier
/// span), about 4 mm across, with mild weights.
fn patch(r: &mut TestRng, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> SurfaceSpec {
    let cps = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64 * 1.3, j as f64 * 1.3);
                    // Bent and twisted: the Newton model couples u and v.
                    let bulge = 0.35 * ((x - 2.0).powi(2) - 0.6 * (y - 2.0).powi(2))
                        + 0.5 * (x - 2.0) * (y - 2.0);
                    [
                        x + uniform(r, -0.2, 0.2),
                        y + uniform(r, -0.2, 0.2),
                        bulge + uniform(r, -0.3, 0.3),
                    ]
                })
                .collect()
        })
        .collect();
    let weights = (0..4)
        .map(|_| (0..4).map(|_| uniform(r, 0.7, 1.4)).collect())
        .collect();
    SurfaceSpec {
        name: "patch".into(),
        degree: [3, 3],
        knots_u: vec![u0, u0, u0, u0, u1, u1, u1, u1],
        knots_v: vec![v0, v0, v0, v0, v1, v1, v1, v1],
        control_points: cps,
        weights: Some(weights),
        reversed: false,
        trim: None,
    }
}

/// Least distance from `p` to the patch over the parameter rectangle
/// `[lo, hi]`: an 81 x 81 grid, then 9 x 9 grids shrinking by 4 around the
/// best point, clamped to the rectangle, with the points evaluated from
/// the definition.
fn reference(spec: &SurfaceSpec, p: Point3, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let dist = |u: f64, v: f64| (Point3::from(reference_point(spec, u, v)) - p).norm();
    let grid = |c: [f64; 2], half: [f64; 2], n: usize, best: &mut (f64, [f64; 2])| {
        for i in 0..=n {
            for j in 0..=n {
                let t = |k: usize, a: usize| {
                    let x = c[a] - half[a] + 2.0 * half[a] * k as f64 / n as f64;
                    x.clamp(lo[a], hi[a])
                };
                let (u, v) = (t(i, 0), t(j, 1));
                let d = dist(u, v);
                if d < best.0 {
                    *best = (d, [u, v]);
                }
            }
        }
    };
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
    let mut best = (f64::INFINITY, mid);
    grid(mid, half, 80, &mut best);
    half = half.map(|h| h * 2.0 / 80.0 * 2.0);
    for _ in 0..40 {
        let c = best.1;
        grid(c, half, 8, &mut best);
        half = half.map(|h| h * 0.25);
    }
    best.0
}

fn workpiece(spec: SurfaceSpec) -> Workpiece {
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "bounds".into(),
        units: "mm".into(),
        surfaces: vec![spec],
    })
}

/// Query points near the patch, most of them beyond an edge or a corner
/// (feet on the bounds).
fn queries(r: &mut TestRng, n: usize) -> Vec<Point3> {
    (0..n)
        .map(|_| {
            Point3::new(
                uniform(r, -4.0, 8.0),
                uniform(r, -4.0, 8.0),
                uniform(r, -4.0, 4.0),
            )
        })
        .collect()
}

/// Bounds whose `x0 + (hi - x0)` is one unit in the last place short of
/// `hi` for many `x0`.
const AWKWARD: [(f64, f64); 4] = [
    (0.0, 1.000_000_000_000_000_2),
    (0.1, 0.1 + 0.2),
    (-0.7, 0.9 + 1e-16),
    (2.0 / 3.0, 10.0 / 3.0),
];

/// Checks every query against the reference over `[lo, hi]`.
fn check_all(wp: &Workpiece, spec: &SurfaceSpec, lo: [f64; 2], hi: [f64; 2], r: &mut TestRng) {
    for (k, p) in queries(r, 80).into_iter().enumerate() {
        let want = reference(spec, p, lo, hi);
        let fp = cmm::evaluate::closest_point(wp, p).unwrap();
        let got = fp.projection;
        assert_eq!(got.status, SearchStatus::Confirmed, "query {k} at {p}");
        assert!(
            (got.distance - want).abs() < 1e-9,
            "query {k} at {p}: {} vs reference {want} (foot {:?}, bounds {lo:?} {hi:?})",
            got.distance,
            got.uv
        );
    }
}

#[test]
fn untrimmed_patches_with_awkward_bounds_match_the_reference() {
    let mut r = rng(71);
    for &(u0, u1) in &AWKWARD {
        for &(v0, v1) in &AWKWARD {
            let spec = patch(&mut r, (u0, u1), (v0, v1));
            let wp = workpiece(spec.clone());
            check_all(&wp, &spec, [u0, v0], [u1, v1], &mut r);
        }
    }
}

#[test]
fn rectangular_trims_with_awkward_bounds_match_the_reference() {
    let mut r = rng(72);
    for &(u0, u1) in &AWKWARD {
        let (v0, v1) = (0.0, 1.0);
        let mut spec = patch(&mut r, (u0, u1), (v0, v1));
        // A rectangle reaching the upper u bound, its v range inside.
        let (tu0, tv0, tv1) = (u0 + 0.3 * (u1 - u0), 0.1 + 0.2, 0.7 + 0.1);
        spec.trim = Some(TrimSpec {
            outer: vec![[tu0, tv0], [u1, tv0], [u1, tv1], [tu0, tv1]],
            holes: vec![],
        });
        let wp = workpiece(spec.clone());
        check_all(&wp, &spec, [tu0, tv0], [u1, tv1], &mut r);
    }
}
