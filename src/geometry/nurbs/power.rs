//! Fast evaluation of low-degree surfaces: every rational Bezier patch is
//! converted once to power-basis coefficients in its local parameters
//! `s, t` in [0, 1], so a point with derivatives costs one span lookup and a
//! few dozen vector multiply-adds instead of the basis-function recursion.
//! Local parameters keep the power basis well conditioned for the degrees
//! it is used for (up to [`FAST_MAX_DEGREE`]).
use super::bezier::{decompose, BezierPatch};
use super::binomial;
use super::jet::Jet2;
use super::surface::NurbsSurface;
use crate::math::{Vec3, Vec4};

/// Highest degree (in either direction) evaluated in the power basis.
/// Real CAD parts carry rational blends of degree 6 to 10 (fillets and
/// variable-radius blends exported as B-splines); the conversion's
/// coefficients grow like `2^p` times a binomial, which each patch's own
/// origin (its first control point) keeps small: the coefficients are
/// those of the patch less its origin, so a part placed 1000 mm from the
/// machine's zero rounds like one at the zero (tests/nurbs.rs checks
/// degrees 5 to 11 against the basis recursion at table coordinates).
pub const FAST_MAX_DEGREE: usize = 11;
const CAP: usize = FAST_MAX_DEGREE + 1;

/// A local patch parameter in [0, 1] with the inverse width of its span.
type LocalParam = (f64, f64);

/// Power-basis coefficients of all patches of a surface.
#[derive(Debug, Clone)]
pub(crate) struct PowerPatches {
    breaks_u: Vec<f64>,
    breaks_v: Vec<f64>,
    /// `1 / (breaks[i + 1] - breaks[i])` per span, u and v (kept: every
    /// evaluation maps its parameter into its span).
    inv_width: [Vec<f64>; 2],
    degree: [usize; 2],
    /// Patch `(a, b)` starts at `(a * nb + b) * stride`; entry `i * (q + 1) + j`
    /// multiplies `s^i t^j`.
    coef: Vec<Vec4>,
    /// Each patch's origin, taken off its coefficients (mm): the
    /// coefficients are those of `S - origin`.
    origin: Vec<Vec3>,
    /// The same coefficients without weights, for non-rational surfaces
    /// (empty for rational ones).
    coef3: Vec<Vec3>,
}

impl PowerPatches {
    /// Converts a surface of degree at most [`FAST_MAX_DEGREE`].
    pub fn new(surface: &NurbsSurface) -> Option<PowerPatches> {
        let degree = [surface.knots_u().degree(), surface.knots_v().degree()];
        if degree[0] > FAST_MAX_DEGREE || degree[1] > FAST_MAX_DEGREE {
            return None;
        }
        let (mu, mv) = (bezier_to_power(degree[0]), bezier_to_power(degree[1]));
        let patches = decompose(surface);
        let origin: Vec<Vec3> = patches.iter().map(patch_origin).collect();
        let coef: Vec<Vec4> = (patches.iter().zip(&origin))
            .flat_map(|(patch, &o)| convert(patch, o, &mu, &mv))
            .collect();
        let coef3 = if surface.is_rational() {
            Vec::new()
        } else {
            coef.iter().map(|c| c.xyz()).collect()
        };
        let (breaks_u, breaks_v) = (
            surface.knots_u().breakpoints(),
            surface.knots_v().breakpoints(),
        );
        let inv = |b: &[f64]| b.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect();
        Some(PowerPatches {
            inv_width: [inv(&breaks_u), inv(&breaks_v)],
            breaks_u,
            breaks_v,
            degree,
            coef,
            origin,
            coef3,
        })
    }

    /// Euclidean derivatives of a non-rational surface into `out`
    /// (`d[k][l]` for `k + l <= nd` at a clamped parameter); `false` for
    /// rational surfaces, which need the homogeneous path.
    #[inline]
    pub fn derivs_polynomial(&self, u: f64, v: f64, nd: usize, out: &mut [[Vec3; 4]; 4]) -> bool {
        self.polynomial_into(u, v, nd, out)
    }

    /// [`Self::derivs_polynomial`] to second order straight into a jet.
    #[inline]
    pub fn jet2_polynomial(&self, u: f64, v: f64, out: &mut Jet2) -> bool {
        self.polynomial_into(u, v, 2, out)
    }

