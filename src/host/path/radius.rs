//! Effective radius of a path segment (seed 001): the smaller of the
//! curvature radius over the segment and a radius derived from the angle
//! between this segment's chord and the next segment's chord.
//!
//! Seed 001 gives no formula for the chord-angle radius. We use the radius
//! of the circle through the three points when the two chords are equal:
//! for chords `c1`, `c2` turning by `theta` at their common point,
//! `R = min(|c1|, |c2|) / (2 sin(theta / 2))`. It equals `R` for points
//! sampled on a circle of radius `R`, grows without bound as the chords
//! align, and falls monotonically to `min(|c1|, |c2|) / 2` for a full
//! reversal (unlike the circumradius of unequal chords, which grows again
//! past 90 degrees).

use super::pcc::CubicSegment;
use crate::math::Vec3;

/// Chord-angle radius of two consecutive chords, mm: `min(|a|, |b|) /
/// (2 sin(theta / 2))` with `theta` the angle between `a` and `b`;
/// infinite when `theta <= min_angle_rad` or a chord is zero.
pub fn chord_angle_radius(a: &Vec3, b: &Vec3, min_angle_rad: f64) -> f64 {
    let chord = a.norm().min(b.norm());
    if chord == 0.0 || !chord.is_finite() {
        return f64::INFINITY;
    }
    let theta = a.angle(b);
    if theta <= min_angle_rad {
        return f64::INFINITY;
    }
    chord / (2.0 * (0.5 * theta).sin())
}

/// Relative margin below the curvature `enough` of [`max_curvature`] that
/// an upper bound must keep before the refinement is skipped; it covers
/// the rounding of the bound and of the curvature evaluations (~1e-15), so
/// that the skipped refinement could not have reached `enough`.
const SKIP_MARGIN: f64 = 1e-6;

/// Largest curvature over a segment, 1/mm: the largest of `samples + 1`
/// evenly spaced evaluations, refined by golden-section search on the
/// bracket around it (`refine_iters` steps). The refinement only matters
/// where the curvature can limit the speed: when an upper bound over the
/// whole segment ([`curvature_bound`]) stays below `enough` (the curvature
/// up to which the commanded speed holds), the largest sample is returned
/// as it is (it is below `enough` too, and so is the refined value).
pub(crate) fn max_curvature(
    seg: &CubicSegment,
    samples: usize,
    refine_iters: usize,
    enough: f64,
) -> f64 {
    let n = samples.max(1);
    let h = seg.param_len();
    let at = |j: usize| h * j as f64 / n as f64;
    let (best_j, best_k) =
        (0..=n)
            .map(|j| (j, seg.curvature(at(j))))
            .fold(
                (0, f64::NEG_INFINITY),
                |acc, x| if x.1 > acc.1 { x } else { acc },
            );
    if curvature_bound(seg, n) <= enough * (1.0 - SKIP_MARGIN) {
        return best_k;
    }
    let lo = at(best_j.saturating_sub(1));
    let hi = at((best_j + 1).min(n));
    best_k.max(golden_max(|u| seg.curvature(u), lo, hi, refine_iters))
}

/// Upper bound of the curvature over a whole segment, 1/mm:
/// `|P' x P''| / |P'|^3 <= max|P''| / min|P'|^2`. `P''` is linear in `u`,
/// so `max|P''|` is taken at an end; `|P'|` changes by at most `max|P''|`
/// per unit of `u`, so `min|P'|` is at least its smallest value at `n + 1`
/// evenly spaced parameters less `max|P''|` times half their spacing.
/// Infinite when that lower bound is not positive.
fn curvature_bound(seg: &CubicSegment, n: usize) -> f64 {
    let h = seg.param_len();
    let d2 = seg.d2(0.0).norm().max(seg.d2(h).norm());
    let slowest = (0..=n)
        .map(|j| seg.d1(h * j as f64 / n as f64).norm())
        .fold(f64::INFINITY, f64::min);
    let speed = slowest - d2 * h / (2 * n) as f64;
    if speed > 0.0 && d2.is_finite() {
        d2 / (speed * speed)
    } else {
        f64::INFINITY
    }
}

/// Golden-section search for the maximum of `f` on `[lo, hi]`.
fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, iters: usize) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let mut best = f(lo).max(f(hi));
    for _ in 0..iters {
        let x1 = hi - INV_PHI * (hi - lo);
        let x2 = lo + INV_PHI * (hi - lo);
        let (f1, f2) = (f(x1), f(x2));
        best = best.max(f1).max(f2);
        if f1 > f2 {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    best
}
