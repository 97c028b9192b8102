//! The near-search pieces against brute force: the grid lists exactly the
//! leaves whose boxes come within the bound (as a walk over all leaves
//! finds them), and a leaf's convexity certificate never spares a leaf
//! that has a point closer than the local minimum it was given (a dense
//! parameter grid over the leaf with Newton from its best points).
use super::ProjectionIndex;
use crate::geometry::projection::newton::{self, Bounds};
use crate::math::{Point3, Vec2};
use crate::workpiece::{examples, Workpiece};
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::path::Path;

fn load(file: &crate::workpiece::WorkpieceFile) -> Workpiece {
    match Workpiece::from_file(file, Path::new("example.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

fn uniform(r: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * r.random::<f64>()
}

/// A point `offset` mm along the normal from a random point of the face.
fn point_off(wp: &Workpiece, r: &mut ChaCha8Rng, offset: f64) -> (usize, Point3) {
    let i = (uniform(r, 0.0, wp.faces.len() as f64) as usize).min(wp.faces.len() - 1);
    let s = &wp.faces[i].surface;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (u, v) = (uniform(r, u0, u1), uniform(r, v0, v1));
    (i, s.point(u, v) + s.normal(u, v) * offset)
}

/// The leaves `for_leaves_near` hands over for a fixed bound, sorted.
fn listed(index: &ProjectionIndex, p: Point3, bound2: f64) -> Vec<usize> {
    let mut out = Vec::new();
    let mut b = bound2;
    let _ = index.for_leaves_near(p, &mut b, |leaf, _| -> Result<(), ()> {
        out.push(leaf);
        Ok(())
    });
    out.sort_unstable();
    out
}

/// Points near and far, bounds from tiny (one cell) to large (the tree):
/// the same leaves as a walk over all of them, each once.
#[test]
fn the_grid_lists_exactly_the_leaves_within_the_bound() {
    for (file, seed) in [
        (examples::blade(), 1),
        (examples::panel(), 2),
        (examples::reference_sphere(25.0), 3),
    ] {
        let wp = load(&file);
        let mut r = ChaCha8Rng::seed_from_u64(seed);
        for k in 0..300 {
            let off = uniform(&mut r, -3.0, 3.0);
            let (i, p) = point_off(&wp, &mut r, off);
            let radius = [0.01, 0.1, 1.0, 5.0, 40.0][k % 5];
            let index = &wp.faces[i].index();
            let got = listed(index, p, radius * radius);
            let want: Vec<usize> = (0..index.leaves.len())
                .filter(|&l| index.leaves[l].aabb.dist2(p) < radius * radius)
                .collect();
            assert_eq!(got, want, "case {k}: radius {radius} at {p}");
        }
    }
}

/// The least distance from `p` to leaf `l` of face `face` by brute force:
/// a 40 x 40 grid over its parameter box, then Newton (bounded to the box)
/// from the 8 best grid points.
fn brute_leaf(wp: &Workpiece, face: usize, bounds: &Bounds, p: Point3) -> f64 {
    let s = &wp.faces[face].surface;
    let n = 40;
    let mut grid: Vec<(f64, Vec2)> = (0..=n)
        .flat_map(|a| (0..=n).map(move |b| (a, b)))
        .map(|(a, b)| {
            let t = Vec2::new(a as f64 / n as f64, b as f64 / n as f64);
            let uv = bounds.lo + (bounds.hi - bounds.lo).component_mul(&t);
            ((s.point(uv.x, uv.y) - p).norm(), uv)
        })
        .collect();
    grid.sort_by(|a, b| a.0.total_cmp(&b.0));
    let polished = grid
        .iter()
        .take(8)
        .map(|g| newton::minimise(s, p, g.1, bounds, &wp.options).map_or(g.0, |f| f.dist2.sqrt()));
    polished.fold(grid.first().map_or(f64::INFINITY, |g| g.0), f64::min)
}

/// Largest distance of a foot counted as near, mm.
const NEAR_MM: f64 = 0.2;

/// Counts of a certificate check: near feet certified, near feet (foot
/// distance below [`NEAR_MM`]), far feet certified.
#[derive(Default)]
struct Certified {
    near_certified: usize,
    near: usize,
    far_certified: usize,
}

impl Certified {
    /// At least 80 % of the near feet's leaves certified, and some far.
    fn assert_most_near_certified(&self) {
        let (c, n) = (self.near_certified, self.near);
        assert!(c * 10 >= n * 8, "{c} of {n} near points certified");
        assert!(self.far_certified > 0, "no far point certified");
    }
}

/// Random points on both sides of the faces of `wp`, up to 0.1 mm off and
/// up to 30 mm off (where a leaf can hold more than one local minimum),
/// and Newton on the whole face from a random point of a random leaf:
/// wherever a leaf holding its foot (a local minimum) is certified, the
/// foot is that leaf's least distance (brute force). (Newton may also end
/// far away, on the seam of a closed surface, say.)
fn check_certificates(wp: &Workpiece, seed: u64, cases: usize, counts: &mut Certified) {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    for k in 0..cases {
        let reach = if k % 2 == 0 { 0.1 } else { 30.0 };
        let off = uniform(&mut r, -reach, reach);
        let (face, p) = point_off(wp, &mut r, off);
        let f = &wp.faces[face];
        let ((u0, u1), (v0, v1)) = f.surface.domain();
        let domain = Bounds {
            lo: Vec2::new(u0, v0),
            hi: Vec2::new(u1, v1),
        };
        let leaf = &f.index().leaves[(uniform(&mut r, 0.0, f.index().leaves.len() as f64)
            as usize)
            .min(f.index().leaves.len() - 1)];
        let t = Vec2::new(uniform(&mut r, 0.0, 1.0), uniform(&mut r, 0.0, 1.0));
        let start = leaf.bounds.lo + (leaf.bounds.hi - leaf.bounds.lo).component_mul(&t);
        let Ok(foot) = newton::minimise(&f.surface, p, start, &domain, &wp.options) else {
            continue;
        };
        let d = foot.dist2.sqrt();
        for holder in f
            .index()
            .leaves
            .iter()
            .filter(|l| l.bounds.contains(foot.uv))
        {
            let certified = holder.convexity().excludes_closer(d);
            if d < NEAR_MM {
                counts.near += 1;
                counts.near_certified += usize::from(certified);
            } else {
                counts.far_certified += usize::from(certified);
            }
            if certified {
                let least = brute_leaf(wp, face, &holder.bounds, p);
                assert!(
                    least >= d - 1e-9,
                    "seed {seed} case {k}: {least} < {d} on a certified leaf"
                );
            }
        }
    }
}

/// The blade and the panel (polynomial leaves): no certified leaf has a
/// closer point, and most near points are certified.
#[test]
fn a_certified_leaf_has_no_closer_point() {
    let mut counts = Certified::default();
    for (file, seed) in [(examples::blade(), 11), (examples::panel(), 12)] {
        check_certificates(&load(&file), seed, 600, &mut counts);
    }
    counts.assert_most_near_certified();
}

/// The same for rational leaves (a sphere, small and large, and a bore,
/// whose leaves' weights differ): no certified leaf has a closer point,
/// and most near points are certified.
#[test]
fn a_certified_rational_leaf_has_no_closer_point() {
    let mut counts = Certified::default();
    let files = [
        (examples::reference_sphere(25.0), 13),
        (examples::reference_sphere(400.0), 14),
        (examples::bore(50.0, 20.0), 15),
    ];
    for (file, seed) in files {
        let wp = load(&file);
        let rational = wp.faces.iter().flat_map(|f| &f.index().leaves).any(|l| {
            let w0 = l.patch.pw[0].w;
            l.patch.pw.iter().any(|c| c.w != w0)
        });
        assert!(rational, "seed {seed}: no rational leaf");
        check_certificates(&wp, seed, 600, &mut counts);
    }
    counts.assert_most_near_certified();
}