    /// The second-order jet of a rational surface whose patches have a
    /// dedicated kernel (each of degrees 1 to 3 by 1 to 3),
    /// by Horner's rule on the homogeneous coefficients and the
    /// quotient rule; `false` when it does not apply (the general
    /// homogeneous path serves then).
    #[inline]
    pub fn jet2_rational(&self, u: f64, v: f64, out: &mut Jet2) -> bool {
        let [p, q] = self.degree;
        let Some((patch, su, tv, o)) = self.patch_at(&self.coef, u, v) else {
            return false;
        };
        let mut hom = HomogeneousJet2([Vec4::zeros(); 6]);
        match (p + 1, q + 1) {
            (4, 4) => poly_kernel::<4, 4, 2, _, _>(patch, su, tv, &mut hom),
            (3, 3) => poly_kernel::<3, 3, 2, _, _>(patch, su, tv, &mut hom),
            (3, 2) => poly_kernel::<3, 2, 2, _, _>(patch, su, tv, &mut hom),
            (2, 3) => poly_kernel::<2, 3, 2, _, _>(patch, su, tv, &mut hom),
            (2, 2) => poly_kernel::<2, 2, 2, _, _>(patch, su, tv, &mut hom),
            (4, 2) => poly_kernel::<4, 2, 2, _, _>(patch, su, tv, &mut hom),
            (2, 4) => poly_kernel::<2, 4, 2, _, _>(patch, su, tv, &mut hom),
            (4, 3) => poly_kernel::<4, 3, 2, _, _>(patch, su, tv, &mut hom),
            (3, 4) => poly_kernel::<3, 4, 2, _, _>(patch, su, tv, &mut hom),
            _ => return false,
        }
        hom.project(out);
        out.d[0] += o;
        true
    }

