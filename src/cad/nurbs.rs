//! A minimal local NURBS evaluator (de Boor on homogeneous points) for
//! sampling edges and pcurves. Independent of the geometry kernel on purpose.
use crate::math::{Point3, Vec4};
use crate::workpiece::format::SurfaceSpec;

/// A rational B-spline curve with an expanded knot vector.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsCurve {
    /// Degree.
    pub degree: usize,
    /// Full knot vector (length = points + degree + 1).
    pub knots: Vec<f64>,
    /// Control points (mm, or parameter units for pcurves).
    pub points: Vec<Point3>,
    /// Positive weights, one per control point.
    pub weights: Vec<f64>,
}

impl NurbsCurve {
    /// True when the counts agree and the knots do not decrease.
    pub fn is_valid(&self) -> bool {
        let n = self.points.len();
        n > self.degree
            && self.weights.len() == n
            && self.knots.len() == n + self.degree + 1
            && self.knots.windows(2).all(|w| matches!(w, [a, b] if a <= b))
            && self.weights.iter().all(|w| *w > 0.0)
    }

    /// The parameter domain `[t_p, t_n]`.
    pub fn domain(&self) -> (f64, f64) {
        let lo = self.knots.get(self.degree).copied().unwrap_or(0.0);
        let hi = self.knots.get(self.points.len()).copied().unwrap_or(lo);
        (lo, hi)
    }

    /// The point at `t` (clamped into the domain).
    pub fn eval(&self, t: f64) -> Point3 {
        let cps: Vec<Vec4> = self
            .points
            .iter()
            .zip(&self.weights)
            .map(|(p, w)| Vec4::new(p.x * w, p.y * w, p.z * w, *w))
            .collect();
        let h = de_boor(self.degree, &self.knots, &cps, t);
        project(h)
    }

    /// The distinct interior knots (span boundaries) inside the domain.
    pub fn breaks(&self) -> Vec<f64> {
        let (lo, hi) = self.domain();
        let mut out = vec![lo];
        for &k in &self.knots {
            if k > lo && k < hi && out.last().is_some_and(|l| k > *l) {
                out.push(k);
            }
        }
        out.push(hi);
        out
    }
}

fn project(h: Vec4) -> Point3 {
    if h.w.abs() < f64::MIN_POSITIVE {
        return Point3::new(h.x, h.y, h.z);
    }
    Point3::new(h.x / h.w, h.y / h.w, h.z / h.w)
}

/// de Boor's algorithm on homogeneous points; never panics (degenerate input gives zero).
pub fn de_boor(p: usize, knots: &[f64], cps: &[Vec4], t: f64) -> Vec4 {
    let n = cps.len();
    if n == 0 || knots.len() < n + p + 1 {
        return Vec4::zeros();
    }
    let lo = knots.get(p).copied().unwrap_or(0.0);
    let hi = knots.get(n).copied().unwrap_or(lo);
    let t = t.clamp(lo, hi);
    let span = find_span(p, knots, n, t);
    let mut d: Vec<Vec4> = (0..=p)
        .map(|j| cps.get(span + j - p).copied().unwrap_or_else(Vec4::zeros))
        .collect();
    for r in 1..=p {
        for j in (r..=p).rev() {
            let i = span + j - p;
            let a = knots.get(i).copied().unwrap_or(0.0);
            let b = knots.get(i + p + 1 - r).copied().unwrap_or(0.0);
            let alpha = if b > a { (t - a) / (b - a) } else { 0.0 };
            let prev = d.get(j - 1).copied().unwrap_or_else(Vec4::zeros);
            if let Some(dj) = d.get_mut(j) {
                *dj = prev * (1.0 - alpha) + *dj * alpha;
            }
        }
    }
    d.get(p).copied().unwrap_or_else(Vec4::zeros)
}

/// Index `k` with `knots[k] <= t < knots[k+1]`, `p <= k < n`.
fn find_span(p: usize, knots: &[f64], n: usize, t: f64) -> usize {
    let mut k = p;
    while k + 1 < n && knots.get(k + 1).is_some_and(|&next| next <= t) {
        k += 1;
    }
    k
}

/// Evaluates a surface spec at `(u, v)` (for mapping pcurves to 3-D).
pub fn eval_surface(s: &SurfaceSpec, u: f64, v: f64) -> Point3 {
    let [p, q] = s.degree;
    let column: Vec<Vec4> = s
        .control_points
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let cps: Vec<Vec4> = row
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    let w = weight(s, i, j);
                    Vec4::new(c[0] * w, c[1] * w, c[2] * w, w)
                })
                .collect();
            de_boor(q, &s.knots_v, &cps, v)
        })
        .collect();
    project(de_boor(p, &s.knots_u, &column, u))
}

fn weight(s: &SurfaceSpec, i: usize, j: usize) -> f64 {
    s.weights
        .as_ref()
        .and_then(|w| w.get(i))
        .and_then(|r| r.get(j))
        .copied()
        .unwrap_or(1.0)
}
