//! The direct-move clearance check (which steps on the search trees' box
//! lower bound and projects only when that is not enough) against dense
//! exact distances: a move it calls clear keeps the required distance up
//! to half a sampling step everywhere, and a move it refuses comes closer
//! than the required distance somewhere. Random moves around the blade.
mod common;

use cmm::host::inspect::clearance::{ClearanceOptions, PartClearance};
use cmm::host::modes::FreeSpace;
use cmm::math::{Mat3, Point3, Vec3};
use cmm::program::Pose;
use cmm::workpiece::Workpiece;
use common::*;

/// Spacing of the dense exact samples along the move, mm.
const ALONG_MM: f64 = 0.1;
/// Spacing of the dense exact samples along the stylus, mm.
const UP_MM: f64 = 0.5;

/// Smallest exact distance from the ball or stylus to the part along the
/// move, sampled every [`ALONG_MM`] along it and [`UP_MM`] along the
/// stylus.
fn dense_min(wp: &Workpiece, stylus: Vec3, a: Point3, b: Point3) -> f64 {
    let count = |len: f64, step: f64| (len / step).ceil().max(1.0) as usize;
    let (n, m) = (count((b - a).norm(), ALONG_MM), count(stylus.norm(), UP_MM));
    let mut least = f64::INFINITY;
    for j in 0..=m {
        let lift = stylus * (j as f64 / m as f64);
        for k in 0..=n {
            let p = a + (b - a) * (k as f64 / n as f64) + lift;
            least = least.min(wp.closest_point(p).unwrap().projection.distance);
        }
    }
    least
}

#[test]
fn clear_moves_keep_the_margin_and_refused_ones_do_not() {
    let wp = example("blade");
    let opts = ClearanceOptions::default();
    let c = PartClearance {
        workpiece: &wp,
        pose: Pose {
            rotation: Mat3::identity(),
            translation: Vec3::zeros(),
        },
        stylus: Vec3::new(0.0, 0.0, 10.0),
        tip_radius_mm: 1.5,
        shaft_radius_mm: 1.0,
        body: None,
        opts,
    };
    let need = c.tip_radius_mm + opts.margin_mm;
    let mut r = rng(31);
    let (mut clear, mut refused) = (0, 0);
    for k in 0..24 {
        let around = |r: &mut TestRng| {
            Point3::new(
                uniform(r, -30.0, 90.0),
                uniform(r, -40.0, 60.0),
                uniform(r, -20.0, 120.0),
            )
        };
        let (a, b) = (around(&mut r), around(&mut r));
        let least = dense_min(&wp, c.stylus, a, b);
        if c.segment_clear(a, b) {
            clear += 1;
            assert!(
                least >= need - 0.5 * opts.step_mm,
                "move {k} called clear comes within {least} mm"
            );
        } else {
            refused += 1;
            // The refusing sample is within half the dense spacings of one
            // of the dense ones.
            assert!(
                least < need + 0.5 * (ALONG_MM + UP_MM),
                "move {k} refused but keeps {least} mm"
            );
        }
    }
    assert!(clear > 3 && refused > 3, "{clear} clear, {refused} refused");
}
