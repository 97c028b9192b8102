//! Rational B-spline curves in 3-D.
use super::knots::{KnotVector, MAX_DEGREE};
use super::{binomial, homogeneous, xyz, NurbsError};
use crate::math::{Point3, Vec3, Vec4};

/// A NURBS curve `C(t)`, mm.
///
/// ```
/// use cmm::geometry::NurbsCurve;
/// // Quarter circle of radius 2 as a rational quadratic.
/// let w = std::f64::consts::FRAC_1_SQRT_2;
/// let c = NurbsCurve::try_new(2, vec![0., 0., 0., 1., 1., 1.],
///     vec![[2., 0., 0.], [2., 2., 0.], [0., 2., 0.]], Some(vec![1., w, 1.])).unwrap();
/// assert!(((c.point(0.3) - cmm::math::Point3::origin()).norm() - 2.0).abs() < 1e-14);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsCurve {
    knots: KnotVector,
    points: Vec<Vec4>,
}

impl NurbsCurve {
    /// Builds a curve; weights default to 1.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<[f64; 3]>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self, NurbsError> {
        let knots = KnotVector::try_new(knots, degree)
            .map_err(|source| NurbsError::Knots { dir: "", source })?;
        check_count(&knots, points.len())?;
        let weights = weights.unwrap_or_else(|| vec![1.0; points.len()]);
        check_count(&knots, weights.len())?;
        let points = points
            .iter()
            .zip(&weights)
            .enumerate()
            .map(|(i, (p, &w))| checked_point(i, p, w))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(NurbsCurve { knots, points })
    }

    /// Builds a curve from already validated parts.
    pub(crate) fn from_parts(knots: KnotVector, points: Vec<Vec4>) -> Self {
        NurbsCurve { knots, points }
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// Homogeneous control points.
    pub fn homogeneous_points(&self) -> &[Vec4] {
        &self.points
    }

    /// Parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }

    /// The point `C(t)` (t clamped to the domain).
    pub fn point(&self, t: f64) -> Point3 {
        Point3::from(self.derivs(t, 0)[0])
    }

    /// `C` and its derivatives up to order `nd` (at most 3) at `t`.
    pub fn derivs(&self, t: f64, nd: usize) -> [Vec3; 4] {
        if self.knots.degree() <= 3 {
            self.derivs_n::<4>(t, nd)
        } else if self.knots.degree() <= 7 {
            self.derivs_n::<8>(t, nd)
        } else {
            self.derivs_n::<{ MAX_DEGREE + 1 }>(t, nd)
        }
    }

    fn derivs_n<const N: usize>(&self, t: f64, nd: usize) -> [Vec3; 4] {
        let p = self.knots.degree();
        let span = self.knots.find_span(t);
        let (lo, hi) = self.domain();
        let basis = self.knots.basis_derivs::<N>(span, t.clamp(lo, hi), nd);
        let mut aw = [Vec4::zeros(); 4];
        let pts = &self.points[span - p..=span];
        for (a, nk) in aw.iter_mut().zip(&basis).take(nd + 1) {
            *a = pts
                .iter()
                .zip(nk)
                .fold(Vec4::zeros(), |acc, (cp, &b)| acc + cp * b);
        }
        rational_curve_derivs(&aw, nd)
    }
}

/// Quotient rule (A4.2): Euclidean derivatives from homogeneous ones.
pub(crate) fn rational_curve_derivs(aw: &[Vec4; 4], nd: usize) -> [Vec3; 4] {
    let mut ck = [Vec3::zeros(); 4];
    for k in 0..=nd {
        let mut v = xyz(&aw[k]);
        for i in 1..=k {
            v -= ck[k - i] * (binomial(k, i) * aw[i].w);
        }
        ck[k] = v / aw[0].w;
    }
    ck
}

fn check_count(knots: &KnotVector, found: usize) -> Result<(), NurbsError> {
    let expected = knots.num_basis();
    if found != expected {
        return Err(NurbsError::Count {
            dir: "points".into(),
            expected,
            found,
        });
    }
    Ok(())
}

fn checked_point(i: usize, p: &[f64; 3], w: f64) -> Result<Vec4, NurbsError> {
    if !p.iter().all(|c| c.is_finite()) {
        return Err(NurbsError::NotFinite { index: vec![i] });
    }
    if !(w.is_finite() && w > 0.0) {
        return Err(NurbsError::Weight {
            index: vec![i],
            value: w,
        });
    }
    Ok(homogeneous(*p, w))
}
