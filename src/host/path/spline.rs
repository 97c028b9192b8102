//! C2 cubic spline through points with chord-length parameterisation,
//! by the second-derivative ("moment") formulation.
//!
//! With chords `h_i = |p_{i+1} - p_i|` and slopes `d_i = (p_{i+1} - p_i) / h_i`,
//! the second derivatives `M_i` at the points satisfy, at every interior
//! point, `h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} =
//! 6 (d_i - d_{i-1})`. Closed paths wrap the indices (cyclic system); open
//! paths add natural (`M = 0`) or not-a-knot ends.

use super::options::EndCondition;
use super::pcc::CubicSegment;
use crate::math::{Point3, Vec3};

/// Tridiagonal system rows: `sub[i] x[i-1] + diag[i] x[i] + sup[i] x[i+1]`.
struct Tridiag {
    sub: Vec<f64>,
    diag: Vec<f64>,
    sup: Vec<f64>,
    rhs: Vec<Vec3>,
}

/// Chord lengths and unit chord directions (closing chord included when
/// `closed`).
fn chords(points: &[Point3], closed: bool) -> (Vec<f64>, Vec<Vec3>) {
    let n = points.len();
    let count = if closed { n } else { n.saturating_sub(1) };
    (0..count)
        .map(|i| {
            let chord = points[(i + 1) % n] - points[i];
            let h = chord.norm();
            (h, chord / h)
        })
        .unzip()
}

/// Cubic segments through `points` (at least 2, or 3 when closed, with
/// non-zero chords: the caller validates).
pub(crate) fn segments(
    points: &[Point3],
    closed: bool,
    end: EndCondition,
    quad_panels: usize,
) -> Vec<CubicSegment> {
    let (h, d) = chords(points, closed);
    let moments = if closed {
        periodic_moments(&h, &d)
    } else {
        open_moments(&h, &d, end)
    };
    (0..h.len())
        .map(|i| {
            let m1 = moments[(i + 1) % moments.len()];
            CubicSegment::from_moments(points[i], d[i], h[i], moments[i], m1, quad_panels)
        })
        .collect()
}

/// Interior row `i` (1-based neighbours `i-1`, `i`) of the moment system.
fn row(h0: f64, h1: f64, d0: Vec3, d1: Vec3) -> (f64, f64, f64, Vec3) {
    (h0, 2.0 * (h0 + h1), h1, 6.0 * (d1 - d0))
}

/// Moments of a periodic spline (`n >= 3` chords).
fn periodic_moments(h: &[f64], d: &[Vec3]) -> Vec<Vec3> {
    let n = h.len();
    let mut sys = Tridiag::with_capacity(n);
    for i in 0..n {
        let prev = (i + n - 1) % n;
        sys.push(row(h[prev], h[i], d[prev], d[i]));
    }
    sys.solve_cyclic()
}

/// Moments of an open spline with `h.len() + 1` points.
fn open_moments(h: &[f64], d: &[Vec3], end: EndCondition) -> Vec<Vec3> {
    let n = h.len() + 1;
    if n < 3 {
        return vec![Vec3::zeros(); n];
    }
    let mut sys = Tridiag::with_capacity(n - 2);
    for i in 1..n - 1 {
        sys.push(row(h[i - 1], h[i], d[i - 1], d[i]));
    }
    let not_a_knot = end == EndCondition::NotAKnot && n >= 4;
    if not_a_knot {
        sys.apply_not_a_knot(h);
    }
    let inner = sys.solve();
    let mut m = Vec::with_capacity(n);
    m.push(Vec3::zeros());
    m.extend(inner);
    m.push(Vec3::zeros());
    if not_a_knot {
        extrapolate_not_a_knot(&mut m, h);
    }
    m
}

/// End moments from the not-a-knot conditions (continuous third
/// derivative at the second and second-to-last points).
fn extrapolate_not_a_knot(m: &mut [Vec3], h: &[f64]) {
    let (n, k) = (m.len(), h.len());
    let e = h[0] / h[1];
    m[0] = m[1] * (1.0 + e) - m[2] * e;
    let g = h[k - 1] / h[k - 2];
    m[n - 1] = m[n - 2] * (1.0 + g) - m[n - 3] * g;
}

impl Tridiag {
    fn with_capacity(n: usize) -> Self {
        Tridiag {
            sub: Vec::with_capacity(n),
            diag: Vec::with_capacity(n),
            sup: Vec::with_capacity(n),
            rhs: Vec::with_capacity(n),
        }
    }

    fn push(&mut self, (a, b, c, r): (f64, f64, f64, Vec3)) {
        self.sub.push(a);
        self.diag.push(b);
        self.sup.push(c);
        self.rhs.push(r);
    }

    /// Eliminates the end moments of the first and last rows by the
    /// not-a-knot conditions (at least 2 rows).
    fn apply_not_a_knot(&mut self, h: &[f64]) {
        let (rows, k) = (self.diag.len(), h.len());
        let e = h[0] / h[1];
        self.diag[0] += h[0] * (1.0 + e);
        self.sup[0] -= h[0] * e;
        let g = h[k - 1] / h[k - 2];
        self.diag[rows - 1] += h[k - 1] * (1.0 + g);
        self.sub[rows - 1] -= h[k - 1] * g;
    }

    /// Thomas algorithm (diagonally dominant rows, no pivoting needed);
    /// `sub[0]` and the last `sup` are ignored.
    fn solve(&self) -> Vec<Vec3> {
        thomas(&self.sub, &self.diag, &self.sup, &self.rhs)
    }

    /// Cyclic system (`sub[0]` couples to the last unknown, the last `sup`
    /// to the first) by Sherman-Morrison on the Thomas solution.
    fn solve_cyclic(&self) -> Vec<Vec3> {
        let n = self.diag.len();
        let (alpha, beta) = (self.sup[n - 1], self.sub[0]);
        let gamma = -self.diag[0];
        let mut diag = self.diag.clone();
        diag[0] -= gamma;
        diag[n - 1] -= alpha * beta / gamma;
        let x = thomas(&self.sub, &diag, &self.sup, &self.rhs);
        let mut u = vec![Vec3::zeros(); n];
        u[0] = Vec3::repeat(gamma);
        u[n - 1] = Vec3::repeat(alpha);
        let z = thomas(&self.sub, &diag, &self.sup, &u);
        let fact = (x[0] + x[n - 1] * (beta / gamma))
            .component_div(&(Vec3::repeat(1.0) + z[0] + z[n - 1] * (beta / gamma)));
        x.iter()
            .zip(&z)
            .map(|(xi, zi)| xi - zi.component_mul(&fact))
            .collect()
    }
}

/// Thomas algorithm for a tridiagonal system with vector right-hand sides.
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[Vec3]) -> Vec<Vec3> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut r = vec![Vec3::zeros(); n];
    for i in 0..n {
        let (c_prev, r_prev) = if i == 0 {
            (0.0, Vec3::zeros())
        } else {
            (c[i - 1], r[i - 1])
        };
        let a = if i == 0 { 0.0 } else { sub[i] };
        let denom = diag[i] - a * c_prev;
        c[i] = sup[i] / denom;
        r[i] = (rhs[i] - r_prev * a) / denom;
    }
    for i in (0..n.saturating_sub(1)).rev() {
        let next = r[i + 1];
        r[i] -= next * c[i];
    }
    r
}
