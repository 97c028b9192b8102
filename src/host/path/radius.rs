//! Effective radius of a path segment (active-scanning speed planning): the smaller of the
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

use super::pcc::{CubicSegment, CurvatureParts};
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
/// where the curvature can limit the speed, that is above `enough` (the
/// curvature up to which the segment's speed does not depend on it):
///
/// 1. when an upper bound over the whole segment from its middle
///    ([`middle_bound`]) stays below `enough`, the curvature at the middle
///    is returned (no sample can reach `enough`, nor could the refinement);
/// 2. when the tighter bound from the samples ([`Samples`]) stays below
///    `enough`, the largest sample is returned;
/// 3. when the curvature provably rises or falls throughout each sample
///    interval of the bracket ([`Slope::keeps_sign`]), its largest value on
///    the bracket is at a sample: the largest sample is returned, which the
///    refinement would only have approached;
/// 4. otherwise the refinement runs.
pub(crate) fn max_curvature(
    seg: &CubicSegment,
    samples: usize,
    refine_iters: usize,
    enough: f64,
) -> f64 {
    let below = enough * (1.0 - SKIP_MARGIN);
    let (middle_k, bound) = middle_bound(seg);
    if bound <= below {
        return middle_k;
    }
    let n = samples.max(1);
    let found = Samples::take(seg, n);
    if found.bound <= below {
        return found.best_k;
    }
    // The bracket: the sample intervals next to the largest sample.
    let (lo, hi) = (found.best_j.saturating_sub(1), (found.best_j + 1).min(n));
    let slope = Slope::new(seg);
    let monotone =
        (lo..hi).all(|j| slope.keeps_sign(sample_at(seg, j, n), sample_at(seg, j + 1, n)));
    if monotone {
        return found.best_k;
    }
    let (lo, hi) = (sample_at(seg, lo, n), sample_at(seg, hi, n));
    // The bracket's ends are samples: `best_k` already holds them.
    found
        .best_k
        .max(golden_max(|u| seg.curvature(u), lo, hi, refine_iters))
}

/// Parameter of sample `j` of `n + 1` evenly spaced over a segment.
fn sample_at(seg: &CubicSegment, j: usize, n: usize) -> f64 {
    seg.param_len() * j as f64 / n as f64
}

/// The curvature at the middle `m` of a segment and an upper bound of the
/// curvature over the whole segment from there, 1/mm. With `r = h / 2`:
/// `C = P' x P''` is the quadratic `C(m) + C'(m) s + C'' s^2 / 2`, so
/// `|C| <= |C(m)| + |C'(m)| r + |C''| r^2 / 2`; `|P'|^2` is the quartic
/// `sum_i b_i s^i` around `m`, at least `b_0` less the absolute values of
/// its odd and negative terms at `|s| = r`. The bound is
/// `max|C| / min|P'|^3`, infinite when `min|P'|^2` is not positive or a
/// value is not finite.
fn middle_bound(seg: &CubicSegment) -> (f64, f64) {
    let r = 0.5 * seg.param_len();
    let m = seg.curvature_parts(r);
    let [_, _, _, c3] = *seg.coefficients();
    let (d1, d2, d3) = (seg.d1(r), seg.d2(r), c3 * 6.0);
    let cross = m.cross + d1.cross(&d3).norm() * r + 0.5 * seg.cross_d2() * r * r;
    // |P'(m + s)|^2 = |d1 + d2 s + d3 s^2 / 2|^2 = sum_i b_i s^i, whose
    // quartic coefficient is not negative.
    let b1 = 2.0 * d1.dot(&d2);
    let b2 = d2.norm_squared() + d1.dot(&d3);
    let b3 = d2.dot(&d3);
    let speed2 = m.speed * m.speed - b1.abs() * r + b2.min(0.0) * r * r - b3.abs() * r * r * r;
    let bound = if speed2 > 0.0 && cross.is_finite() {
        cross / (speed2 * speed2.sqrt())
    } else {
        f64::INFINITY
    };
    (m.curvature(), bound)
}

/// The curvature at `n + 1` evenly spaced parameters of a segment, and an
/// upper bound of the curvature over the whole segment from the same
/// evaluations (see [`interval_bound`]).
struct Samples {
    /// Index of the largest sample (the first of equal ones).
    best_j: usize,
    /// Largest sample, 1/mm (negative infinity if every sample is NaN).
    best_k: f64,
    /// Upper bound of the curvature over the segment, 1/mm (infinite when
    /// none can be given).
    bound: f64,
}

