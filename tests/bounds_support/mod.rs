//! Small bicubic patches over chosen parameter boxes, the independent
//! closest-point reference for them (a dense grid of points evaluated from
//! the NURBS definition, refined by shrinking grids around the best point)
//! and the seeded sweep of warm searches over boxes with awkward bounds.
#![allow(dead_code)]
use crate::common::{from_file, reference_point, uniform, TestRng};
use cmm::math::{Point3, Vec2};
use cmm::workpiece::{SurfaceSpec, Workpiece, WorkpieceFile};

/// A small curved bicubic patch over `[u0, u1] x [v0, v1]` (one Bezier
/// span), about 4 mm across, with mild weights.
pub fn patch(r: &mut TestRng, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> SurfaceSpec {
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
pub fn reference(spec: &SurfaceSpec, p: Point3, lo: [f64; 2], hi: [f64; 2]) -> f64 {
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

/// A workpiece of the one surface `spec`.
pub fn workpiece(spec: SurfaceSpec) -> Workpiece {
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "bounds".into(),
        units: "mm".into(),
        surfaces: vec![spec],
    })
}

/// Least distance from `p` (mm) that grids of 9 x 9 points around `c`,
/// clamped to `[lo, hi]` and halving 45 times from a tenth of the box,
/// find, the points evaluated from the definition.
pub fn local_reference(spec: &SurfaceSpec, p: Point3, c: Vec2, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let dist = |x: [f64; 2]| (Point3::from(reference_point(spec, x[0], x[1])) - p).norm();
    let mut best = (dist([c.x, c.y]), [c.x, c.y]);
    let mut half = [0.05 * (hi[0] - lo[0]), 0.05 * (hi[1] - lo[1])];
    for _ in 0..45 {
        let c = best.1;
        for i in 0..=8 {
            for j in 0..=8 {
                let at = |k: usize, a: usize| {
                    (c[a] - half[a] + 2.0 * half[a] * k as f64 / 8.0).clamp(lo[a], hi[a])
                };
                let x = [at(i, 0), at(j, 1)];
                let d = dist(x);
                if d < best.0 {
                    best = (d, x);
                }
            }
        }
        half = half.map(|h| h * 0.5);
    }
    best.0
}

/// Bounds of the warm searches: thirds and tenths, whose `x0 + (b - x0)`
/// often rounds to a neighbour of `b`, and domains far from 0.
pub const ROUNDING: [(f64, f64); 6] = [
    (0.0, 1.0 / 3.0),
    (0.1, 0.7),
    (0.1, 0.1 + 0.2),
    (2.0 / 3.0, 10.0 / 3.0),
    (1000.1, 1000.7),
    (123.456, 123.456 + 1.0 / 3.0),
];

/// Seed of the sweep of warm searches over `ROUNDING` x `ROUNDING`.
pub const ROUNDING_SWEEP_SEED: u64 = 73;

/// Hints spread over the box, half of them in its upper corner.
pub fn hints(r: &mut TestRng, lo: [f64; 2], hi: [f64; 2], n: usize) -> Vec<Vec2> {
    (0..n)
        .map(|k| {
            let from = if k % 2 == 0 { 0.0 } else { 0.8 };
            let t = |a: usize, r: &mut TestRng| lo[a] + (hi[a] - lo[a]) * uniform(r, from, 1.0);
            let u = t(0, r);
            Vec2::new(u, t(1, r))
        })
        .collect()
}

/// One patch of the sweep with its queries, each with its warm hints.
pub struct SweepPatch {
    /// The patch.
    pub spec: SurfaceSpec,
    /// Lower corner of its parameter box.
    pub lo: [f64; 2],
    /// Upper corner of its parameter box.
    pub hi: [f64; 2],
    /// Query points, each with the hints its warm searches start from.
    pub queries: Vec<(Point3, Vec<Vec2>)>,
}

/// The sweep of warm searches over `ROUNDING` x `ROUNDING` drawn from
/// `r`: per box a patch and 40 queries, mostly beyond the upper u or v
/// edge (feet on those bounds), with 6 hints each.
pub fn rounding_sweep(r: &mut TestRng) -> Vec<SweepPatch> {
    let mut out = Vec::new();
    for &(u0, u1) in &ROUNDING {
        for &(v0, v1) in &ROUNDING {
            let spec = patch(r, (u0, u1), (v0, v1));
            let (lo, hi) = ([u0, v0], [u1, v1]);
            let queries = (0..40)
                .map(|_| {
                    let p = Point3::new(
                        uniform(r, 1.0, 7.0),
                        uniform(r, 1.0, 7.0),
                        uniform(r, -3.0, 3.0),
                    );
                    (p, hints(r, lo, hi, 6))
                })
                .collect();
            out.push(SweepPatch {
                spec,
                lo,
                hi,
                queries,
            });
        }
    }
    out
}
