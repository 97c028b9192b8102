use super::{CubicSegment, SKIP_MARGIN};

/// Largest curvature over a segment, 1/mm, as before: the largest of
/// the samples, refined by golden-section search around it unless the
/// whole-segment bound stays below `enough`.
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
pub(super) fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, iters: usize) -> f64 {
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
