//! The leaf tree made for the nominal pieces and refitted to a machined
//! part's leaves answers every query as a look at every leaf does: the
//! leaves within a distance of points and segments, and the nearest leaf
//! bound, on a real part (the flange) moved, turned and stretched.
use super::leaves::{LeafOptions, Leaves, Pieces};
use super::shapes::Segment;
use super::tree::{LeafTree, Shape};
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::Workpiece;
use crate::world::as_machined::{AsMachined, AsMachinedSpec};
use rand::{RngExt, SeedableRng};

/// The flange of `workpieces/`.
pub(super) fn flange() -> Workpiece {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/io1-flange.stp");
    Workpiece::from_path(&path).unwrap()
}

/// The flange moved, turned, stretched, offset and bumped.
pub(super) fn machined(wp: &Workpiece) -> AsMachined {
    let spec: AsMachinedSpec = serde_json::from_str(
        r#"{"transform":{"translate_mm":[0.4,-0.3,0.2],"rotate_deg":[0.5,-0.3,0.8],"scale":1.002},
            "form":[{"kind":"offset","mm":0.02},
                    {"kind":"bump","center_mm":[6,32.5,18.75],"radius_mm":3,"height_mm":0.05}]}"#,
    )
    .unwrap();
    AsMachined::from_spec(&spec, wp).unwrap()
}

/// Every leaf whose bound from `shape` is below `radius`, by looking at
/// each.
fn brute<S: Shape>(leaves: &Leaves, shape: S, radius: f64) -> Vec<u32> {
    let r2 = radius * radius;
    (0..leaves.leaves.len() as u32)
        .filter(|&i| {
            let l = &leaves.leaves[i as usize];
            shape.leaf_bound_within(l, r2).is_some_and(|b| b < radius)
        })
        .collect()
}

/// The tree's leaves within `radius` of `shape` against [`brute`]; their
/// number.
fn check_within<S: Shape + std::fmt::Debug>(
    tree: &LeafTree,
    leaves: &Leaves,
    shape: S,
    radius: f64,
) -> usize {
    let mut got = Vec::new();
    tree.within(&leaves.leaves, shape, radius, &mut got);
    got.sort_unstable();
    assert_eq!(
        got,
        brute(leaves, shape, radius),
        "{shape:?} within {radius}"
    );
    got.len()
}

#[test]
fn refitted_tree_answers_as_every_leaf_does() {
    let wp = flange();
    let pieces = Pieces::new(&wp, &LeafOptions::default());
    let am = machined(&wp);
    let leaves = Leaves::of(&pieces, &am);
    let tree = pieces.tree.refit(&leaves.leaves);
    let fresh = {
        let boxes: Vec<_> = leaves.leaves.iter().map(|l| l.aabb).collect();
        LeafTree::over(&boxes)
    };
    let (lo, hi) = leaves.leaves.iter().fold(
        (
            Point3::from(Vec3::repeat(f64::INFINITY)),
            Point3::from(Vec3::repeat(f64::NEG_INFINITY)),
        ),
        |(lo, hi), l| (lo.inf(&l.aabb.min), hi.sup(&l.aabb.max)),
    );
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
    // Points over the part's box and 2 mm beyond.
    let mut point = || {
        let t = Vec3::new(rng.random(), rng.random(), rng.random());
        let span = hi - lo + Vec3::repeat(4.0);
        Point3::from(lo.coords - Vec3::repeat(2.0) + span.component_mul(&t))
    };
    let mut hits = 0;
    for k in 0..400 {
        let p = point();
        let q = point();
        let radius = 0.5 + (k % 7) as f64;
        hits += check_within(&tree, &leaves, p, radius);
        check_within(&tree, &leaves, Segment { a: p, b: q }, radius);
        let all = (leaves.leaves.iter())
            .map(|l| p.leaf_bound(l))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(tree.nearest(&leaves.leaves, p), all);
        assert_eq!(fresh.nearest(&leaves.leaves, p), all);
    }
    assert!(hits > 1000, "{hits}");
}

/// Every leaf's box, slab and oriented box hold the true surface over its
/// rectangle (points of it from the as-machined part's own evaluation), for
/// the machined flange and for variants of it, whose leaves place the
/// bounds the first one made at their own translation and form.
#[test]
fn placed_leaves_hold_their_true_surface() {
    let wp = flange();
    let pieces = Pieces::new(&wp, &LeafOptions::default());
    let base = machined(&wp);
    for am in [base.clone(), base.variant(3), base.variant(11)] {
        let leaves = Leaves::of(&pieces, &am);
        let mut worst: f64 = 0.0;
        for l in &leaves.leaves {
            for (i, j) in (0..5).flat_map(|i| (0..5).map(move |j| (i, j))) {
                let (s, t) = (f64::from(i) / 4.0, f64::from(j) / 4.0);
                let uv = l.bounds.lo + (l.bounds.hi - l.bounds.lo).component_mul(&Vec2::new(s, t));
                let q = am.true_point(&wp, l.face, uv);
                worst = worst.max(l.tight_bound(q, l.lower_bound(q)));
            }
        }
        assert!(
            worst < 1e-9,
            "a true point {worst} mm outside its leaf's bounds"
        );
    }
}

/// The tree's nearest bound within a ratio of the excess over an offset
/// keeps that ratio and never exceeds the least bound.
#[test]
fn nearest_within_a_ratio_keeps_it() {
    let wp = flange();
    let pieces = Pieces::new(&wp, &LeafOptions::default());
    let leaves = Leaves::of(&pieces, &machined(&wp));
    let tree = pieces.tree.refit(&leaves.leaves);
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(5);
    for k in 0..300 {
        let t = Vec3::new(rng.random(), rng.random(), rng.random());
        let p = Point3::from(
            Vec3::new(-30.0, -60.0, -60.0) + t.component_mul(&Vec3::new(70.0, 120.0, 120.0)),
        );
        let all = (leaves.leaves.iter())
            .map(|l| p.leaf_bound(l))
            .fold(f64::INFINITY, f64::min);
        let (offset, ratio) = (f64::from(k % 5), 0.9);
        let got = tree.nearest_within(&leaves.leaves, p, (offset, ratio));
        let kept = if all > offset {
            offset + ratio * (all - offset)
        } else {
            all
        };
        assert!(
            got <= all && got >= kept - 1e-12,
            "{got} for {all} at {p:?}"
        );
    }
}
