//! A certificate that no point of a leaf comes closer to a point `p` than
//! a local minimum `f` of the distance found on it (by a warm start), at
//! distance `d`: then the leaf needs no Newton iteration of its own.
//!
//! Take the leaf's own parameters on `[0, 1]^2`, scaled by the (root mean square)
//! lengths of the first derivatives (an affine change of the surface's
//! parameters: local minima stay local minima, convex functions convex).
//! A polynomial Bezier leaf's first derivatives `a = S_u`, `b = S_v` lie in
//! the convex hulls of its scaled control point differences, its second
//! ones in those of the second differences. From their extreme points:
//! `|P J w| >= sigma` for unit `w`, where `P` projects on the plane of the
//! leaf's oriented box (`sigma` from the spread of `P a` and `P b` about
//! their means, or from their least 2-D cross product over the largest
//! Frobenius norm: the cross product is bilinear, so least at extreme
//! points, the better of both), `|J w| <= m`, and
//! `|D^2 S [w, w]| <= kappa`. Then `|S(x) - S(y)| >= sigma |x - y|`
//! (integrate `P J` along the segment: its mean lies in the same hulls),
//! so a point `x` of the leaf at most `d` from `p`, within `2 d` of `f`,
//! has `|x - x_f| <= 2 d / sigma`. On that disc (cut to the leaf, a convex
//! set) `|S - p| <= d + 2 d m / sigma`, and the Hessian of `|S - p|^2 / 2`,
//! `J^T J + (S - p) . D^2 S >= sigma^2 - d (1 + 2 m / sigma) kappa`. When
//! that is positive the squared distance is strictly convex there, so `f`,
//! a local minimum, is its least value on the disc, and no point of the
//! leaf outside it comes within `d`.
//!
//! A rational leaf `S = c + R / W` (`R` the homogeneous control points
//! about the box centre `c`, `W` the weight polynomial, both Bezier) has
//! `J = (R' - (S - c) W') / W`. Along a segment the mean of `R' / W` is
//! `C A` with `C`, the mean of `1 / W`, in `[1 / Wmax, 1 / Wmin]` (the
//! extreme weights) and `A` a weighted mean of `R'`, so in the hulls of
//! its coefficients' differences; the rest moves `J w` by at most
//! `h g / Wmin`, `h` the box's half diagonal (`|S - c| <= h`) and `g` a
//! bound of `|W' w|` from the weights' differences. So `sigma` and `m` are
//! those of `R` over `Wmax` and `Wmin`, less and plus that drift. From
//! `W (S - c) = R` twice differentiated,
//! `D^2 S [w, w] = (D^2 R [w, w] - D^2 W [w, w] (S - c) - 2 (W' w)(J w)) / W`,
//! bounded with the hulls of the second differences, `h`, `g` and `m`.
use super::Obb;
use crate::geometry::nurbs::bezier::BezierPatch;
use crate::math::{Vec2, Vec3};

/// Relative margin of the certificate's inequality against rounding.
const MARGIN: f64 = 1e-9;

/// The constants of one leaf's certificate.
#[derive(Debug, Clone, Copy)]
pub(super) struct Convexity {
    /// `sigma` (zero: no certificate).
    sigma: f64,
    /// `m`.
    m: f64,
    /// `kappa`.
    kappa: f64,
}

impl Convexity {
    /// No certificate.
    const NONE: Convexity = Convexity {
        sigma: 0.0,
        m: f64::INFINITY,
        kappa: f64::INFINITY,
    };

