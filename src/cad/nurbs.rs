//! B-spline geometry of the reader is the geometry kernel's: curves are
//! [`crate::geometry::NurbsCurve`], surfaces are evaluated as
//! [`crate::geometry::NurbsSurface`] (built with
//! [`crate::formats::workpiece::SurfaceSpec::to_surface`]). These helpers build curves
//! from file data and read control points and weights back for the
//! swept-surface constructions.
pub use crate::geometry::NurbsCurve;
use crate::geometry::NurbsError;
use crate::math::Point3;

/// A curve from degree, full knot vector, control points and weights.
pub fn new_curve(
    degree: usize,
    knots: Vec<f64>,
    points: &[Point3],
    weights: Vec<f64>,
) -> Result<NurbsCurve, NurbsError> {
    let pts = points.iter().map(|p| [p.x, p.y, p.z]).collect();
    NurbsCurve::try_new(degree, knots, pts, Some(weights))
}

/// The curve's control points (Euclidean).
pub fn control_points(c: &NurbsCurve) -> Vec<Point3> {
    c.homogeneous_points()
        .iter()
        .map(|h| Point3::new(h.x / h.w, h.y / h.w, h.z / h.w))
        .collect()
}

/// The curve's weights.
pub fn weights(c: &NurbsCurve) -> Vec<f64> {
    c.homogeneous_points().iter().map(|h| h.w).collect()
}

/// The distinct knots inside the domain (span boundaries), both ends included.
pub fn breaks(c: &NurbsCurve) -> Vec<f64> {
    c.knots().breakpoints()
}
