//! B-spline geometry of the reader is the geometry kernel's: curves are
//! [`crate::geometry::NurbsCurve`] and surfaces are evaluated as
//! [`NurbsSurface`]. These helpers build them from file data and read the
//! control points and weights back for the swept-surface constructions.
pub use crate::geometry::NurbsCurve;
use crate::geometry::{NurbsError, NurbsSurface};
use crate::math::Point3;
use crate::workpiece::format::SurfaceSpec;

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

/// The kernel surface of a spec (for evaluation and projection).
pub fn kernel_surface(spec: &SurfaceSpec) -> Result<NurbsSurface, NurbsError> {
    NurbsSurface::try_new(
        spec.degree,
        spec.knots_u.clone(),
        spec.knots_v.clone(),
        &spec.control_points,
        spec.weights.as_deref(),
        spec.reversed,
    )
}
