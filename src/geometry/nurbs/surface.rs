//! Rational B-spline (NURBS) surfaces: evaluation, derivatives, normals and
//! curvature.
use super::knots::{KnotVector, MAX_DEGREE};
use super::{binomial, homogeneous, xyz, NurbsError};
use std::sync::OnceLock;

use super::jet::Jet2;
use super::power::PowerPatches;
use crate::math::{Point3, Vec2, Vec3, Vec4};

/// A NURBS surface `S(u, v)` with an outward side, mm.
///
/// Control points `[i][j]` run along u (i) and v (j). The outward normal is
/// `Su x Sv` normalised, or its negation when the surface is `reversed`.
#[derive(Debug, Clone)]
pub struct NurbsSurface {
    ku: KnotVector,
    kv: KnotVector,
    /// Homogeneous control points, row-major: index `i * nv + j`.
    pw: Vec<Vec4>,
    nv: usize,
    rational: bool,
    reversed: bool,
    /// Power-basis patches for fast evaluation, built on first use.
    fast: OnceLock<Option<PowerPatches>>,
}

impl PartialEq for NurbsSurface {
    fn eq(&self, o: &Self) -> bool {
        self.ku == o.ku && self.kv == o.kv && self.pw == o.pw && self.reversed == o.reversed
    }
}

/// Partial derivatives of a surface at one parameter: `d[k][l]` is
/// `d^(k+l) S / du^k dv^l` (valid for `k + l <=` the requested order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceDerivs {
    /// The derivative table.
    pub d: [[Vec3; 4]; 4],
}

impl SurfaceDerivs {
    /// `S(u, v)`.
    pub fn point(&self) -> Point3 {
        Point3::from(self.d[0][0])
    }
    /// `dS/du`.
    pub fn su(&self) -> Vec3 {
        self.d[1][0]
    }
    /// `dS/dv`.
    pub fn sv(&self) -> Vec3 {
        self.d[0][1]
    }
    /// `d2S/du2`.
    pub fn suu(&self) -> Vec3 {
        self.d[2][0]
    }
    /// `d2S/dudv`.
    pub fn suv(&self) -> Vec3 {
        self.d[1][1]
    }
    /// `d2S/dv2`.
    pub fn svv(&self) -> Vec3 {
        self.d[0][2]
    }
}

/// Principal curvatures (1/mm) and directions at a surface point. Signs are
/// relative to the outward normal: positive where the surface bends towards
/// it (concave from outside, e.g. a bore), negative where it bends away
/// (convex, e.g. a sphere seen from outside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curvature {
    /// Smaller principal curvature.
    pub k_min: f64,
    /// Larger principal curvature.
    pub k_max: f64,
    /// Unit tangent direction of `k_min`.
    pub dir_min: Vec3,
    /// Unit tangent direction of `k_max`.
    pub dir_max: Vec3,
}

/// Below this ratio of |Su| to |Sv| (or back) the normal is taken from the
/// limit at a degenerate edge (pole) instead of the ill-conditioned `Su x Sv`.
const NEAR_DEGENERATE_RATIO: f64 = 1e-8;
/// Parameters within this fraction of the domain from an edge are "at" it.
const EDGE_PROXIMITY: f64 = 1e-6;

impl NurbsSurface {
    /// Builds a surface from degrees, knots, `control_points[i][j]` and
    /// optional weights of the same shape (default 1).
    pub fn try_new(
        degree: [usize; 2],
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        control_points: &[Vec<[f64; 3]>],
        weights: Option<&[Vec<f64>]>,
        reversed: bool,
    ) -> Result<Self, NurbsError> {
        let ku = KnotVector::try_new(knots_u, degree[0])
            .map_err(|source| NurbsError::Knots { dir: "u", source })?;
        let kv = KnotVector::try_new(knots_v, degree[1])
            .map_err(|source| NurbsError::Knots { dir: "v", source })?;
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        check_grid(
            control_points.iter().map(Vec::len),
            nu,
            nv,
            "control_points",
        )?;
        if let Some(w) = weights {
            check_grid(w.iter().map(Vec::len), nu, nv, "weights")?;
        }
        let pw = build_homogeneous(control_points, weights)?;
        let rational = pw.iter().any(|p| p.w != 1.0);
        Ok(NurbsSurface {
            ku,
            kv,
            pw,
            nv,
            rational,
            reversed,
            fast: OnceLock::new(),
        })
    }