    /// The coefficients of the patch holding `(u, v)` (from `coef`, laid
    /// out as [`Self::coef`]) with the local parameters and inverse span
    /// widths `(s, 1/hu)`, `(t, 1/hv)`.
    #[inline(always)]
    fn patch_at<'c, V>(
        &self,
        coef: &'c [V],
        u: f64,
        v: f64,
    ) -> Option<(&'c [V], LocalParam, LocalParam, Vec3)> {
        let [p, q] = self.degree;
        let (a, s, hu) = span_of(&self.breaks_u, &self.inv_width[0], u);
        let (b, t, hv) = span_of(&self.breaks_v, &self.inv_width[1], v);
        let stride = (p + 1) * (q + 1);
        let index = a * (self.breaks_v.len() - 1) + b;
        let patch = coef.get(index * stride..(index + 1) * stride)?;
        Some((patch, (s, hu), (t, hv), *self.origin.get(index)?))
    }

    #[inline(always)]
    fn polynomial_into<S: Sink<Vec3>>(&self, u: f64, v: f64, nd: usize, out: &mut S) -> bool {
        if self.coef3.is_empty() {
            return false;
        }
        let [p, q] = self.degree;
        let Some((patch, su, tv, o)) = self.patch_at(&self.coef3, u, v) else {
            return false;
        };
        match (p + 1, q + 1, nd) {
            // Bicubic patches with the orders Newton iterations ask for get
            // fully unrolled kernels.
            (4, 4, 2) => poly_kernel::<4, 4, 2, _, _>(patch, su, tv, out),
            (4, 4, 3) => poly_kernel::<4, 4, 3, _, _>(patch, su, tv, out),
            (4, 4, _) => poly_kernel_nd::<4, 4, _>(patch, su, tv, nd, out),
            (3, 3, _) => poly_kernel_nd::<3, 3, _>(patch, su, tv, nd, out),
            (2, 2, _) => poly_kernel_nd::<2, 2, _>(patch, su, tv, nd, out),
            // Extrusions and ruled faces of CAD parts (cubic or quadratic
            // by linear) and cubic by quadratic blends.
            (4, 2, _) => poly_kernel_nd::<4, 2, _>(patch, su, tv, nd, out),
            (2, 4, _) => poly_kernel_nd::<2, 4, _>(patch, su, tv, nd, out),
            (3, 2, _) => poly_kernel_nd::<3, 2, _>(patch, su, tv, nd, out),
            (2, 3, _) => poly_kernel_nd::<2, 3, _>(patch, su, tv, nd, out),
            (4, 3, _) => poly_kernel_nd::<4, 3, _>(patch, su, tv, nd, out),
            (3, 4, _) => poly_kernel_nd::<3, 4, _>(patch, su, tv, nd, out),
            _ => {
                let (_, su) = local(&self.breaks_u, u, p, nd);
                let (_, tv) = local(&self.breaks_v, v, q, nd);
                let all = kernel_any(patch, &su, &tv, nd, p + 1, q + 1);
                for (k, row) in all.iter().enumerate() {
                    for (l, &d) in row.iter().enumerate().take(nd + 1 - k.min(nd)) {
                        out.put(k, l, d);
                    }
                }
            }
        }
        out.shift(o);
        true
    }

    /// The point at a parameter already clamped into the domain: the same
    /// sums, in the same order, as [`Self::derivs_polynomial`] (and, for a
    /// rational surface, [`Self::derivs`] followed by the division by the
    /// weight) give at order 0, without their derivative tables.
    #[inline]
    pub fn point(&self, u: f64, v: f64) -> Option<Vec3> {
        if self.coef3.is_empty() {
            let (patch, (s, _), (t, _), o) = self.patch_at(&self.coef, u, v)?;
            let a = self.sum0(patch, s, t);
            Some(xyz_of(&a) / a.w + o)
        } else {
            let (patch, (s, _), (t, _), o) = self.patch_at(&self.coef3, u, v)?;
            Some(self.sum0(patch, s, t) + o)
        }
    }

    /// `sum_i s^i sum_j t^j c_ij` over one patch's coefficients.
    #[inline(always)]
    fn sum0<V: Coef>(&self, patch: &[V], s: f64, t: f64) -> V {
        let [p, q] = self.degree;
        match (p + 1, q + 1) {
            (4, 4) => sum0::<V, 4, 4>(patch, s, t),
            (3, 3) => sum0::<V, 3, 3>(patch, s, t),
            (2, 2) => sum0::<V, 2, 2>(patch, s, t),
            (3, 2) => sum0::<V, 3, 2>(patch, s, t),
            (2, 3) => sum0::<V, 2, 3>(patch, s, t),
            (np, nq) => sum0_any(patch, (s, np), (t, nq)),
        }
    }

    /// Homogeneous derivatives `aw[k][l]` for `k + l <= nd` (nd <= 3) at a
    /// parameter already clamped into the domain.
    pub fn derivs(&self, u: f64, v: f64, nd: usize) -> [[Vec4; 4]; 4] {
        let [p, q] = self.degree;
        let (a, su) = local(&self.breaks_u, u, p, nd);
        let (b, tv) = local(&self.breaks_v, v, q, nd);
        let stride = (p + 1) * (q + 1);
        let index = a * (self.breaks_v.len() - 1) + b;
        let start = index * stride;
        let patch = &self.coef[start..start + stride];
        let mut aw = match (p + 1, q + 1) {
            (4, 4) => kernel::<Vec4, 4, 4>(patch, &su, &tv, nd),
            (3, 3) => kernel::<Vec4, 3, 3>(patch, &su, &tv, nd),
            (2, 2) => kernel::<Vec4, 2, 2>(patch, &su, &tv, nd),
            (3, 2) => kernel::<Vec4, 3, 2>(patch, &su, &tv, nd),
            (2, 3) => kernel::<Vec4, 2, 3>(patch, &su, &tv, nd),
            _ => kernel_any(patch, &su, &tv, nd, p + 1, q + 1),
        };
        let o = self.origin.get(index).copied().unwrap_or_else(Vec3::zeros);
        for (k, row) in aw.iter_mut().enumerate().take(nd + 1) {
            for a in row.iter_mut().take(nd + 1 - k) {
                shift_homogeneous(a, o);
            }
        }
        aw
    }
}