impl Samples {
    /// Evaluates the curvature at the `n + 1` samples (`n >= 1`).
    fn take(seg: &CubicSegment, n: usize) -> Samples {
        let half = 0.5 * seg.param_len() / n as f64;
        let cross_d2 = seg.cross_d2();
        let mut found = Samples {
            best_j: 0,
            best_k: f64::NEG_INFINITY,
            bound: f64::NEG_INFINITY,
        };
        // The sum of every part, finite only when all of them are.
        let mut total = cross_d2;
        let mut prev: Option<CurvatureParts> = None;
        for j in 0..=n {
            let parts = seg.curvature_parts(sample_at(seg, j, n));
            let k = parts.curvature();
            if k > found.best_k {
                (found.best_j, found.best_k) = (j, k);
            }
            total += parts.speed + parts.cross + parts.d2;
            if let Some(a) = prev {
                let b = interval_bound(&a, &parts, half, cross_d2);
                found.bound = found.bound.max(b);
            }
            prev = Some(parts);
        }
        if !total.is_finite() {
            found.bound = f64::INFINITY;
        }
        found
    }
}

/// Upper bound of the curvature `|C| / |P'|^3` (`C = P' x P''`) between
/// two samples `a`, `b` that are `2 half` apart, 1/mm. `C` is quadratic in
/// `u` with the constant second derivative of norm `cross_d2`, so `|C|`
/// exceeds the larger of its end values by at most `cross_d2 half^2 / 2`
/// (the interpolation error of a quadratic); `|P'|` changes by at most
/// `max|P''|` per unit of `u` (`P''` is linear, so `max|P''|` is at an
/// end), so it is at least its smaller end value less `max|P''| half`.
/// Infinite when that lower bound is not positive (the caller checks that
/// the parts are finite).
fn interval_bound(a: &CurvatureParts, b: &CurvatureParts, half: f64, cross_d2: f64) -> f64 {
    let cross = a.cross.max(b.cross) + 0.5 * cross_d2 * half * half;
    let speed = a.speed.min(b.speed) - a.d2.max(b.d2) * half;
    if speed > 0.0 {
        cross / (speed * speed * speed)
    } else {
        f64::INFINITY
    }
}

/// Relative margin by which the Bernstein coefficients of [`Slope`] must
/// clear the bound of their rounding before their sign is trusted. The
/// bound is the same computation on magnitudes (norms instead of cross and
/// dot products); each coefficient is within about 40 roundings of 1.1e-16
/// (4.4e-15) of it, far below this margin.
const SLOPE_MARGIN: f64 = 1e-12;

/// Degree of the slope polynomial [`Slope`].
const SLOPE_DEGREE: usize = 7;

/// The sign of the curvature's slope along a segment: with `A = |C|^2`
/// (`C = P' x P''`) and `B = |P'|^2`, both quartic in `u`,
/// `d(k^2)/du = (A' B - 3 A B') / B^4`, so the curvature rises where the
/// degree-7 polynomial `g = A' B - 3 A B'` is positive and falls where it
/// is negative (and `g != 0` implies `B > 0`: where `B` vanishes, so does
/// `B'`).
struct Slope {
    /// Coefficients of `g` in powers of `u`, lowest first.
    g: [f64; SLOPE_DEGREE + 1],
    /// The same polynomial computed from magnitudes: every coefficient is
    /// at least the sum of the absolute values of the terms of `g`'s.
    mag: [f64; SLOPE_DEGREE + 1],
}

impl Slope {
    /// The slope polynomial of `seg`.
    fn new(seg: &CubicSegment) -> Slope {
        let [_, c1, c2, c3] = *seg.coefficients();
        // P' = p0 + p1 u + p2 u^2 and C = q0 + q1 u + q2 u^2.
        let p = [c1, c2 * 2.0, c3 * 3.0];
        let q = [
            c1.cross(&c2) * 2.0,
            c1.cross(&c3) * 6.0,
            c2.cross(&c3) * 6.0,
        ];
        let (pn, qn) = (p.map(|v| v.norm()), q.map(|v| v.norm()));
        let dot = |x: &[Vec3; 3], y: &[Vec3; 3]| square(|i, j| x[i].dot(&y[j]));
        let (a, b) = (dot(&q, &q), dot(&p, &p));
        let (am, bm) = (square(|i, j| qn[i] * qn[j]), square(|i, j| pn[i] * pn[j]));
        Slope {
            g: slope(&a, &b, -3.0),
            mag: slope(&am, &bm, 3.0),
        }
    }

    /// Whether the curvature provably rises, or provably falls, throughout
    /// `[lo, hi]` (`0 <= lo < hi`): all Bernstein coefficients of `g` on
    /// the interval have one sign and clear their rounding bound by
    /// [`SLOPE_MARGIN`].
    fn keeps_sign(&self, lo: f64, hi: f64) -> bool {
        if !(lo >= 0.0 && hi > lo) {
            return false;
        }
        let g = bernstein(&self.g, lo, hi);
        let mag = bernstein(&self.mag, lo, hi);
        let clear = |s: f64| g.iter().zip(&mag).all(|(c, m)| s * c > SLOPE_MARGIN * m);
        clear(1.0) || clear(-1.0)
    }
}