    /// Builds a surface from validated parts (used by knot insertion).
    pub(crate) fn from_parts(
        ku: KnotVector,
        kv: KnotVector,
        pw: Vec<Vec4>,
        reversed: bool,
    ) -> Self {
        let nv = kv.num_basis();
        let rational = pw.iter().any(|p| p.w != 1.0);
        NurbsSurface {
            ku,
            kv,
            pw,
            nv,
            rational,
            reversed,
            fast: OnceLock::new(),
        }
    }

    /// Knot vector in u.
    pub fn knots_u(&self) -> &KnotVector {
        &self.ku
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &KnotVector {
        &self.kv
    }
    /// Number of control points along u and v.
    pub fn counts(&self) -> (usize, usize) {
        (self.ku.num_basis(), self.nv)
    }
    /// Homogeneous control point `[i][j]`.
    pub fn homogeneous_point(&self, i: usize, j: usize) -> Vec4 {
        self.pw[i * self.nv + j]
    }
    /// All homogeneous control points, row-major (`i * nv + j`).
    pub fn homogeneous_points(&self) -> &[Vec4] {
        &self.pw
    }
    /// Whether any weight differs from 1.
    pub fn is_rational(&self) -> bool {
        self.rational
    }
    /// Whether the outward normal is `-(Su x Sv)`.
    pub fn is_reversed(&self) -> bool {
        self.reversed
    }
    /// Parameter domain `((u0, u1), (v0, v1))`.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.ku.domain(), self.kv.domain())
    }
    /// Clamps `(u, v)` into the domain.
    pub fn clamp(&self, uv: Vec2) -> Vec2 {
        let ((u0, u1), (v0, v1)) = self.domain();
        Vec2::new(uv.x.clamp(u0, u1), uv.y.clamp(v0, v1))
    }

    /// The point `S(u, v)`.
    pub fn point(&self, u: f64, v: f64) -> Point3 {
        if let Some(fast) = self.fast.get_or_init(|| PowerPatches::new(self)) {
            let uv = self.clamp(Vec2::new(u, v));
            if let Some(p) = fast.point(uv.x, uv.y) {
                return Point3::from(p);
            }
        }
        self.derivs(u, v, 0).point()
    }

    /// `S` and its partial derivatives up to total order `nd` (at most 3).
    /// Parameters outside the domain are clamped.
    pub fn derivs(&self, u: f64, v: f64, nd: usize) -> SurfaceDerivs {
        let mut out = SurfaceDerivs {
            d: [[Vec3::zeros(); 4]; 4],
        };
        self.derivs_into(u, v, nd, &mut out);
        out
    }

    /// [`Self::derivs`] into a table the caller owns (entries beyond order
    /// `nd` are left as they are).
    #[inline]
    pub fn derivs_into(&self, u: f64, v: f64, nd: usize, out: &mut SurfaceDerivs) {
        let nd = nd.min(3);
        if let Some(fast) = self.fast.get_or_init(|| PowerPatches::new(self)) {
            let uv = self.clamp(Vec2::new(u, v));
            if fast.derivs_polynomial(uv.x, uv.y, nd, &mut out.d) {
                return;
            }
            let mut jet = Jet2 {
                d: [Vec3::zeros(); 6],
            };
            if nd == 2 && fast.jet2_rational(uv.x, uv.y, &mut jet) {
                let [s, su, sv, suu, suv, svv] = jet.d;
                let d = &mut out.d;
                (d[0][0], d[1][0], d[0][1]) = (s, su, sv);
                (d[2][0], d[1][1], d[0][2]) = (suu, suv, svv);
                return;
            }
            let aw = fast.derivs(uv.x, uv.y, nd);
            out.d = self.rational_derivs(&aw, nd);
            return;
        }
        *out = self.derivs_de_boor(u, v, nd);
    }

