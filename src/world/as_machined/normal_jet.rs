//! The displaced surface `G = S + h(S) n` and its derivatives to second
//! order, from the NURBS derivatives to third order.
use super::form::{sum_jets, Form, Jet};
use crate::geometry::{Jet2, NurbsSurface};
use crate::math::{Vec2, Vec3};

/// Unit normal with its first and second parameter derivatives:
/// `[n, n_u, n_v, n_uu, n_uv, n_vv]`.
type NormalJet = [Vec3; 6];

/// Below this ratio of the shorter tangent (`|Su|` or `|Sv|`) to the
/// longer, a point lies so near a collapsed edge (a pole) that the short
/// tangent's rounding error (about 1e-14 mm on a part of tens of mm) turns
/// `Su x Sv` visibly: the displacement then takes the limit normal, which
/// is off the true one by less than the ratio times the tangent's turning
/// (a few 1e-7 rad on a sphere, 1e-8 mm at h = 0.1 mm).
const COLLAPSED_TANGENT_RATIO: f64 = 1e-7;

/// `G(u, v)` and its derivatives to order `nd` (values 1..3 give order 2),
/// with the normal's second derivatives exact.
pub(super) fn displaced<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    nd: usize,
) -> Jet2 {
    let order = if nd == 0 { 1 } else { 3 };
    let s = surface.derivs(uv.x, uv.y, order);
    let t = &s.d;
    let third = [t[3][0], t[2][1], t[1][2], t[0][3]];
    let mut g = Jet2::from(&s);
    let second = Second::Exact(&third);
    if !displace(surface, terms.clone(), nd, second, &mut g) {
        g = displaced_degenerate(surface, terms, uv, nd);
    }
    g
}

/// `G(u, v)` with its derivatives to second order written into `g`, the
/// normal's second derivatives as [`Second::NormalPart`] gives them: only
/// the surface's second-order jet is evaluated (no derivative table).
pub(super) fn displaced_jet_into<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    g: &mut Jet2,
) {
    surface.jet2_into(uv.x, uv.y, g);
    if !displace(surface, terms.clone(), 2, Second::NormalPart, g) {
        displaced_degenerate_jet(surface, terms, uv, g);
    }
}

/// [`displaced_degenerate`] for Newton's evaluation: the surface's
/// second-order jets alone (at the point and at the point nudged inside),
/// the normal's second derivatives as [`Second::NormalPart`] gives them
/// (a foot at a sphere's pole is evaluated on every control cycle of a
/// touch there).
fn displaced_degenerate_jet<'a, I: Iterator<Item = &'a Form> + Clone>(
    surface: &NurbsSurface,
    terms: I,
    uv: Vec2,
    g: &mut Jet2,
) {
    let mut at = Jet2 {
        d: [Vec3::zeros(); 6],
    };
    surface.jet2_into(uv.x, uv.y, &mut at);
    let n = surface.normal_from_jet(&at, uv);
    let nudged = nudged_inside(surface, uv);
    let mut inner = at;
    surface.jet2_into(nudged.x, nudged.y, &mut inner);
    let sign = if surface.is_reversed() { -1.0 } else { 1.0 };
    *g = inner;
    let mut nj = [Vec3::zeros(); 6];
    if normal_jet(&inner, Second::NormalPart, &mut nj) {
        let jet = sum_jets(terms.clone(), inner.point());
        second_order(g, &inner, &nj, sign, &jet);
    }
    g.d[0] = at.d[0] + n * sum_jets(terms, at.point()).h;
}

/// Turns the surface jet `g` (`S` and its derivatives) into that of the
/// displaced surface in place; false (and `g` untouched) where the normal
/// is degenerate.
#[inline(always)]
fn displace<'a, I: Iterator<Item = &'a Form>>(
    surface: &NurbsSurface,
    terms: I,
    nd: usize,
    second: Second,
    g: &mut Jet2,
) -> bool {
    // The height field first: its call (and the exponentials in it) then
    // finds no derivatives live in registers to save.
    let (lu, lv) = (g.su().norm_squared(), g.sv().norm_squared());
    let r2 = COLLAPSED_TANGENT_RATIO * COLLAPSED_TANGENT_RATIO;
    if lu < r2 * lv || lv < r2 * lu {
        return false;
    }
    let jet = sum_jets(terms, g.point());
    let s = *g;
    let sign = if surface.is_reversed() { -1.0 } else { 1.0 };
    let mut n = [Vec3::zeros(); 6];
    if !normal_jet(&s, second, &mut n) {
        return false;
    }
    g.d[0] += n[0] * (sign * jet.h);
    if nd > 0 {
        second_order(g, &s, &n, sign, &jet);
    }
    true
}