    /// The certificate's constants for the leaf `patch` with the oriented
    /// box `obb`.
    pub(super) fn of(patch: &BezierPatch, obb: &Obb) -> Convexity {
        let [p, q] = patch.degree;
        let w0 = patch.pw.first().map_or(f64::NAN, |c| c.w);
        if p == 0 || q == 0 || patch.pw.len() != (p + 1) * (q + 1) {
            return Convexity::NONE;
        }
        if patch.pw.iter().any(|c| c.w != w0) {
            return Convexity::rational(patch, obb);
        }
        let pts: Vec<Vec3> = patch.pw.iter().map(|c| c.xyz() / c.w).collect();
        let at = |i: usize, j: usize| pts.get(i * (q + 1) + j).copied().unwrap_or_default();
        let (pf, qf) = (p as f64, q as f64);
        let mut su = Vec::with_capacity(p * (q + 1));
        let mut sv = Vec::with_capacity((p + 1) * q);
        for i in 0..=p {
            for j in 0..=q {
                if i < p {
                    su.push((at(i + 1, j) - at(i, j)) * pf);
                }
                if j < q {
                    sv.push((at(i, j + 1) - at(i, j)) * qf);
                }
            }
        }
        let (ku, kv) = (1.0 / rms_length(&su), 1.0 / rms_length(&sv));
        if !(ku.is_finite() && kv.is_finite()) {
            return Convexity::NONE;
        }
        su.iter_mut().for_each(|x| *x *= ku);
        sv.iter_mut().for_each(|x| *x *= kv);
        // Largest squared lengths of the second differences.
        let (mut kuu, mut kuv, mut kvv) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..=p {
            for j in 0..=q {
                if i + 1 < p {
                    kuu = kuu.max((at(i + 2, j) - at(i + 1, j) * 2.0 + at(i, j)).norm_squared());
                }
                if j + 1 < q {
                    kvv = kvv.max((at(i, j + 2) - at(i, j + 1) * 2.0 + at(i, j)).norm_squared());
                }
                if i < p && j < q {
                    let twist = at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j);
                    kuv = kuv.max(twist.norm_squared());
                }
            }
        }
        let kuu = kuu.sqrt() * pf * (pf - 1.0) * ku * ku;
        let kvv = kvv.sqrt() * qf * (qf - 1.0) * kv * kv;
        let kuv = kuv.sqrt() * pf * qf * ku * kv;
        let (spread_sigma, spread_m) = spread_bounds(&su, &sv, &obb.axes);
        let frobenius = (longest2(&su) + longest2(&sv)).sqrt();
        let m = spread_m.min(frobenius);
        let sigma = spread_sigma.max(cross_sigma(&su, &sv, &obb.axes));
        if !(sigma > 0.0 && m.is_finite()) {
            return Convexity::NONE;
        }
        Convexity {
            sigma,
            m,
            kappa: largest_eigenvalue(kuu, kuv, kvv),
        }
    }

    /// [`Self::of`] for a rational leaf (see the module's notes).
    fn rational(patch: &BezierPatch, obb: &Obb) -> Convexity {
        let [p, q] = patch.degree;
        let c = obb.center.coords;
        let r: Vec<Vec3> = (patch.pw.iter())
            .map(|h| Vec3::new(h.x, h.y, h.z) - c * h.w)
            .collect();
        let w: Vec<f64> = patch.pw.iter().map(|h| h.w).collect();
        let w_min = w.iter().copied().fold(f64::INFINITY, f64::min);
        let w_max = w.iter().copied().fold(0.0, f64::max);
        if !(w_min > 0.0 && w_max.is_finite()) {
            return Convexity::NONE;
        }
        let (mut su, mut sv) = first_differences(&r, [p, q]);
        let (ku, kv) = (1.0 / rms_length(&su), 1.0 / rms_length(&sv));
        if !(ku.is_finite() && kv.is_finite()) {
            return Convexity::NONE;
        }
        su.iter_mut().for_each(|x| *x *= ku);
        sv.iter_mut().for_each(|x| *x *= kv);
        let (spread_sigma, spread_m) = spread_bounds(&su, &sv, &obb.axes);
        let frobenius = (longest2(&su) + longest2(&sv)).sqrt();
        let sigma_r = spread_sigma.max(cross_sigma(&su, &sv, &obb.axes));
        let m_r = spread_m.min(frobenius);
        let dw = Differences::of(&w, [p, q], |x: &f64| x.abs());
        let dr = Differences::of(&r, [p, q], |x: &Vec3| x.norm());
        let g = (dw.first[0] * ku).hypot(dw.first[1] * kv);
        let half = Vec3::new(obb.half[0], obb.half[1], obb.half[2]).norm();
        let drift = half * g / w_min;
        let sigma = sigma_r / w_max - drift;
        let m = m_r / w_min + drift;
        let kappa =
            (dr.second_bound(ku, kv) + dw.second_bound(ku, kv) * half + 2.0 * g * m) / w_min;
        if !(sigma > 0.0 && m.is_finite() && kappa.is_finite()) {
            return Convexity::NONE;
        }
        Convexity { sigma, m, kappa }
    }

    /// Whether no point of the leaf comes closer to a point than `d`, the
    /// distance of a local minimum of the distance found on the leaf.
    pub(super) fn excludes_closer(&self, d: f64) -> bool {
        let s = self.sigma;
        s > 0.0 && s * s > d * (1.0 + 2.0 * self.m / s) * self.kappa * (1.0 + MARGIN)
    }
}

/// Bounds of the derivatives of a Bezier polynomial on its unit square,
/// from the hulls of its coefficients' differences: `first` of `|f_u|`
/// and `|f_v|`, `second` of `|f_uu|`, `|f_uv|`, `|f_vv|`.
struct Differences {
    first: [f64; 2],
    second: [f64; 3],
}