    /// The point with its derivatives to second order (the table Newton
    /// iterations use); written straight from the power-basis kernel for
    /// non-rational surfaces.
    #[inline]
    pub fn jet2(&self, u: f64, v: f64) -> Jet2 {
        let mut out = Jet2 {
            d: [Vec3::zeros(); 6],
        };
        self.jet2_into(u, v, &mut out);
        out
    }

    /// [`Self::jet2`] written into `out` (no table copied on return).
    #[inline]
    pub fn jet2_into(&self, u: f64, v: f64, out: &mut Jet2) {
        if let Some(fast) = self.fast.get_or_init(|| PowerPatches::new(self)) {
            let uv = self.clamp(Vec2::new(u, v));
            if fast.jet2_polynomial(uv.x, uv.y, out) || fast.jet2_rational(uv.x, uv.y, out) {
                return;
            }
        }
        *out = Jet2::from(&self.derivs(u, v, 2));
    }

    /// [`Self::derivs`] by the B-spline basis recursion (any degree); the
    /// reference for the power-basis fast path.
    pub fn derivs_de_boor(&self, u: f64, v: f64, nd: usize) -> SurfaceDerivs {
        let nd = nd.min(3);
        let p = self.ku.degree().max(self.kv.degree());
        if p <= 3 {
            self.derivs_n::<4>(u, v, nd)
        } else if p <= 7 {
            self.derivs_n::<8>(u, v, nd)
        } else {
            self.derivs_n::<{ MAX_DEGREE + 1 }>(u, v, nd)
        }
    }

    fn derivs_n<const N: usize>(&self, u: f64, v: f64, nd: usize) -> SurfaceDerivs {
        let uv = self.clamp(Vec2::new(u, v));
        let (p, q) = (self.ku.degree(), self.kv.degree());
        let (su, sv) = (self.ku.find_span(uv.x), self.kv.find_span(uv.y));
        let nu = self.ku.basis_derivs::<N>(su, uv.x, nd);
        let nvb = self.kv.basis_derivs::<N>(sv, uv.y, nd);
        let mut aw = [[Vec4::zeros(); 4]; 4];
        for (k, nuk) in nu.iter().enumerate().take(nd.min(p) + 1) {
            let mut temp = [Vec4::zeros(); N];
            for (r, &coef) in nuk.iter().enumerate().take(p + 1) {
                let row = (su - p + r) * self.nv + sv - q;
                for (t, cp) in temp.iter_mut().zip(&self.pw[row..=row + q]) {
                    *t += cp * coef;
                }
            }
            for (l, nvl) in nvb.iter().enumerate().take((nd - k).min(q) + 1) {
                aw[k][l] = temp
                    .iter()
                    .zip(nvl)
                    .take(q + 1)
                    .fold(Vec4::zeros(), |acc, (t, &b)| acc + t * b);
            }
        }
        SurfaceDerivs {
            d: self.rational_derivs(&aw, nd),
        }
    }

    fn rational_derivs(&self, aw: &[[Vec4; 4]; 4], nd: usize) -> [[Vec3; 4]; 4] {
        let mut skl = [[Vec3::zeros(); 4]; 4];
        if !self.rational {
            for k in 0..=nd {
                for l in 0..=nd - k {
                    skl[k][l] = xyz(&aw[k][l]);
                }
            }
            return skl;
        }
        for k in 0..=nd {
            for l in 0..=nd - k {
                skl[k][l] = quotient_term(aw, &skl, k, l) / aw[0][0].w;
            }
        }
        skl
    }