/// Sums `s^i t^j` terms for compile-time patch sizes (loops unroll).
#[inline(always)]
fn kernel<V: Coef, const NP: usize, const NQ: usize>(
    patch: &[V],
    su: &[[f64; CAP]; 4],
    tv: &[[f64; CAP]; 4],
    nd: usize,
) -> [[V; 4]; 4] {
    let mut rows = [[V::zero(); 4]; NP];
    for (row, c) in rows.iter_mut().zip(patch.chunks_exact(NQ)) {
        for (l, out) in row.iter_mut().enumerate().take(nd + 1) {
            let mut acc = V::zero();
            for j in 0..NQ {
                acc += c[j] * tv[l][j];
            }
            *out = acc;
        }
    }
    combine(&rows, su, nd)
}

fn kernel_any<V: Coef>(
    patch: &[V],
    su: &[[f64; CAP]; 4],
    tv: &[[f64; CAP]; 4],
    nd: usize,
    np: usize,
    nq: usize,
) -> [[V; 4]; 4] {
    let mut rows = [[V::zero(); 4]; CAP];
    for (row, c) in rows.iter_mut().zip(patch.chunks_exact(nq)).take(np) {
        for (l, out) in row.iter_mut().enumerate().take(nd + 1) {
            *out = c
                .iter()
                .zip(&tv[l])
                .fold(V::zero(), |acc, (&cij, &t)| acc + cij * t);
        }
    }
    combine(&rows[..np], su, nd)
}

/// `s^0 .. s^(N-1)`, each power the last one times `s`.
#[inline(always)]
fn powers<const N: usize>(s: f64) -> [f64; N] {
    let mut out = [1.0; N];
    for i in 1..N {
        out[i] = out[i - 1] * s;
    }
    out
}

/// [`PowerPatches::sum0`] for compile-time patch sizes: each row summed
/// along `t` first, then the rows along `s` (the kernels' order).
#[inline(always)]
fn sum0<V: Coef, const NP: usize, const NQ: usize>(patch: &[V], s: f64, t: f64) -> V {
    let (ps, pt) = (powers::<NP>(s), powers::<NQ>(t));
    let mut acc = V::zero();
    for (c, &si) in patch.chunks_exact(NQ).zip(&ps) {
        let mut row = V::zero();
        for j in 0..NQ {
            row += c[j] * pt[j];
        }
        acc += row * si;
    }
    acc
}

/// [`sum0`] for any patch size (at most [`CAP`] by [`CAP`]).
fn sum0_any<V: Coef>(patch: &[V], (s, np): (f64, usize), (t, nq): (f64, usize)) -> V {
    let (ps, pt) = (powers::<CAP>(s), powers::<CAP>(t));
    let mut acc = V::zero();
    for (c, &si) in patch.chunks_exact(nq).zip(&ps).take(np) {
        let row = c
            .iter()
            .zip(&pt)
            .fold(V::zero(), |a, (&cij, &tj)| a + cij * tj);
        acc += row * si;
    }
    acc
}

/// The Euclidean part of a homogeneous point.
#[inline(always)]
fn xyz_of(a: &Vec4) -> Vec3 {
    Vec3::new(a.x, a.y, a.z)
}

/// Vectors the kernels sum: homogeneous `Vec4` or Euclidean `Vec3`.
trait Coef:
    Copy + std::ops::Add<Output = Self> + std::ops::Mul<f64, Output = Self> + std::ops::AddAssign
{
    fn zero() -> Self;
}
impl Coef for Vec4 {
    fn zero() -> Self {
        Vec4::zeros()
    }
}
impl Coef for Vec3 {
    fn zero() -> Self {
        Vec3::zeros()
    }
}

#[inline(always)]
fn combine<V: Coef>(rows: &[[V; 4]], su: &[[f64; CAP]; 4], nd: usize) -> [[V; 4]; 4] {
    let mut aw = [[V::zero(); 4]; 4];
    for (k, awk) in aw.iter_mut().enumerate().take(nd + 1) {
        for (l, out) in awk.iter_mut().enumerate().take(nd - k + 1) {
            let mut acc = V::zero();
            for (r, &s) in rows.iter().zip(&su[k]) {
                acc += r[l] * s;
            }
            *out = acc;
        }
    }
    aw
}

/// `FALLING[k][i] = i! / (i - k)!` (zero for i < k).
const FALLING: [[f64; CAP]; 4] = {
    let mut t = [[0.0; CAP]; 4];
    let mut i = 0;
    while i < CAP {
        let mut k = 0;
        while k < 4 && k <= i {
            let mut f = 1.0;
            let mut m = i + 1 - k;
            while m <= i {
                f *= m as f64;
                m += 1;
            }
            t[k][i] = f;
            k += 1;
        }
        i += 1;
    }
    t
};

