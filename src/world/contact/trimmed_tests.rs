//! The trimmed boxes of the leaves the trim crosses hold the true surface
//! over the part of the leaf inside the trim, and only about that: on a
//! real part (the flange, a plate with seven holes among its faces) moved,
//! turned, stretched and bumped, every true point of a crossed leaf inside
//! its face's trim has a trimmed bound of zero, and true points of the
//! untrimmed surface over the holes are bounded away by millimetres.
use super::index::PartIndex;
use super::leaves::Leaf;
use super::refit_tests::{flange, machined};
use super::shapes::Segment;
use super::ContactOptions;
use crate::geometry::Jet2;
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;

#[test]
fn trimmed_boxes_hold_the_trimmed_true_surface_and_leave_out_the_holes() {
    let wp = flange();
    let am = machined(&wp);
    let ix = PartIndex::new(&wp, &am, &ContactOptions::default().leaves);
    let n = 24;
    let (mut inside, mut crossed, mut far_over_holes) = (0, 0, 0);
    for (id, leaf) in ix.all_leaves((&wp, &am)) {
        if !leaf.crossed() {
            assert_eq!(
                ix.trimmed_bound(id, (&wp, &am), point(Vec3::zeros()), 0.0),
                None
            );
            continue;
        }
        crossed += 1;
        let face = &wp.faces[leaf.face];
        for (uv, q) in true_grid((&wp, &am), leaf, n) {
            let q = q.coords;
            let b = ix.trimmed_bound(id, (&wp, &am), point(q), 0.0).unwrap();
            if face.contains(uv) {
                inside += 1;
                assert!(
                    b <= 1e-9,
                    "leaf {id} at {uv}: true point {q} {b} mm outside"
                );
            } else if b > 0.5 {
                far_over_holes += 1;
            }
        }
    }
    assert!(
        crossed > 100 && inside > 10_000,
        "{crossed} leaves, {inside} points"
    );
    assert!(
        far_over_holes > 1000,
        "{far_over_holes} points over holes bounded away"
    );
}

/// The true points over an `(n + 1) x (n + 1)` grid of `leaf`'s parameter
/// rectangle, with their nominal parameters.
fn true_grid<'a>(
    (wp, am): (&'a Workpiece, &'a AsMachined),
    leaf: &'a Leaf,
    n: usize,
) -> impl Iterator<Item = (Vec2, Point3)> + 'a {
    let (lo, hi) = (leaf.bounds.lo, leaf.bounds.hi);
    (0..=n).flat_map(move |i| {
        (0..=n).map(move |j| {
            let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
            let uv = Vec2::new(lo.x + (hi.x - lo.x) * s, lo.y + (hi.y - lo.y) * t);
            let mut jet = Jet2 {
                d: [Vec3::zeros(); 6],
            };
            am.true_jet_into(wp, leaf.face, uv, &mut jet);
            (uv, jet.point())
        })
    })
}

/// The segment of no length at `p`.
fn point(p: Vec3) -> Segment {
    Segment {
        a: p.into(),
        b: p.into(),
    }
}

/// The oriented box of a leaf bounds the true surface over it: for
/// segments beside every leaf of the machined flange (moved, turned,
/// stretched, bumped), the tight bound is never above the distance to a
/// dense sampling of the true surface over the leaf, and it beats the
/// axis-aligned box and slab bound on many leaves tilted across the axes.
#[test]
fn oriented_boxes_bound_the_true_surface_and_tighten_tilted_leaves() {
    let wp = flange();
    let am = machined(&wp);
    let ix = PartIndex::new(&wp, &am, &ContactOptions::default().leaves);
    let n = 16;
    let (mut checked, mut tighter) = (0, 0);
    for (_, leaf) in ix.all_leaves((&wp, &am)).into_iter().step_by(7) {
        let true_points: Vec<_> = true_grid((&wp, &am), leaf, n).map(|(_, q)| q).collect();
        let centre = leaf.aabb.min + (leaf.aabb.max - leaf.aabb.min) * 0.5;
        let size = (leaf.aabb.max - leaf.aabb.min).norm();
        // Segments 20 mm long beside the leaf, along each axis and askew.
        for (k, dir) in [
            Vec3::x(),
            Vec3::y(),
            Vec3::z(),
            Vec3::new(1.0, 2.0, -1.5).normalize(),
        ]
        .into_iter()
        .enumerate()
        {
            let off = Vec3::new(0.6, -0.8, 0.3 + 0.2 * k as f64).normalize() * (0.3 * size + 0.5);
            let (a, b) = (centre + off - dir * 10.0, centre + off + dir * 10.0);
            let sampled = true_points
                .iter()
                .map(|p| distance_to_segment(*p, a, b))
                .fold(f64::INFINITY, f64::min);
            let cheap = leaf.segment_lower_bound(a, b);
            let tight = leaf.tight_segment_bound(a, b, cheap);
            assert!(
                tight <= sampled + 1e-9,
                "leaf of face {}: bound {tight} above the sampled distance {sampled}",
                leaf.face
            );
            checked += 1;
            if tight > cheap + 0.1 {
                tighter += 1;
            }
        }
    }
    assert!(
        checked > 1000 && tighter > 50,
        "{checked} segments, {tighter} tighter"
    );
}

/// Distance from `p` to the segment `a..b`.
fn distance_to_segment(
    p: crate::math::Point3,
    a: crate::math::Point3,
    b: crate::math::Point3,
) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (a + d * t)).norm()
}
