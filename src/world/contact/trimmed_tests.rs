//! The trimmed boxes of the leaves the trim crosses hold the true surface
//! over the part of the leaf inside the trim, and only about that: on a
//! real part (the flange, a plate with seven holes among its faces) moved,
//! turned, stretched and bumped, every true point of a crossed leaf inside
//! its face's trim has a trimmed bound of zero, and true points of the
//! untrimmed surface over the holes are bounded away by millimetres.
use super::refit_tests::{flange, machined};
use super::search::PartIndex;
use super::shapes::Segment;
use super::ContactOptions;
use crate::geometry::Jet2;
use crate::math::{Vec2, Vec3};

#[test]
fn trimmed_boxes_hold_the_trimmed_true_surface_and_leave_out_the_holes() {
    let wp = flange();
    let am = machined(&wp);
    let ix = PartIndex::new(&wp, &am, &ContactOptions::default());
    let n = 24;
    let (mut inside, mut crossed, mut far_over_holes) = (0, 0, 0);
    for (id, leaf) in ix.leaves.leaves.iter().enumerate() {
        if !leaf.crossed() {
            assert_eq!(ix.trimmed_bound(id, (&wp, &am), point(Vec3::zeros())), None);
            continue;
        }
        crossed += 1;
        let face = &wp.faces[leaf.face];
        let (lo, hi) = (leaf.bounds.lo, leaf.bounds.hi);
        for i in 0..=n {
            for j in 0..=n {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                let uv = Vec2::new(lo.x + (hi.x - lo.x) * s, lo.y + (hi.y - lo.y) * t);
                let mut jet = Jet2 {
                    d: [Vec3::zeros(); 6],
                };
                am.true_jet_into(&wp, leaf.face, uv, &mut jet);
                let q = jet.point().coords;
                let b = ix.trimmed_bound(id, (&wp, &am), point(q)).unwrap();
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

/// The segment of no length at `p`.
fn point(p: Vec3) -> Segment {
    Segment {
        a: p.into(),
        b: p.into(),
    }
}