/// `uv` moved a billionth of the way towards the domain's centre: off a
/// collapsed edge, where the tangents are whole again.
fn nudged_inside(surface: &NurbsSurface, uv: Vec2) -> Vec2 {
    let ((u0, u1), (v0, v1)) = surface.domain();
    let centre = Vec2::new(0.5 * (u0 + u1), 0.5 * (v0 + v1));
    uv + (centre - uv) * 1e-9
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
    let nudged = nudged_inside(surface, uv);
    let s0 = surface.derivs(uv.x, uv.y, 0);
    let table = surface.derivs(nudged.x, nudged.y, 3);
    let t = &table.d;
    let third = [t[3][0], t[2][1], t[1][2], t[0][3]];
    let inner = Jet2::from(&table);
    let sign = if surface.is_reversed() { -1.0 } else { 1.0 };
    let mut g = inner;
    let mut nj = [Vec3::zeros(); 6];
    if normal_jet(&inner, Second::Exact(&third), &mut nj) && nd > 0 {
        let jet = sum_jets(terms.clone(), inner.point());
        second_order(&mut g, &inner, &nj, sign, &jet);
    }
    g.d[0] = s0.d[0][0] + n * sum_jets(terms, s0.point()).h;
    g
}

/// The displaced surface's first and second derivatives from the surface
/// jet `s`, the normal jet `n` of `Su x Sv` (the outward one times `sign`,
/// +-1) and the height field's jet.
///
/// The sign goes onto the height's derivatives instead of the six normal
/// vectors: `(n sign) x` and `n (sign x)` are the same number for
/// `sign = +-1` (rounding is symmetric in sign), with fewer products.
#[inline(always)]
fn second_order(g: &mut Jet2, s: &Jet2, n: &NormalJet, sign: f64, jet: &Jet) {
    let (su, sv) = (s.su(), s.sv());
    let hu = jet.grad.dot(&su);
    let hv = jet.grad.dot(&sv);
    let huu = su.dot(&(jet.hess * su)) + jet.grad.dot(&s.suu());
    let huv = su.dot(&(jet.hess * sv)) + jet.grad.dot(&s.suv());
    let hvv = sv.dot(&(jet.hess * sv)) + jet.grad.dot(&s.svv());
    let [h, hu, hv, huu, huv, hvv] = [jet.h, hu, hv, huu, huv, hvv].map(|x| sign * x);
    g.d[1] = su + n[0] * hu + n[1] * h;
    g.d[2] = sv + n[0] * hv + n[2] * h;
    g.d[3] = s.suu() + n[0] * huu + n[1] * (2.0 * hu) + n[3] * h;
    g.d[4] = s.suv() + n[0] * huv + n[2] * hu + n[1] * hv + n[4] * h;
    g.d[5] = s.svv() + n[0] * hvv + n[2] * (2.0 * hv) + n[5] * h;
}

/// How the normal's second derivatives `n_uu, n_uv, n_vv` are computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Second<'t> {
    /// Exactly, from the surface's third derivatives
    /// `[Suuu, Suuv, Suvv, Svvv]`.
    Exact(&'t [Vec3; 4]),
    /// Only their component along `n` (`n . n_ab = -n_a . n_b`), from the
    /// surface's second derivatives. The tangential part dropped enters
    /// the distance Hessian only through the tangential part of the
    /// residual `q - x` times the height `h`, which is small at a foot, so
    /// Newton on the as-machined surface converges to the same exact foot
    /// (the gradient is exact) as fast in practice.
    NormalPart,
}

/// Writes the unit normal `N / |N|`, `N = Su x Sv`, and its derivatives
/// into `out` (the outward normal's for a surface that is not reversed);
/// false (and `out` untouched) where `N` vanishes.
#[inline(always)]
fn normal_jet(s: &Jet2, second: Second, out: &mut NormalJet) -> bool {
    let [_, su, sv, suu, suv, svv] = s.d;
    let big_n = su.cross(&sv);
    let m = big_n.norm();
    if m <= 1e-14 * (su.norm_squared() + sv.norm_squared()) || m == 0.0 {
        return false;
    }
    let nu = suu.cross(&sv) + su.cross(&suv);
    let nv = suv.cross(&sv) + su.cross(&svv);
    let n = big_n / m;
    let (ma, mb) = (n.dot(&nu), n.dot(&nv));
    let n_u = (nu - n * ma) / m;
    let n_v = (nv - n * mb) / m;
    let [n_uu, n_uv, n_vv] = match second {
        // n . n_ab = -n_a . n_b for a unit normal: the part of the second
        // derivatives along n, from first derivatives only.
        Second::NormalPart => {
            [-n_u.norm_squared(), -n_u.dot(&n_v), -n_v.norm_squared()].map(|k| n * k)
        }
        Second::Exact(third) => {
            let first = FirstOrder {
                n,
                m,
                nu,
                nv,
                ma,
                mb,
                n_u,
                n_v,
            };
            exact_second(s, third, &first)
        }
    };
    *out = [n, n_u, n_v, n_uu, n_uv, n_vv];
    true
}