/// Span index, local parameter in [0, 1] and `1 / span length`.
#[inline(always)]
fn span_of(breaks: &[f64], inv_width: &[f64], x: f64) -> (usize, f64, f64) {
    let last = breaks.len().saturating_sub(2);
    let span = breaks
        .partition_point(|&b| b <= x)
        .saturating_sub(1)
        .min(last);
    let (x0, h) = (breaks[span], inv_width[span]);
    (span, (x - x0) * h, h)
}

/// Derivatives (order `0..=nd`, chain rule included) of `s^i`, `i < NP`.
#[inline(always)]
fn monomials<const NP: usize>(s: f64, h: f64, nd: usize) -> [[f64; NP]; 4] {
    let mut powers = [1.0; NP];
    for i in 1..NP {
        powers[i] = powers[i - 1] * s;
    }
    let mut out = [[0.0; NP]; 4];
    let mut scale = 1.0;
    for (k, row) in out.iter_mut().enumerate().take(nd + 1) {
        for i in k..NP {
            row[i] = FALLING[k][i] * powers[i - k] * scale;
        }
        scale *= h;
    }
    out
}

/// Non-rational patch evaluation with the derivative order known at
/// compile time, by Horner's rule with derivatives: first along `t` for
/// every row of coefficients, then along `s` for every order in `t`.
#[inline(always)]
fn poly_kernel<const NP: usize, const NQ: usize, const ND: usize, V: Coef, S: Sink<V>>(
    patch: &[V],
    (s, hu): (f64, f64),
    (t, hv): (f64, f64),
    out: &mut S,
) {
    let mut cols = [[V::zero(); NP]; 4];
    for (i, row) in patch.chunks_exact(NQ).take(NP).enumerate() {
        let r = horner::<ND, V>(row, t);
        for (col, v) in cols.iter_mut().zip(r).take(ND + 1) {
            col[i] = v;
        }
    }
    let (mut scale_l, mut fact_l) = (1.0, 1.0);
    for (l, col) in cols.iter().enumerate().take(ND + 1) {
        let c = horner_upto(col, s, ND - l);
        let (mut scale_k, mut fact_k) = (1.0, 1.0);
        for (k, &v) in c.iter().enumerate().take(ND - l + 1) {
            out.put(k, l, v * (scale_k * scale_l * fact_k * fact_l));
            scale_k *= hu;
            fact_k *= (k + 1) as f64;
        }
        scale_l *= hv;
        fact_l *= (l + 1) as f64;
    }
}

/// `q[l] = P^(l)(x) / l!` for `l <= ND` of `P(x) = sum_j c[j] x^j`.
#[inline(always)]
fn horner<const ND: usize, V: Coef>(c: &[V], x: f64) -> [V; 4] {
    let mut q = [V::zero(); 4];
    let Some((last, rest)) = c.split_last() else {
        return q;
    };
    q[0] = *last;
    for &cj in rest.iter().rev() {
        for l in (1..=ND.min(3)).rev() {
            q[l] = q[l] * x + q[l - 1];
        }
        q[0] = q[0] * x + cj;
    }
    q
}

/// [`horner`] with the order given at run time (a constant after
/// unrolling in the kernels).
#[inline(always)]
fn horner_upto<V: Coef>(c: &[V], x: f64, nd: usize) -> [V; 4] {
    match nd {
        0 => horner::<0, V>(c, x),
        1 => horner::<1, V>(c, x),
        2 => horner::<2, V>(c, x),
        _ => horner::<3, V>(c, x),
    }
}

