//! Bezier decomposition and de Casteljau subdivision of NURBS surfaces,
//! the building blocks of the projection hierarchy and section seeding.
use super::surface::NurbsSurface;
use crate::math::{Point3, Vec4};

/// One rational Bezier patch of a surface, with its parameter rectangle.
#[derive(Debug, Clone, PartialEq)]
pub struct BezierPatch {
    /// Parameter range in u.
    pub u: (f64, f64),
    /// Parameter range in v.
    pub v: (f64, f64),
    /// Degrees.
    pub degree: [usize; 2],
    /// Homogeneous control points, row-major (`i * (q + 1) + j`).
    pub pw: Vec<Vec4>,
}

impl BezierPatch {
    /// Euclidean control points (the patch lies in their convex hull since
    /// all weights are positive).
    pub fn points(&self) -> impl Iterator<Item = Point3> + '_ {
        self.pw
            .iter()
            .map(|p| Point3::new(p.x / p.w, p.y / p.w, p.z / p.w))
    }

    /// Control point `[i][j]` (Euclidean).
    pub fn point(&self, i: usize, j: usize) -> Point3 {
        let p = self.pw[i * (self.degree[1] + 1) + j];
        Point3::new(p.x / p.w, p.y / p.w, p.z / p.w)
    }

    /// Splits at the parameter midpoint of u.
    pub fn split_u(&self) -> (BezierPatch, BezierPatch) {
        let [p, q] = self.degree;
        let mid = 0.5 * (self.u.0 + self.u.1);
        let mut a = self.clone();
        let mut b = self.clone();
        for j in 0..=q {
            let col: Vec<Vec4> = (0..=p).map(|i| self.pw[i * (q + 1) + j]).collect();
            let (left, right) = de_casteljau_halves(&col);
            for i in 0..=p {
                a.pw[i * (q + 1) + j] = left[i];
                b.pw[i * (q + 1) + j] = right[i];
            }
        }
        a.u = (self.u.0, mid);
        b.u = (mid, self.u.1);
        (a, b)
    }

    /// Splits at the parameter midpoint of v.
    pub fn split_v(&self) -> (BezierPatch, BezierPatch) {
        let [p, q] = self.degree;
        let mid = 0.5 * (self.v.0 + self.v.1);
        let mut a = self.clone();
        let mut b = self.clone();
        for i in 0..=p {
            let row = &self.pw[i * (q + 1)..(i + 1) * (q + 1)];
            let (left, right) = de_casteljau_halves(row);
            a.pw[i * (q + 1)..(i + 1) * (q + 1)].copy_from_slice(&left);
            b.pw[i * (q + 1)..(i + 1) * (q + 1)].copy_from_slice(&right);
        }
        a.v = (self.v.0, mid);
        b.v = (mid, self.v.1);
        (a, b)
    }
}

/// Splits a Bezier polygon at t = 1/2 into its two halves.
fn de_casteljau_halves(points: &[Vec4]) -> (Vec<Vec4>, Vec<Vec4>) {
    let n = points.len();
    let mut work = points.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![Vec4::zeros(); n];
    for level in 0..n {
        left.push(work[0]);
        right[n - 1 - level] = work[n - 1 - level];
        for i in 0..n - 1 - level {
            work[i] = (work[i] + work[i + 1]) * 0.5;
        }
    }
    (left, right)
}

/// Splits a surface into its rational Bezier patches, row-major over the
/// knot spans (u outer, v inner).
pub fn decompose(surface: &NurbsSurface) -> Vec<BezierPatch> {
    let refined = refine_to_bezier(surface);
    let (p, q) = (refined.knots_u().degree(), refined.knots_v().degree());
    let us = spans(refined.knots_u().as_slice(), p, refined.counts().0);
    let vs = spans(refined.knots_v().as_slice(), q, refined.counts().1);
    let mut patches = Vec::with_capacity(us.len() * vs.len());
    for &(ku, u) in &us {
        for &(kv, v) in &vs {
            let pw = (0..=p)
                .flat_map(|i| (0..=q).map(move |j| (i, j)))
                .map(|(i, j)| refined.homogeneous_point(ku - p + i, kv - q + j))
                .collect();
            patches.push(BezierPatch {
                u,
                v,
                degree: [p, q],
                pw,
            });
        }
    }
    patches
}

/// Non-empty spans `(k, (knot[k], knot[k+1]))` of a refined knot vector.
fn spans(knots: &[f64], p: usize, n: usize) -> Vec<(usize, (f64, f64))> {
    (p..n)
        .filter(|&k| knots[k] < knots[k + 1])
        .map(|k| (k, (knots[k], knots[k + 1])))
        .collect()
}

/// Inserts every breakpoint (domain ends included) up to multiplicity p.
fn refine_to_bezier(surface: &NurbsSurface) -> NurbsSurface {
    let mut s = surface.clone();
    let p = s.knots_u().degree();
    for u in s.knots_u().breakpoints() {
        let need = p.saturating_sub(s.knots_u().multiplicity(u));
        if need > 0 {
            s = s.insert_knot_u(u, need).unwrap_or(s);
        }
    }
    let q = s.knots_v().degree();
    for v in s.knots_v().breakpoints() {
        let need = q.saturating_sub(s.knots_v().multiplicity(v));
        if need > 0 {
            s = s.insert_knot_v(v, need).unwrap_or(s);
        }
    }
    s
}
