//! The displaced surface `G = S + h(S) n` and its derivatives to second
//! order, from the NURBS derivatives to third order.
use super::form::{sum_jets, Form, Jet};
use crate::geometry::{Jet2, NurbsSurface, SurfaceDerivs};
use crate::math::{Vec2, Vec3};

/// Unit normal with its first and second parameter derivatives:
/// `[n, n_u, n_v, n_uu, n_uv, n_vv]`.
type NormalJet = [Vec3; 6];

/// `G(u, v)` and its derivatives to order `nd` (values 1..3 give order 2).
pub(super) fn displaced<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    nd: usize,
) -> Jet2 {
    let mut g = Jet2 {
        d: [Vec3::zeros(); 6],
    };
    displaced_into(surface, terms, uv, nd, Second::Exact, &mut g);
    g
}

/// [`displaced`] written into `g` (the per-cycle path copies no tables),
/// with the normal's second derivatives as `second` says.
pub(super) fn displaced_into<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    nd: usize,
    second: Second,
    g: &mut Jet2,
) {
    let mut s = SurfaceDerivs {
        d: [[Vec3::zeros(); 4]; 4],
    };
    let order = match (nd, second) {
        (0, _) => 1,
        (_, Second::Exact) => 3,
        (_, Second::NormalPart) => 2,
    };
    surface.derivs_into(uv.x, uv.y, order, &mut s);
    let sign = if surface.is_reversed() { -1.0 } else { 1.0 };
    let jet = sum_jets(terms.clone(), s.point());
    let mut n = [Vec3::zeros(); 6];
    if !normal_jet(&s, sign, second, &mut n) {
        *g = displaced_degenerate(surface, terms, uv, nd);
        return;
    }
    let t = &s.d;
    g.d = [t[0][0], t[1][0], t[0][1], t[2][0], t[1][1], t[0][2]];
    g.d[0] += n[0] * jet.h;
    if nd > 0 {
        second_order(g, &s, &n, &jet);
    }
}

/// At a degenerate normal (pole) the displacement uses the limit normal and
/// the derivatives of the point nudged slightly inside the domain.
fn displaced_degenerate<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    nd: usize,
) -> Jet2 {
    let n = surface.normal(uv.x, uv.y);
    let ((u0, u1), (v0, v1)) = surface.domain();
    let centre = Vec2::new(0.5 * (u0 + u1), 0.5 * (v0 + v1));
    let nudged = uv + (centre - uv) * 1e-9;
    let s0 = surface.derivs(uv.x, uv.y, 0);
    let inner = surface.derivs(nudged.x, nudged.y, 3);
    let sign = if surface.is_reversed() { -1.0 } else { 1.0 };
    let mut g = Jet2::from(&inner);
    let mut nj = [Vec3::zeros(); 6];
    if normal_jet(&inner, sign, Second::Exact, &mut nj) && nd > 0 {
        second_order(&mut g, &inner, &nj, &sum_jets(terms.clone(), inner.point()));
    }
    g.d[0] = s0.d[0][0] + n * sum_jets(terms, s0.point()).h;
    g
}

fn second_order(g: &mut Jet2, s: &SurfaceDerivs, n: &NormalJet, jet: &Jet) {
    let (su, sv) = (s.su(), s.sv());
    let hu = jet.grad.dot(&su);
    let hv = jet.grad.dot(&sv);
    let huu = su.dot(&(jet.hess * su)) + jet.grad.dot(&s.suu());
    let huv = su.dot(&(jet.hess * sv)) + jet.grad.dot(&s.suv());
    let hvv = sv.dot(&(jet.hess * sv)) + jet.grad.dot(&s.svv());
    let h = jet.h;
    g.d[1] = su + n[0] * hu + n[1] * h;
    g.d[2] = sv + n[0] * hv + n[2] * h;
    g.d[3] = s.suu() + n[0] * huu + n[1] * (2.0 * hu) + n[3] * h;
    g.d[4] = s.suv() + n[0] * huv + n[2] * hu + n[1] * hv + n[4] * h;
    g.d[5] = s.svv() + n[0] * hvv + n[2] * (2.0 * hv) + n[5] * h;
}

/// How the normal's second derivatives `n_uu, n_uv, n_vv` are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Second {
    /// Exactly (needs the surface's third derivatives).
    Exact,
    /// Only their component along `n` (`n . n_ab = -n_a . n_b`), from the
    /// surface's second derivatives. The tangential part dropped enters
    /// the distance Hessian only through the tangential part of the
    /// residual `q - x` times the height `h`, which is small at a foot, so
    /// Newton on the as-machined surface converges to the same exact foot
    /// (the gradient is exact) as fast in practice.
    NormalPart,
}

/// Writes the unit normal `sign * N / |N|`, `N = Su x Sv`, and its
/// derivatives into `out`; false (and `out` untouched) where `N` vanishes.
fn normal_jet(s: &SurfaceDerivs, sign: f64, second: Second, out: &mut NormalJet) -> bool {
    let d = &s.d;
    let (su, sv) = (d[1][0], d[0][1]);
    let big_n = su.cross(&sv);
    let m = big_n.norm();
    if m <= 1e-14 * (su.norm_squared() + sv.norm_squared()) || m == 0.0 {
        return false;
    }
    let nu = d[2][0].cross(&sv) + su.cross(&d[1][1]);
    let nv = d[1][1].cross(&sv) + su.cross(&d[0][2]);
    let n = big_n / m;
    let (ma, mb) = (n.dot(&nu), n.dot(&nv));
    let n_u = (nu - n * ma) / m;
    let n_v = (nv - n * mb) / m;
    if second == Second::NormalPart {
        // n . n_ab = -n_a . n_b for a unit normal: the part of the second
        // derivatives along n, from first derivatives only.
        let normal_part = [-n_u.norm_squared(), -n_u.dot(&n_v), -n_v.norm_squared()];
        let [n_uu, n_uv, n_vv] = normal_part.map(|k| n * k);
        for (slot, v) in out.iter_mut().zip([n, n_u, n_v, n_uu, n_uv, n_vv]) {
            *slot = v * sign;
        }
        return true;
    }
    let nuu = d[3][0].cross(&sv) + d[2][0].cross(&d[1][1]) * 2.0 + su.cross(&d[2][1]);
    let nuv = d[2][1].cross(&sv) + d[2][0].cross(&d[0][2]) + su.cross(&d[1][2]);
    let nvv = d[1][2].cross(&sv) + d[1][1].cross(&d[0][2]) * 2.0 + su.cross(&d[0][3]);
    let second_of = |nab: Vec3, n_b: Vec3, na: Vec3, n_a: Vec3, m_a: f64, m_b: f64| {
        let m_ab = n_b.dot(&na) + n.dot(&nab);
        (nab - n_b * m_a - n * m_ab) / m - n_a * (m_b / m)
    };
    let n_uu = second_of(nuu, n_u, nu, n_u, ma, ma);
    let n_uv = second_of(nuv, n_v, nu, n_u, ma, mb);
    let n_vv = second_of(nvv, n_v, nv, n_v, mb, mb);
    for (slot, v) in out.iter_mut().zip([n, n_u, n_v, n_uu, n_uv, n_vv]) {
        *slot = v * sign;
    }
    true
}
