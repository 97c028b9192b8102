//! Building the cold-search hierarchy: Bezier pieces split until flat,
//! leaves with their boxes and sample points, and the box tree over them.
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::OnceLock;

use super::grid::Grid;
use super::{Aabb, Leaf, Node, Obb, ProjectionIndex};
use crate::geometry::nurbs::bezier::{decompose, BezierPatch};
use crate::geometry::projection::newton::Bounds;
use crate::geometry::{NurbsSurface, ProjectionOptions};
use crate::math::{Point3, Vec2, Vec3};

/// Builds the hierarchy for `surface`.
pub(super) fn index(surface: &NurbsSurface, opts: &ProjectionOptions) -> ProjectionIndex {
    let mut leaf_patches = Vec::new();
    for patch in decompose(surface) {
        split_until_flat(patch, 0, opts, &mut leaf_patches);
    }
    // Neighbouring leaves share sample parameters (bitwise, mostly):
    // each distinct one is evaluated once.
    let mut points =
        PointCache::with_capacity_and_hasher(9 * leaf_patches.len(), Default::default());
    let boxes: Vec<Aabb> = leaf_patches
        .iter()
        .map(|(p, _)| aabb_of(p.points()))
        .collect();
    let leaves: Vec<Leaf> = (leaf_patches.into_iter().zip(&boxes))
        .map(|((p, obb), aabb)| make_leaf(surface, p, (obb, *aabb), &mut points))
        .collect();
    let mut nodes = Vec::with_capacity(2 * leaves.len());
    let mut ids: Vec<usize> = (0..leaves.len()).collect();
    build_tree(&boxes, &mut ids, &mut nodes);
    ProjectionIndex {
        leaves,
        nodes,
        grid: Grid::new(&boxes, opts),
        opts: *opts,
    }
}

/// Splits `patch` in halves until each piece is flat and its control
/// net's tangents turn by at most `leaf_max_turn` along u and along v,
/// collecting the pieces with their oriented boxes.
fn split_until_flat(
    patch: BezierPatch,
    depth: usize,
    opts: &ProjectionOptions,
    out: &mut Vec<(BezierPatch, Obb)>,
) {
    let obb = obb_of(&patch);
    let flat = is_flat(&obb, opts.leaf_flatness);
    let min_cos = opts.leaf_max_turn.cos();
    let turn = if flat {
        least_cosines(&patch)
    } else {
        [1.0; 2]
    };
    let turning = turn[0].min(turn[1]) < min_cos;
    if depth >= opts.max_leaf_depth || (flat && !turning) {
        out.push((patch, obb));
        return;
    }
    let along_u = if turning {
        turn[0] <= turn[1]
    } else {
        u_extent(&patch) >= v_extent(&patch)
    };
    let (a, b) = if along_u {
        patch.split_u()
    } else {
        patch.split_v()
    };
    split_until_flat(a, depth + 1, opts, out);
    split_until_flat(b, depth + 1, opts, out);
}

/// The least cosines of the angles between the control net's tangents
/// (its point differences) along u, and along v, and the first tangent of
/// their row or column (1 where a tangent vanishes).
fn least_cosines(patch: &BezierPatch) -> [f64; 2] {
    let [p, q] = patch.degree;
    let cos = |a: Vec3, b: Vec3| {
        let norms = (a.norm_squared() * b.norm_squared()).sqrt();
        if norms > 0.0 {
            a.dot(&b) / norms
        } else {
            1.0
        }
    };
    let along = |n: usize, m: usize, at: &dyn Fn(usize, usize) -> Point3| {
        let mut least = 1.0f64;
        for j in 0..=m {
            let first = at(1, j) - at(0, j);
            for i in 2..=n {
                least = least.min(cos(first, at(i, j) - at(i - 1, j)));
            }
        }
        least
    };
    [
        along(p, q, &|i, j| patch.point(i, j)),
        along(q, p, &|j, i| patch.point(i, j)),
    ]
}

fn corners(patch: &BezierPatch) -> [Point3; 4] {
    let [p, q] = patch.degree;
    [
        patch.point(0, 0),
        patch.point(p, 0),
        patch.point(0, q),
        patch.point(p, q),
    ]
}

