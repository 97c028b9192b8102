//! Exact degree elevation of NURBS curves and multiplication of a curve's
//! homogeneous form by another curve's weight function. Both work on the
//! Bezier segments of the curve, in homogeneous coordinates, so the
//! elevated or reweighted curve has the same point at every parameter.
//!
//! The results carry every interior breakpoint with full multiplicity
//! (knots are not removed afterwards): the shape and parameterisation are
//! exact, the knot vector states only continuity C0.
use super::curve::NurbsCurve;
use super::insert::InsertError;
use super::knots::MAX_DEGREE;
use super::segments::{join, product, segments, Segment};
use super::NurbsError;

/// Why a curve could not be elevated or reweighted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElevateError {
    /// The resulting degree would exceed [`MAX_DEGREE`].
    #[error("degree {degree} exceeds the supported maximum {max}", max = MAX_DEGREE)]
    DegreeTooHigh {
        /// The degree asked for.
        degree: usize,
    },
    /// The weight factor is defined over another parameter domain.
    #[error(
        "the factor's domain [{factor_lo}, {factor_hi}] differs from the curve's [{lo}, {hi}]"
    )]
    Domain {
        /// Curve domain start.
        lo: f64,
        /// Curve domain end.
        hi: f64,
        /// Factor domain start.
        factor_lo: f64,
        /// Factor domain end.
        factor_hi: f64,
    },
    /// The Bezier spans of the curve and the factor, split at the union
    /// of their breakpoints, do not pair up.
    #[error("the Bezier spans of the curve and the factor differ")]
    Spans,
    /// Splitting into Bezier segments failed.
    #[error("splitting into Bezier segments: {0}")]
    Insert(#[from] InsertError),
    /// The joined segments do not form a curve.
    #[error("joining Bezier segments: {0}")]
    Join(#[from] NurbsError),
}

fn check_degree(degree: usize) -> Result<(), ElevateError> {
    if degree > MAX_DEGREE {
        return Err(ElevateError::DegreeTooHigh { degree });
    }
    Ok(())
}

impl NurbsCurve {
    /// The same curve (the same point at every parameter) with its degree
    /// raised by `t`: each Bezier segment is multiplied, in homogeneous
    /// coordinates, by the constant 1 written with degree `t`.
    ///
    /// ```
    /// use cmm::geometry::NurbsCurve;
    /// let w = std::f64::consts::FRAC_1_SQRT_2;
    /// let arc = NurbsCurve::try_new(2, vec![0., 0., 0., 1., 1., 1.],
    ///     vec![[1., 0., 0.], [1., 1., 0.], [0., 1., 0.]], Some(vec![1., w, 1.])).unwrap();
    /// let cubic = arc.elevate_degree(1).unwrap();
    /// assert_eq!(cubic.knots().degree(), 3);
    /// assert!(((cubic.point(0.3) - arc.point(0.3)).norm()) < 1e-15);
    /// ```
    pub fn elevate_degree(&self, t: usize) -> Result<NurbsCurve, ElevateError> {
        let q = self.knots().degree() + t;
        check_degree(q)?;
        if t == 0 {
            return Ok(self.clone());
        }
        let ones = vec![1.0; t + 1];
        let segs: Vec<Segment> = segments(self, &[])?
            .into_iter()
            .map(|s| Segment {
                pw: product(&s.pw, &ones),
                span: s.span,
            })
            .collect();
        Ok(join(q, &segs)?)
    }

    /// The same curve (the same point at every parameter) with its
    /// homogeneous form multiplied by the weight function of `factor`
    /// (a curve over the same domain): the weight function becomes the
    /// product of both, the degree the sum of both degrees. Two rational
    /// curves reweighted by each other share one weight function.
    pub fn reweighted_by(&self, factor: &NurbsCurve) -> Result<NurbsCurve, ElevateError> {
        let ((lo, hi), (factor_lo, factor_hi)) = (self.domain(), factor.domain());
        if (lo, hi) != (factor_lo, factor_hi) {
            return Err(ElevateError::Domain {
                lo,
                hi,
                factor_lo,
                factor_hi,
            });
        }
        let q = self.knots().degree() + factor.knots().degree();
        check_degree(q)?;
        // Both split at the union of their breakpoints: the spans pair up.
        let mine = segments(self, &factor.knots().breakpoints())?;
        let theirs = segments(factor, &self.knots().breakpoints())?;
        if !mine
            .iter()
            .map(|s| s.span)
            .eq(theirs.iter().map(|s| s.span))
        {
            return Err(ElevateError::Spans);
        }
        let segs: Vec<Segment> = mine
            .iter()
            .zip(&theirs)
            .map(|(a, b)| {
                let w: Vec<f64> = b.pw.iter().map(|h| h.w).collect();
                Segment {
                    pw: product(&a.pw, &w),
                    span: a.span,
                }
            })
            .collect();
        Ok(join(q, &segs)?)
    }
}