/// Non-rational patch evaluation for compile-time sizes, into `out`.
#[inline(always)]
fn poly_kernel_nd<const NP: usize, const NQ: usize, S: Sink<Vec3>>(
    patch: &[Vec3],
    (s, hu): (f64, f64),
    (t, hv): (f64, f64),
    nd: usize,
    out: &mut S,
) {
    let su = monomials::<NP>(s, hu, nd);
    let tv = monomials::<NQ>(t, hv, nd);
    let mut rows = [[Vec3::zeros(); 4]; NP];
    for (row, c) in rows.iter_mut().zip(patch.chunks_exact(NQ)) {
        for (l, r) in row.iter_mut().enumerate().take(nd + 1) {
            let mut acc = Vec3::zeros();
            for j in 0..NQ {
                acc += c[j] * tv[l][j];
            }
            *r = acc;
        }
    }
    for (k, suk) in su.iter().enumerate().take(nd + 1) {
        for l in 0..=nd - k {
            let mut acc = Vec3::zeros();
            for (row, &s) in rows.iter().zip(suk) {
                acc += row[l] * s;
            }
            out.put(k, l, acc);
        }
    }
}

/// Where a kernel writes derivative `d^(k+l) S / du^k dv^l`.
trait Sink<V> {
    fn put(&mut self, k: usize, l: usize, v: V);
    /// Adds the patch origin `o` taken off the coefficients back.
    fn shift(&mut self, o: Vec3);
}

/// `A + o w` (every derivative of `A = A' + o w` alike): the homogeneous
/// table of `S` from that of `S - o`.
#[inline(always)]
fn shift_homogeneous(a: &mut Vec4, o: Vec3) {
    let w = a.w;
    a.x += o.x * w;
    a.y += o.y * w;
    a.z += o.z * w;
}

impl Sink<Vec3> for [[Vec3; 4]; 4] {
    #[inline(always)]
    fn put(&mut self, k: usize, l: usize, v: Vec3) {
        if let Some(slot) = self.get_mut(k).and_then(|row| row.get_mut(l)) {
            *slot = v;
        }
    }

    #[inline(always)]
    fn shift(&mut self, o: Vec3) {
        self[0][0] += o;
    }
}

impl Sink<Vec3> for Jet2 {
    #[inline(always)]
    fn put(&mut self, k: usize, l: usize, v: Vec3) {
        if let Some(slot) = jet_slot(k, l).and_then(|i| self.d.get_mut(i)) {
            *slot = v;
        }
    }

    #[inline(always)]
    fn shift(&mut self, o: Vec3) {
        self.d[0] += o;
    }
}

/// Homogeneous second-order jet `[A, A_u, A_v, A_uu, A_uv, A_vv]` (with
/// the weight as fourth component), in [`Jet2`] order.
struct HomogeneousJet2([Vec4; 6]);

impl Sink<Vec4> for HomogeneousJet2 {
    #[inline(always)]
    fn put(&mut self, k: usize, l: usize, v: Vec4) {
        if let Some(slot) = jet_slot(k, l).and_then(|i| self.0.get_mut(i)) {
            *slot = v;
        }
    }

    #[inline(always)]
    fn shift(&mut self, o: Vec3) {
        for a in &mut self.0 {
            shift_homogeneous(a, o);
        }
    }
}

/// Where `d^(k+l) / du^k dv^l` goes in a second-order jet.
#[inline(always)]
fn jet_slot(k: usize, l: usize) -> Option<usize> {
    match (k, l) {
        (0, 0) => Some(0),
        (1, 0) => Some(1),
        (0, 1) => Some(2),
        (2, 0) => Some(3),
        (1, 1) => Some(4),
        (0, 2) => Some(5),
        _ => None,
    }
}

impl HomogeneousJet2 {
    /// The Euclidean jet by the quotient rule: with `S = A / w`,
    /// `S_a = (A_a - w_a S) / w` and
    /// `S_ab = (A_ab - w_a S_b - w_b S_a - w_ab S) / w`.
    #[inline(always)]
    fn project(&self, out: &mut Jet2) {
        let [a, au, av, auu, auv, avv] = self.0;
        let inv = 1.0 / a.w;
        let s = a.xyz() * inv;
        let su = (au.xyz() - s * au.w) * inv;
        let sv = (av.xyz() - s * av.w) * inv;
        let suu = (auu.xyz() - su * (2.0 * au.w) - s * auu.w) * inv;
        let suv = (auv.xyz() - sv * au.w - su * av.w - s * auv.w) * inv;
        let svv = (avv.xyz() - sv * (2.0 * av.w) - s * avv.w) * inv;
        out.d = [s, su, sv, suu, suv, svv];
    }
}