/// Length of the control net along u (longest row polyline).
fn u_extent(patch: &BezierPatch) -> f64 {
    let [p, q] = patch.degree;
    (0..=q)
        .map(|j| {
            (1..=p)
                .map(|i| (patch.point(i, j) - patch.point(i - 1, j)).norm())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

fn v_extent(patch: &BezierPatch) -> f64 {
    let [p, q] = patch.degree;
    (0..=p)
        .map(|i| {
            (1..=q)
                .map(|j| (patch.point(i, j) - patch.point(i, j - 1)).norm())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

fn is_flat(obb: &Obb, flatness: f64) -> bool {
    let size = obb.half[0].max(obb.half[1]);
    obb.half[2] <= flatness * size
}

fn obb_of(patch: &BezierPatch) -> Obb {
    let [c00, c10, c01, c11] = corners(patch);
    let du = (c10 - c00) + (c11 - c01);
    let dv = (c01 - c00) + (c11 - c10);
    let axes = frame(du, dv);
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for pt in patch.points() {
        for k in 0..3 {
            let s = pt.coords.dot(&axes[k]);
            lo[k] = lo[k].min(s);
            hi[k] = hi[k].max(s);
        }
    }
    let mid: Vec3 = (0..3).map(|k| axes[k] * 0.5 * (lo[k] + hi[k])).sum();
    Obb {
        center: Point3::from(mid),
        axes,
        half: [0, 1, 2].map(|k| 0.5 * (hi[k] - lo[k])),
    }
}

/// Orthonormal frame with the first axis along `du` and the third along
/// `du x dv`; falls back to the coordinate axes for degenerate nets.
fn frame(du: Vec3, dv: Vec3) -> [Vec3; 3] {
    let (Some(a), Some(n)) = (
        du.try_normalize(1e-300),
        du.cross(&dv).try_normalize(1e-300),
    ) else {
        return [Vec3::x(), Vec3::y(), Vec3::z()];
    };
    [a, n.cross(&a), n]
}

fn aabb_of(points: impl Iterator<Item = Point3>) -> Aabb {
    let init = Aabb {
        min: Point3::from([f64::INFINITY; 3]),
        max: Point3::from([f64::NEG_INFINITY; 3]),
    };
    points.fold(init, |b, p| Aabb {
        min: b.min.inf(&p),
        max: b.max.sup(&p),
    })
}

/// Surface points by the bits of their parameters.
type PointCache = HashMap<(u64, u64), Point3, BuildHasherDefault<BitsHasher>>;

/// A multiplicative hash of a few words (the keys are parameter bits, not
/// input an adversary chooses).
#[derive(Default)]
struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

/// A leaf for `patch` with its oriented and axis-aligned boxes; its sample
/// points come from `points` when their parameters were evaluated already
/// (keyed by the parameters' bits, so a hit gives the very same point).
fn make_leaf(
    surface: &NurbsSurface,
    patch: BezierPatch,
    (obb, aabb): (Obb, Aabb),
    points: &mut PointCache,
) -> Leaf {
    let bounds = Bounds {
        lo: Vec2::new(patch.u.0, patch.v.0),
        hi: Vec2::new(patch.u.1, patch.v.1),
    };
    let samples = std::array::from_fn(|k| {
        let (a, b) = ((k % 3) as f64 * 0.5, (k / 3) as f64 * 0.5);
        let uv = bounds.lo + (bounds.hi - bounds.lo).component_mul(&Vec2::new(a, b));
        let point = *points
            .entry((uv.x.to_bits(), uv.y.to_bits()))
            .or_insert_with(|| surface.point(uv.x, uv.y));
        (uv, point)
    });
    Leaf {
        bounds,
        obb,
        aabb,
        samples,
        patch,
        convexity: OnceLock::new(),
    }
}

/// Builds the tree bottom-up by median splits; the root is the last node.
/// A node's box is the union of its children's (the same as the union of
/// its leaves' boxes: min and max are exact).
fn build_tree(boxes: &[Aabb], ids: &mut [usize], nodes: &mut Vec<Node>) -> usize {
    match ids {
        [] => return usize::MAX,
        [only] => {
            let Some(aabb) = boxes.get(*only).copied() else {
                return usize::MAX;
            };
            nodes.push(Node {
                aabb,
                kind: Ok(*only),
            });
            return nodes.len() - 1;
        }
        _ => {}
    }
    let centre = |i: usize| (boxes[i].min.coords + boxes[i].max.coords) * 0.5;
    let extent = ids
        .iter()
        .map(|&i| boxes[i])
        .reduce(|a, b| a.union(&b))
        .map_or(Vec3::zeros(), |b| b.max - b.min);
    let axis = extent.iamax();
    let mid = ids.len() / 2;
    ids.select_nth_unstable_by(mid, |&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]));
    let (left_ids, right_ids) = ids.split_at_mut(mid);
    let left = build_tree(boxes, left_ids, nodes);
    let right = build_tree(boxes, right_ids, nodes);
    let (Some(l), Some(r)) = (nodes.get(left), nodes.get(right)) else {
        return usize::MAX;
    };
    nodes.push(Node {
        aabb: l.aabb.union(&r.aabb),
        kind: Err((left, right)),
    });
    nodes.len() - 1
}
