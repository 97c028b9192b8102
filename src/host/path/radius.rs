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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;
    use rand::{RngExt, SeedableRng};

    /// Random short cubics like the path's (chord ~0.5 mm, radii from
    /// ~0.5 mm up): the bound is above the refined largest curvature, and
    /// whenever the refinement is skipped the refined value would have
    /// stayed below `enough` too, so the speed limit cannot change.
    #[test]
    fn skipped_refinement_could_not_have_limited_the_speed() {
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
        let mut v = |s: f64| {
            Vec3::new(rng.random(), rng.random(), rng.random()) * s - Vec3::repeat(s / 2.0)
        };
        let enough = 1000.0 / (80.0 * 80.0);
        let mut skipped = 0;
        for k in 0..2000 {
            let scale = [0.02, 0.2, 2.0][k % 3];
            let seg = CubicSegment::from_moments(
                Point3::origin(),
                Vec3::new(1.0, 0.0, 0.0),
                0.5,
                v(scale),
                v(scale),
                4,
            );
            let refined = max_curvature(&seg, 8, 40, 0.0);
            assert!(curvature_bound(&seg, 8) >= refined, "case {k}");
            let got = max_curvature(&seg, 8, 40, enough);
            if curvature_bound(&seg, 8) <= enough * (1.0 - SKIP_MARGIN) {
                skipped += 1;
                assert!(got <= refined && refined < enough, "case {k}: {refined}");
            } else {
                assert_eq!(got, refined, "case {k}");
            }
        }
        assert!(skipped > 100, "{skipped} skipped");
    }
}