    /// Unit outward normal at `(u, v)`, with the limit taken at degenerate
    /// points (poles, collapsed edges) from second derivatives.
    pub fn normal(&self, u: f64, v: f64) -> Vec3 {
        let d = self.derivs(u, v, 2);
        self.normal_from(&d, Vec2::new(u, v))
    }

    /// Unit outward normal from precomputed derivatives (order >= 2 is
    /// needed only at degenerate points; `uv` locates them).
    pub fn normal_from(&self, d: &SurfaceDerivs, uv: Vec2) -> Vec3 {
        self.normal_from_jet(&Jet2::from(d), uv)
    }

    /// [`Self::normal_from`] for a second-order jet.
    pub fn normal_from_jet(&self, d: &Jet2, uv: Vec2) -> Vec3 {
        let sign = if self.reversed { -1.0 } else { 1.0 };
        let n = d.su().cross(&d.sv());
        let (lu2, lv2) = (d.su().norm_squared(), d.sv().norm_squared());
        let r2 = NEAR_DEGENERATE_RATIO * NEAR_DEGENERATE_RATIO;
        let near_degenerate = lu2 < r2 * lv2 || lv2 < r2 * lu2;
        if !near_degenerate && n.norm_squared() > 0.0 {
            return n.normalize() * sign;
        }
        let uv = self.clamp(uv);
        let limit = self.degenerate_normal(d, uv);
        // Next to a collapsed edge the limit's own side is right; at a
        // singular point inside the domain Su x Sv decides the side.
        let side = if self.near_edge(uv) || limit.dot(&n) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        limit * side * sign
    }

    fn near_edge(&self, uv: Vec2) -> bool {
        let ((u0, u1), (v0, v1)) = self.domain();
        let (eu, ev) = ((u1 - u0) * EDGE_PROXIMITY, (v1 - v0) * EDGE_PROXIMITY);
        uv.x - u0 <= eu || u1 - uv.x <= eu || uv.y - v0 <= ev || v1 - uv.y <= ev
    }

    fn degenerate_normal(&self, d: &Jet2, uv: Vec2) -> Vec3 {
        let ((u0, u1), (v0, v1)) = self.domain();
        // Step inward from the degenerate edge: Su(u, v + h) ~ h Suv.
        let candidate = if d.su().norm() <= d.sv().norm() {
            let h = if uv.y - v0 <= v1 - uv.y { 1.0 } else { -1.0 };
            (d.suv() * h).cross(&d.sv())
        } else {
            let h = if uv.x - u0 <= u1 - uv.x { 1.0 } else { -1.0 };
            d.su().cross(&(d.suv() * h))
        };
        if candidate.norm() > 0.0 {
            return candidate.normalize();
        }
        self.nudged_normal(uv)
    }

    fn nudged_normal(&self, uv: Vec2) -> Vec3 {
        let ((u0, u1), (v0, v1)) = self.domain();
        let (cu, cv) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let t = 1e-7;
        let nudged = Vec2::new(uv.x + (cu - uv.x) * t, uv.y + (cv - uv.y) * t);
        let d = self.derivs(nudged.x, nudged.y, 1);
        d.su()
            .cross(&d.sv())
            .try_normalize(0.0)
            .unwrap_or_else(Vec3::z)
    }

    /// Principal curvatures and directions at `(u, v)` (see [`Curvature`]).
    pub fn curvature(&self, u: f64, v: f64) -> Curvature {
        let d = self.derivs(u, v, 2);
        let n = self.normal_from(&d, Vec2::new(u, v));
        principal_curvatures(&d, n)
    }
}