/// The unit normal's first-order terms that its exact second derivatives
/// build on (`N = Su x Sv`, `m = |N|`, `n = N / m`).
#[derive(Clone, Copy)]
struct FirstOrder {
    n: Vec3,
    m: f64,
    /// `N_u`, `N_v`.
    nu: Vec3,
    nv: Vec3,
    /// `m_u`, `m_v` (`n . N_u`, `n . N_v`).
    ma: f64,
    mb: f64,
    /// `n_u`, `n_v`.
    n_u: Vec3,
    n_v: Vec3,
}

/// `[n_uu, n_uv, n_vv]` of the unscaled unit normal, exactly, from the
/// surface's third derivatives `[Suuu, Suuv, Suvv, Svvv]`.
fn exact_second(s: &Jet2, third: &[Vec3; 4], f: &FirstOrder) -> [Vec3; 3] {
    let [_, su, sv, suu, suv, svv] = s.d;
    let [suuu, suuv, suvv, svvv] = *third;
    let FirstOrder {
        n,
        m,
        nu,
        nv,
        ma,
        mb,
        n_u,
        n_v,
    } = *f;
    let nuu = suuu.cross(&sv) + suu.cross(&suv) * 2.0 + su.cross(&suuv);
    let nuv = suuv.cross(&sv) + suu.cross(&svv) + su.cross(&suvv);
    let nvv = suvv.cross(&sv) + suv.cross(&svv) * 2.0 + su.cross(&svvv);
    let second_of = |nab: Vec3, n_b: Vec3, na: Vec3, n_a: Vec3, m_a: f64, m_b: f64| {
        let m_ab = n_b.dot(&na) + n.dot(&nab);
        (nab - n_b * m_a - n * m_ab) / m - n_a * (m_b / m)
    };
    [
        second_of(nuu, n_u, nu, n_u, ma, ma),
        second_of(nuv, n_v, nu, n_u, ma, mb),
        second_of(nvv, n_v, nv, n_v, mb, mb),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    /// The displacement as it was written before the sign moved onto the
    /// height's derivatives: the six normal vectors times the sign, then
    /// the products with the unsigned derivatives.
    fn reference(s: &Jet2, sign: f64, second: Second, jet: &Jet) -> Option<Jet2> {
        let mut n = [Vec3::zeros(); 6];
        if !normal_jet(s, second, &mut n) {
            return None;
        }
        let n = n.map(|v| v * sign);
        let mut g = *s;
        g.d[0] += n[0] * jet.h;
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
        Some(g)
    }

    /// The displacement as [`displace`] does it, from a surface jet.
    fn folded(s: &Jet2, sign: f64, second: Second, jet: &Jet) -> Option<Jet2> {
        let mut n = [Vec3::zeros(); 6];
        if !normal_jet(s, second, &mut n) {
            return None;
        }
        let mut g = *s;
        g.d[0] += n[0] * (sign * jet.h);
        second_order(&mut g, s, &n, sign, jet);
        Some(g)
    }

    /// Bit for bit the same displaced jets for both signs, both kinds of
    /// normal second derivatives and a seeded sweep of surface jets and
    /// height fields (values spanning several orders of magnitude).
    #[test]
    fn sign_on_the_heights_changes_no_bit() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let unit = (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            unit * 10f64.powi((x % 7) as i32 - 3)
        };
        let mut vec = || Vec3::new(next(), next(), next());
        let mut compared = 0;
        for _ in 0..2000 {
            let s = Jet2 {
                d: [vec(), vec(), vec(), vec(), vec(), vec()],
            };
            let third = [vec(), vec(), vec(), vec()];
            let (grad, a, b) = (vec(), vec(), vec());
            let hess = Mat3::from_columns(&[a, b, vec()]) + a * b.transpose();
            let jet = Jet {
                h: grad.x,
                grad,
                hess,
            };
            for sign in [1.0, -1.0] {
                for second in [Second::NormalPart, Second::Exact(&third)] {
                    let (a, b) = (
                        reference(&s, sign, second, &jet),
                        folded(&s, sign, second, &jet),
                    );
                    let bits = |g: Option<Jet2>| g.map(|g| g.d.map(|v| v.map(f64::to_bits)));
                    assert_eq!(bits(a), bits(b), "{s:?} {jet:?} {sign}");
                    compared += usize::from(a.is_some());
                }
            }
        }
        assert!(compared > 7000, "{compared} jets compared");
    }
}