/// Coefficients of `x(u) . y(u)` for quadratics `x`, `y` given by
/// `term(i, j) = x_i . y_j`: a quartic, lowest power first.
fn square(term: impl Fn(usize, usize) -> f64) -> [f64; 5] {
    let mut out = [0.0; 5];
    for i in 0..3 {
        for j in 0..3 {
            out[i + j] += term(i, j);
        }
    }
    out
}

/// Coefficients of `A' B + w A B'` for quartics `A`, `B`: the term
/// `a_i b_j u^(i + j)` contributes `(i + w j) a_i b_j u^(i + j - 1)`.
fn slope(a: &[f64; 5], b: &[f64; 5], w: f64) -> [f64; SLOPE_DEGREE + 1] {
    let mut out = [0.0; SLOPE_DEGREE + 1];
    for (i, ai) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate() {
            if i + j > 0 {
                out[i + j - 1] += (i as f64 + w * j as f64) * ai * bj;
            }
        }
    }
    out
}

/// Bernstein coefficients on `[lo, hi]` of the polynomial with power
/// coefficients `c` (lowest first): shifted to `lo`, scaled to the
/// interval's width, then converted. With `lo >= 0` and nonnegative `c`
/// every step adds nonnegative terms only.
fn bernstein(c: &[f64; SLOPE_DEGREE + 1], lo: f64, hi: f64) -> [f64; SLOPE_DEGREE + 1] {
    let n = SLOPE_DEGREE;
    let mut t = *c;
    // Taylor shift: coefficients of c(lo + s) in powers of s.
    for k in 0..n {
        for i in (k..n).rev() {
            t[i] += lo * t[i + 1];
        }
    }
    let w = hi - lo;
    let mut scale = 1.0;
    for x in t.iter_mut() {
        *x *= scale;
        scale *= w;
    }
    let mut out = [0.0; SLOPE_DEGREE + 1];
    for (o, weights) in out.iter_mut().zip(&BERNSTEIN) {
        *o = weights.iter().zip(&t).map(|(w, x)| w * x).sum();
    }
    out
}

/// Weights turning power coefficients on `[0, 1]` into Bernstein ones of
/// degree `n =` [`SLOPE_DEGREE`]: `b_k = sum_{i <= k} (C(k, i) / C(n, i)) t_i`
/// (row `k`; zero for `i > k`, positive otherwise).
const BERNSTEIN: [[f64; SLOPE_DEGREE + 1]; SLOPE_DEGREE + 1] = {
    let mut w = [[0.0; SLOPE_DEGREE + 1]; SLOPE_DEGREE + 1];
    let mut k = 0;
    while k <= SLOPE_DEGREE {
        let mut i = 0;
        while i <= k {
            w[k][i] = binomial(k, i) / binomial(SLOPE_DEGREE, i);
            i += 1;
        }
        k += 1;
    }
    w
};

/// The binomial coefficient `C(n, k)` as a float (exact for small `n`).
const fn binomial(n: usize, k: usize) -> f64 {
    let mut acc = 1.0;
    let mut i = 0;
    while i < k {
        acc = acc * (n - i) as f64 / (i + 1) as f64;
        i += 1;
    }
    acc
}

/// Golden-section search for the maximum of `f` on `[lo, hi]`: the largest
/// value of `f` at the interior points it visits (not at `lo` and `hi`).
/// Each step places two points; the point kept from the step before is not
/// evaluated again when it falls on exactly the same parameter.
fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, iters: usize) -> f64 {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let mut best = f64::NEG_INFINITY;
    let mut kept: Option<(f64, f64)> = None;
    let eval = |x: f64, kept: Option<(f64, f64)>| match kept {
        Some((u, fu)) if u.to_bits() == x.to_bits() => fu,
        _ => f(x),
    };
    for _ in 0..iters {
        let x1 = hi - INV_PHI * (hi - lo);
        let x2 = lo + INV_PHI * (hi - lo);
        let (f1, f2) = (eval(x1, kept), eval(x2, kept));
        best = best.max(f1).max(f2);
        if f1 > f2 {
            hi = x2;
            kept = Some((x1, f1));
        } else {
            lo = x1;
            kept = Some((x2, f2));
        }
    }
    best
}

/// The curvature maximisation before it was sped up (commit e4de353),
/// verbatim: the reference the tests compare [`max_curvature`] with.
#[cfg(test)]
pub(super) mod reference;

#[cfg(test)]
mod tests;