/// Span index of `x` among the breakpoints and the derivatives (order
/// `0..=nd`) of the local power basis `s^i`, chain rule included.
fn local(breaks: &[f64], x: f64, p: usize, nd: usize) -> (usize, [[f64; CAP]; 4]) {
    let last = breaks.len().saturating_sub(2);
    let span = breaks
        .partition_point(|&b| b <= x)
        .saturating_sub(1)
        .min(last);
    let (x0, x1) = (breaks[span], breaks[span + 1]);
    let h = 1.0 / (x1 - x0);
    let s = (x - x0) * h;
    let mut out = [[0.0; CAP]; 4];
    let mut powers = [0.0; CAP];
    powers[0] = 1.0;
    for i in 1..=p {
        powers[i] = powers[i - 1] * s;
    }
    let mut scale = 1.0;
    for (k, row) in out.iter_mut().enumerate().take(nd + 1) {
        for i in k..=p {
            row[i] = FALLING[k][i] * powers[i - k] * scale;
        }
        scale *= h;
    }
    (span, out)
}

/// Matrix taking Bezier coefficients to power-basis ones for degree `p`.
fn bezier_to_power(p: usize) -> [[f64; CAP]; CAP] {
    let mut m = [[0.0; CAP]; CAP];
    for (i, row) in m.iter_mut().enumerate().take(p + 1) {
        for (k, entry) in row.iter_mut().enumerate().take(i + 1) {
            let sign = if (i - k) % 2 == 0 { 1.0 } else { -1.0 };
            *entry = binomial(p, i) * binomial(i, k) * sign;
        }
    }
    m
}

/// A patch's origin: its first control point (the origin when its weight
/// is not positive).
fn patch_origin(patch: &BezierPatch) -> Vec3 {
    match patch.pw.first() {
        Some(b) if b.w > 0.0 => xyz_of(b) / b.w,
        _ => Vec3::zeros(),
    }
}

/// `A = M_u B M_v^T` for one patch, less its origin `o` (the homogeneous
/// control points `B - o w`).
fn convert(
    patch: &BezierPatch,
    o: Vec3,
    mu: &[[f64; CAP]; CAP],
    mv: &[[f64; CAP]; CAP],
) -> Vec<Vec4> {
    let [p, q] = patch.degree;
    let grid = move |n: usize, m: usize| (0..n).flat_map(move |i| (0..m).map(move |j| (i, j)));
    let b = |k: usize, m: usize| {
        let mut c = patch.pw[k * (q + 1) + m];
        shift_homogeneous(&mut c, -o);
        c
    };
    let half: Vec<Vec4> = grid(p + 1, q + 1)
        .map(|(k, j)| (0..=j).fold(Vec4::zeros(), |acc, m| acc + b(k, m) * mv[j][m]))
        .collect();
    grid(p + 1, q + 1)
        .map(|(i, j)| {
            (0..=i).fold(Vec4::zeros(), |acc, k| {
                acc + half[k * (q + 1) + j] * mu[i][k]
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat rational patch of degrees `p` by `q` on [0, 1]^2.
    fn patch(p: usize, q: usize) -> NurbsSurface {
        let clamped = |n: usize| [vec![0.0; n + 1], vec![1.0; n + 1]].concat();
        let cps: Vec<Vec<[f64; 3]>> = (0..=p)
            .map(|i| (0..=q).map(|j| [i as f64, j as f64, 0.0]).collect())
            .collect();
        let w: Vec<Vec<f64>> = (0..=p).map(|i| vec![1.0 + 0.1 * i as f64; q + 1]).collect();
        NurbsSurface::try_new([p, q], clamped(p), clamped(q), &cps, Some(&w), false).unwrap()
    }

    /// Surfaces up to [`FAST_MAX_DEGREE`] get power-basis patches (the
    /// high-degree blends of real parts included); beyond it the basis
    /// recursion serves.
    #[test]
    fn power_patches_up_to_the_fast_degree() {
        assert!(PowerPatches::new(&patch(3, 3)).is_some());
        assert!(PowerPatches::new(&patch(6, 10)).is_some());
        assert!(PowerPatches::new(&patch(FAST_MAX_DEGREE, 2)).is_some());
        assert!(PowerPatches::new(&patch(FAST_MAX_DEGREE + 1, 2)).is_none());
    }
}