impl Differences {
    /// The bounds for the coefficients `f` (row-major, degrees `[p, q]`)
    /// with the norm `norm`.
    fn of<T>(f: &[T], [p, q]: [usize; 2], norm: impl Fn(&T) -> f64) -> Differences
    where
        T: Copy + std::ops::Sub<Output = T> + std::ops::Add<Output = T>,
    {
        let at = |i: usize, j: usize| coefficient(f, [p, q], i, j);
        let mut d = Differences {
            first: [0.0; 2],
            second: [0.0; 3],
        };
        let keep = |slot: &mut f64, x: Option<T>| {
            if let Some(x) = x {
                *slot = slot.max(norm(&x));
            }
        };
        for i in 0..=p {
            for j in 0..=q {
                let (a, b, c) = (at(i, j), at(i + 1, j), at(i, j + 1));
                let sub = |x: Option<T>, y: Option<T>| Some(x? - y?);
                keep(&mut d.first[0], sub(b, a));
                keep(&mut d.first[1], sub(c, a));
                // f_{i+2,j} - 2 f_{i+1,j} + f_{i,j}, and so on.
                let second = |x: Option<T>, y: Option<T>, z: Option<T>| Some(x? + z? - y? - y?);
                keep(&mut d.second[0], second(at(i + 2, j), b, a));
                keep(&mut d.second[2], second(at(i, j + 2), c, a));
                keep(&mut d.second[1], sub(sub(at(i + 1, j + 1), b), sub(c, a)));
            }
        }
        let (pf, qf) = (p as f64, q as f64);
        d.first = [d.first[0] * pf, d.first[1] * qf];
        d.second = [
            d.second[0] * pf * (pf - 1.0),
            d.second[1] * pf * qf,
            d.second[2] * qf * (qf - 1.0),
        ];
        d
    }

    /// A bound of `|f'' [w, w]|` for unit `w` in the parameters scaled by
    /// `ku` and `kv`.
    fn second_bound(&self, ku: f64, kv: f64) -> f64 {
        let [uu, uv, vv] = self.second;
        largest_eigenvalue(uu * ku * ku, uv * ku * kv, vv * kv * kv)
    }
}

/// The coefficients of the first derivatives of the Bezier polynomial
/// with the coefficients `f` (row-major, degrees `[p, q]`): along u, and
/// along v.
fn first_differences(f: &[Vec3], [p, q]: [usize; 2]) -> (Vec<Vec3>, Vec<Vec3>) {
    let at = |i: usize, j: usize| coefficient(f, [p, q], i, j);
    let (pf, qf) = (p as f64, q as f64);
    let mut su = Vec::with_capacity(p * (q + 1));
    let mut sv = Vec::with_capacity((p + 1) * q);
    for i in 0..=p {
        for j in 0..=q {
            if let (Some(a), Some(b)) = (at(i, j), at(i + 1, j)) {
                su.push((b - a) * pf);
            }
            if let (Some(a), Some(c)) = (at(i, j), at(i, j + 1)) {
                sv.push((c - a) * qf);
            }
        }
    }
    (su, sv)
}

/// Coefficient `(i, j)` of a Bezier polynomial with the coefficients `f`
/// (row-major, degrees `[p, q]`); `None` outside.
fn coefficient<T: Copy>(f: &[T], [p, q]: [usize; 2], i: usize, j: usize) -> Option<T> {
    (i <= p && j <= q)
        .then(|| f.get(i * (q + 1) + j).copied())
        .flatten()
}

/// The largest squared length of the vectors `d` (zero when there are
/// none).
fn longest2(d: &[Vec3]) -> f64 {
    d.iter().map(|x| x.norm_squared()).fold(0.0, f64::max)
}

/// The root mean square length of the vectors `d` (any positive scale
/// serves; not finite when there are none).
fn rms_length(d: &[Vec3]) -> f64 {
    (d.iter().map(|x| x.norm_squared()).sum::<f64>() / d.len() as f64).sqrt()
}

