//! Algebraic (Kasa) circle and sphere fits: linear, hence robust starting
//! values for the orthogonal fits, and exact on noise-free data, partial
//! arcs included.
use nalgebra::{DMatrix, DVector};

use crate::math::Vec3;

/// Kasa fit of a circle (`dims == 2`, z ignored) or sphere (`dims == 3`) to
/// points near the origin: solves `|p|^2 = 2 c.p + k` in the least-squares
/// sense; returns the centre and radius, or `None` when the system is
/// singular (e.g. collinear points).
pub(crate) fn kasa(points: &[Vec3], dims: usize) -> Option<(Vec3, f64)> {
    let n = dims + 1;
    let scale = points.iter().map(|p| p.norm()).fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let (mut m, mut rhs) = ([[0.0; 4]; 4], [0.0; 4]);
    let mut row = [0.0; 4];
    for p in points {
        let q = p / scale;
        (0..dims).for_each(|i| row[i] = q[i]);
        row[dims] = 1.0;
        let target = q.rows(0, dims).norm_squared();
        for i in 0..n {
            rhs[i] += row[i] * target;
            (0..n).for_each(|j| m[i][j] += row[i] * row[j]);
        }
    }
    let m = DMatrix::from_fn(n, n, |i, j| m[i][j]);
    let x = m.lu().solve(&DVector::from_fn(n, |i, _| rhs[i]))?;
    let mut centre = Vec3::zeros();
    (0..dims).for_each(|i| centre[i] = x[i] / 2.0);
    let r2 = x[dims] + centre.norm_squared();
    (r2 > 0.0 && r2.is_finite()).then(|| (centre * scale, r2.sqrt() * scale))
}
