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
        let q = self.degree[1];
        let mid = 0.5 * (self.u.0 + self.u.1);
        let (mut a, mut b) = (self.clone(), self.clone());
        // Column j is every (q + 1)-th point from j.
        for j in 0..=q {
            if let (Some(ca), Some(cb)) = (a.pw.get_mut(j..), b.pw.get_mut(j..)) {
                halve_in_place(ca, cb, q + 1);
            }
        }
        a.u = (self.u.0, mid);
        b.u = (mid, self.u.1);
        (a, b)
    }

    /// Splits at the parameter midpoint of v.
    pub fn split_v(&self) -> (BezierPatch, BezierPatch) {
        let q = self.degree[1];
        let mid = 0.5 * (self.v.0 + self.v.1);
        let (mut a, mut b) = (self.clone(), self.clone());
        for (ra, rb) in a.pw.chunks_mut(q + 1).zip(b.pw.chunks_mut(q + 1)) {
            halve_in_place(ra, rb, 1);
        }
        a.v = (self.v.0, mid);
        b.v = (mid, self.v.1);
        (a, b)
    }
}

/// Splits the Bezier polygon held in every `stride`-th entry of `left`
/// and `right` (both holding it on entry) at t = 1/2: `left` ends as its
/// first half, `right` as its second. De Casteljau's triangle is worked
/// in `right` itself: level `k` leaves its last point, the second half's
/// point `n - 1 - k`, untouched from then on, and its first point is the
/// first half's point `k`.
fn halve_in_place(left: &mut [Vec4], right: &mut [Vec4], stride: usize) {
    let n = right.len().div_ceil(stride);
    for level in 0..n {
        if let (Some(l), Some(&r)) = (left.get_mut(level * stride), right.first()) {
            *l = r;
        }
        for i in 0..n - 1 - level {
            let (Some(&x), Some(&y)) = (right.get(i * stride), right.get((i + 1) * stride)) else {
                continue;
            };
            if let Some(w) = right.get_mut(i * stride) {
                *w = (x + y) * 0.5;
            }
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A rational biquadratic-by-cubic patch (a quarter circle in u with
    /// its `sqrt(1/2)` weight, a wavy cubic in v) over `[0, 2] x [0, 3]`
    /// with an inner knot in each direction.
    fn surface() -> NurbsSurface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let arc = [([1.0, 0.0], 1.0), ([1.0, 1.0], w), ([0.0, 1.0], 1.0)];
        let mut pts = Vec::new();
        let mut wts = Vec::new();
        for i in 0..4 {
            let (mut row, mut rw) = (Vec::new(), Vec::new());
            for j in 0..5 {
                let ([x, y], wt) = arc[(i + j) % 3];
                let r = 10.0 + i as f64 + 0.5 * j as f64;
                row.push([r * x, r * y, 3.0 * j as f64 + (i * j % 3) as f64]);
                rw.push(wt * (1.0 + 0.1 * i as f64));
            }
            pts.push(row);
            wts.push(rw);
        }
        let ku = vec![0.0, 0.0, 0.0, 1.2, 2.0, 2.0, 2.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 1.0, 3.0, 3.0, 3.0, 3.0];
        NurbsSurface::try_new([2, 3], ku, kv, &pts, Some(&wts), false)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// The patch's point at parameters `(u, v)` by its Bernstein sums
    /// (independent of de Casteljau's halving).
    fn bernstein_point(b: &BezierPatch, u: f64, v: f64) -> Point3 {
        let [p, q] = b.degree;
        let basis = |n: usize, k: usize, t: f64| {
            let c = (0..k).fold(1.0, |c, m| c * (n - m) as f64 / (m + 1) as f64);
            c * t.powi(k as i32) * (1.0 - t).powi((n - k) as i32)
        };
        let (s, t) = ((u - b.u.0) / (b.u.1 - b.u.0), (v - b.v.0) / (b.v.1 - b.v.0));
        let mut sum = Vec4::zeros();
        for i in 0..=p {
            for j in 0..=q {
                sum += b.pw[i * (q + 1) + j] * (basis(p, i, s) * basis(q, j, t));
            }
        }
        Point3::new(sum.x / sum.w, sum.y / sum.w, sum.z / sum.w)
    }

    #[test]
    fn halves_trace_the_surface_over_their_rectangles() {
        let s = surface();
        let patches = decompose(&s);
        assert_eq!(patches.len(), 4);
        let mut checked = 0;
        for patch in &patches {
            let (a, b) = patch.split_u();
            let (c, d) = a.split_v();
            for h in [&a, &b, &c, &d] {
                assert!(h.u.0 < h.u.1 && h.v.0 < h.v.1);
                for k in 0..=4 {
                    for l in 0..=4 {
                        let u = h.u.0 + (h.u.1 - h.u.0) * k as f64 / 4.0;
                        let v = h.v.0 + (h.v.1 - h.v.0) * l as f64 / 4.0;
                        let e = (bernstein_point(h, u, v) - s.point(u, v)).norm();
                        assert!(e < 1e-12, "{e} at ({u}, {v})");
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 4 * 4 * 25);
        // The halves meet the rectangle's middle.
        let (a, b) = patches[0].split_u();
        assert_eq!(a.u.1, b.u.0);
    }
}