/// A lower bound of the smallest singular value of `[P a, P b]` over all
/// `a`, `b` in the convex hulls of `su`, `sv`, with `P` the projection on
/// the plane of `axes[0]` and `axes[1]`: the least cross product over the
/// largest Frobenius norm (zero when the cross products may change sign).
/// The cross product `a x b` is linear in each, so its least value over a
/// hull pair is at extreme points; here over the points of one and the
/// bounding box of the other's projections (the better of both ways).
fn cross_sigma(su: &[Vec3], sv: &[Vec3], axes: &[Vec3; 3]) -> f64 {
    let flat = |x: &Vec3| (x.dot(&axes[0]), x.dot(&axes[1]));
    let boxed = |d: &[Vec3]| {
        d.iter().map(flat).fold(
            [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ],
            |b, (x, y)| [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)],
        )
    };
    let (bu, bv) = (boxed(su), boxed(sv));
    // The range of `a.x b.y - a.y b.x` over `b` in the box `bv`, and of
    // the same over `a` in `bu` for a point `b`.
    let over_v = |(ax, ay): (f64, f64)| {
        let (t1, t2) = ((ax * bv[2]).min(ax * bv[3]), (ax * bv[2]).max(ax * bv[3]));
        let (s1, s2) = (
            (-ay * bv[0]).min(-ay * bv[1]),
            (-ay * bv[0]).max(-ay * bv[1]),
        );
        (t1 + s1, t2 + s2)
    };
    let over_u = |(bx, by): (f64, f64)| {
        let (t1, t2) = ((by * bu[0]).min(by * bu[1]), (by * bu[0]).max(by * bu[1]));
        let (s1, s2) = (
            (-bx * bu[2]).min(-bx * bu[3]),
            (-bx * bu[2]).max(-bx * bu[3]),
        );
        (t1 + s1, t2 + s2)
    };
    let range = |r: &mut dyn Iterator<Item = (f64, f64)>| {
        r.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
            (lo.min(a), hi.max(b))
        })
    };
    let least = |(lo, hi): (f64, f64)| {
        if lo > 0.0 {
            lo
        } else if hi < 0.0 {
            -hi
        } else {
            0.0
        }
    };
    let by_u = least(range(&mut su.iter().map(|a| over_v(flat(a)))));
    let by_v = least(range(&mut sv.iter().map(|b| over_u(flat(b)))));
    let frobenius = (longest2(su) + longest2(sv)).sqrt();
    let sigma = by_u.max(by_v) / frobenius;
    if sigma.is_finite() {
        sigma
    } else {
        0.0
    }
}

/// Bounds `(sigma, m)` over all `a`, `b` in the convex hulls of `su` and
/// `sv` and unit `w`: `sigma <= |P (a w_1 + b w_2)|` with `P` the
/// projection on the plane of `axes[0]` and `axes[1]` (the smallest
/// singular value of the projected means less the projected spread, zero
/// when that is not positive), and `m >= |a w_1 + b w_2|` (the largest
/// singular value of the means plus the spread).
fn spread_bounds(su: &[Vec3], sv: &[Vec3], axes: &[Vec3; 3]) -> (f64, f64) {
    let mean = |d: &[Vec3]| d.iter().sum::<Vec3>() / d.len().max(1) as f64;
    let (a, b) = (mean(su), mean(sv));
    let spread =
        |d: &[Vec3], m: Vec3| (d.iter().map(|x| (x - m).norm_squared()).fold(0.0, f64::max)).sqrt();
    let e = spread(su, a).hypot(spread(sv, b));
    let flat = |x: Vec3| Vec2::new(x.dot(&axes[0]), x.dot(&axes[1]));
    let flat_spread = |d: &[Vec3], m: Vec3| {
        let fm = flat(m);
        (d.iter()
            .map(|x| (flat(*x) - fm).norm_squared())
            .fold(0.0, f64::max))
        .sqrt()
    };
    let e_flat = flat_spread(su, a).hypot(flat_spread(sv, b));
    let (fa, fb) = (flat(a), flat(b));
    let sigma = singular_values(fa.dot(&fa), fa.dot(&fb), fb.dot(&fb)).0 - e_flat;
    let m = singular_values(a.dot(&a), a.dot(&b), b.dot(&b)).1 + e;
    if sigma.is_finite() && sigma > 0.0 {
        (sigma, m)
    } else {
        (0.0, m)
    }
}

/// The singular values (smallest, largest) of a matrix with the Gram
/// matrix `[[g11, g12], [g12, g22]]`.
fn singular_values(g11: f64, g12: f64, g22: f64) -> (f64, f64) {
    let half_gap = (0.25 * (g11 - g22).powi(2) + g12 * g12).sqrt();
    let mid = 0.5 * (g11 + g22);
    ((mid - half_gap).max(0.0).sqrt(), (mid + half_gap).sqrt())
}

/// The largest eigenvalue of `[[a, b], [b, c]]`.
fn largest_eigenvalue(a: f64, b: f64, c: f64) -> f64 {
    0.5 * (a + c) + (0.25 * (a - c).powi(2) + b * b).sqrt()
}
