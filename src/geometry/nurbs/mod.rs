//! Rational B-spline (NURBS) curves and surfaces.
//!
//! Control points are stored homogeneously (`[w x, w y, w z, w]`); all
//! evaluation goes through the B-spline basis of [`knots`] and the rational
//! quotient rule (The NURBS Book, A4.2 and A4.4).

pub mod bezier;
pub mod curve;
pub mod elevate;
pub mod insert;
pub mod jet;
pub mod knots;
mod power;
mod segments;
pub mod surface;

use crate::math::{Vec3, Vec4};

/// Binomial coefficient for the small orders used by the quotient rule.
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Euclidean part `[x, y, z]` of a homogeneous vector (not divided by w).
pub(crate) fn xyz(v: &Vec4) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// Homogeneous control point from a Euclidean point and its weight.
pub(crate) fn homogeneous(p: [f64; 3], w: f64) -> Vec4 {
    Vec4::new(p[0] * w, p[1] * w, p[2] * w, w)
}

/// Why a curve or surface could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NurbsError {
    /// A knot vector is invalid.
    #[error("knots_{dir}: {source}")]
    Knots {
        /// `"u"`, `"v"` or `""` for curves.
        dir: &'static str,
        /// What is wrong.
        source: knots::KnotError,
    },
    /// Control point count does not match the knots and degree.
    #[error("{dir}: expected {expected} control points (knots - degree - 1), found {found}")]
    Count {
        /// Which direction (`"u"` rows or `"v"` columns of row `row`).
        dir: String,
        /// Expected count.
        expected: usize,
        /// Found count.
        found: usize,
    },
    /// A control point coordinate is not finite.
    #[error("control point {index:?} is not finite")]
    NotFinite {
        /// `[i]` for curves, `[i, j]` for surfaces.
        index: Vec<usize>,
    },
    /// A weight is not finite and positive.
    #[error("weight {index:?} = {value} must be finite and positive")]
    Weight {
        /// `[i]` for curves, `[i, j]` for surfaces.
        index: Vec<usize>,
        /// The bad weight.
        value: f64,
    },
}