fn quotient_term(aw: &[[Vec4; 4]; 4], skl: &[[Vec3; 4]; 4], k: usize, l: usize) -> Vec3 {
    let mut v = xyz(&aw[k][l]);
    for j in 1..=l {
        v -= skl[k][l - j] * (binomial(l, j) * aw[0][j].w);
    }
    for i in 1..=k {
        v -= skl[k - i][l] * (binomial(k, i) * aw[i][0].w);
        let mut v2 = Vec3::zeros();
        for j in 1..=l {
            v2 += skl[k - i][l - j] * (binomial(l, j) * aw[i][j].w);
        }
        v -= v2 * binomial(k, i);
    }
    v
}

/// Principal curvatures from the fundamental forms, signed against `n`.
pub fn principal_curvatures(d: &SurfaceDerivs, n: Vec3) -> Curvature {
    let (su, sv) = (d.su(), d.sv());
    let (e, f, g) = (su.dot(&su), su.dot(&sv), sv.dot(&sv));
    let (l, m, nn) = (d.suu().dot(&n), d.suv().dot(&n), d.svv().dot(&n));
    let det = e * g - f * f;
    // Shape operator W = I^-1 II; its eigenvalues are the principal
    // curvatures. The discriminant ((a - d) / 2)^2 + b c stays accurate at
    // umbilics, where H^2 - K would cancel.
    let (a, b) = ((g * l - f * m) / det, (g * m - f * nn) / det);
    let (c, dd) = ((e * m - f * l) / det, (e * nn - f * m) / det);
    let mean = 0.5 * (a + dd);
    let disc = (0.25 * (a - dd) * (a - dd) + b * c).max(0.0).sqrt();
    let (k_min, k_max) = (mean - disc, mean + disc);
    let dir = |k: f64| principal_direction(e, f, g, l, m, nn, k, su, sv);
    Curvature {
        k_min,
        k_max,
        dir_min: dir(k_min),
        dir_max: dir(k_max),
    }
}

#[allow(clippy::too_many_arguments)]
fn principal_direction(
    e: f64,
    f: f64,
    g: f64,
    l: f64,
    m: f64,
    n: f64,
    k: f64,
    su: Vec3,
    sv: Vec3,
) -> Vec3 {
    // (L - kE) du + (M - kF) dv = 0 and (M - kF) du + (N - kG) dv = 0.
    let (a, b) = (l - k * e, m - k * f);
    let (c, dd) = (m - k * f, n - k * g);
    let cand = if a.abs() + b.abs() >= c.abs() + dd.abs() {
        (-b, a)
    } else {
        (-dd, c)
    };
    let t = su * cand.0 + sv * cand.1;
    t.try_normalize(1e-300)
        .unwrap_or_else(|| su.try_normalize(1e-300).unwrap_or_else(Vec3::x))
}

fn check_grid(
    rows: impl ExactSizeIterator<Item = usize>,
    nu: usize,
    nv: usize,
    what: &str,
) -> Result<(), NurbsError> {
    if rows.len() != nu {
        return Err(NurbsError::Count {
            dir: what.to_string(),
            expected: nu,
            found: rows.len(),
        });
    }
    for (i, len) in rows.enumerate() {
        if len != nv {
            return Err(NurbsError::Count {
                dir: format!("{what}[{i}]"),
                expected: nv,
                found: len,
            });
        }
    }
    Ok(())
}

fn build_homogeneous(
    cps: &[Vec<[f64; 3]>],
    weights: Option<&[Vec<f64>]>,
) -> Result<Vec<Vec4>, NurbsError> {
    let mut out = Vec::with_capacity(cps.len() * cps.first().map_or(0, Vec::len));
    for (i, row) in cps.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            let w = weights
                .and_then(|w| w.get(i)?.get(j).copied())
                .unwrap_or(1.0);
            if !p.iter().all(|c| c.is_finite()) {
                return Err(NurbsError::NotFinite { index: vec![i, j] });
            }
            if !(w.is_finite() && w > 0.0) {
                return Err(NurbsError::Weight {
                    index: vec![i, j],
                    value: w,
                });
            }
            out.push(homogeneous(*p, w));
        }
    }
    Ok(out)
}
