//! Geometric element fitting: orthogonal-distance least squares and
//! Chebyshev (minimum zone, minimum circumscribed, maximum inscribed) fits
//! of lines, planes, circles, spheres, cylinders and cones to measured
//! points, with probe-radius compensation.
//!
//! ```
//! use cmm::fit::{fit, ElementKind, Element, FitOptions, Method};
//! use cmm::math::Point3;
//! let pts: Vec<Point3> = (0..8)
//!     .map(|i| f64::from(i) * std::f64::consts::FRAC_PI_4)
//!     .map(|a| Point3::new(1.0 + 2.0 * a.cos(), 2.0 * a.sin(), 5.0))
//!     .collect();
//! let report = fit(ElementKind::Circle, Method::Lsq, &pts, &FitOptions::default()).unwrap();
//! let Element::Circle(c) = report.element else { panic!() };
//! assert!((c.radius - 2.0).abs() < 1e-12 && (c.center.x - 1.0).abs() < 1e-12);
//! ```
//!
//! Conventions: see [`element`] for directions and residual signs; all
//! lengths are mm. Every fit centres the data on the centroid first.
mod algebraic;
pub mod element;
mod error;
mod frame;
mod gauss_newton;
mod lsq;
pub mod minimum_zone;
mod model;
mod options;
mod parallel;
mod probe_radius;
mod zone;

pub use element::{
    form_error, residual_stats, Circle, Cone, Cylinder, Element, Line, Plane, ResidualStats, Sphere,
};
pub use error::FitError;
pub use frame::canonical_sign;
pub use options::FitOptions;
pub use probe_radius::{compensate_probe, Side};

use crate::math::Point3;

/// The kinds of element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// Straight line in 3-D.
    Line,
    /// Straight line in the xy plane (z ignored).
    Line2d,
    /// Plane.
    Plane,
    /// Circle in 3-D (least-squares plane, then the circle in it).
    Circle,
    /// Circle in the xy plane (z ignored; centre at the mean z).
    Circle2d,
    /// Sphere.
    Sphere,
    /// Cylinder.
    Cylinder,
    /// Cone.
    Cone,
}

impl ElementKind {
    /// The kind's name as on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::Line => "line",
            ElementKind::Line2d => "line2d",
            ElementKind::Plane => "plane",
            ElementKind::Circle => "circle",
            ElementKind::Circle2d => "circle2d",
            ElementKind::Sphere => "sphere",
            ElementKind::Cylinder => "cylinder",
            ElementKind::Cone => "cone",
        }
    }
}

/// The fitting criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Orthogonal-distance least squares (Gauss).
    Lsq,
    /// Minimum zone (Chebyshev): the narrowest zone holding all points.
    MinimumZone,
    /// Minimum circumscribed (shafts): circle, sphere, cylinder.
    MinCircumscribed,
    /// Maximum inscribed (bores): circle, sphere, cylinder.
    MaxInscribed,
}

impl Method {
    /// The method's name as on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Method::Lsq => "lsq",
            Method::MinimumZone => "minimum-zone",
            Method::MinCircumscribed => "min-circumscribed",
            Method::MaxInscribed => "max-inscribed",
        }
    }
}

/// A fitted element with its residuals and form error.
#[derive(Debug, Clone, PartialEq)]
pub struct FitReport {
    /// What was fitted.
    pub kind: ElementKind,
    /// How.
    pub method: Method,
    /// The element.
    pub element: Element,
    /// Signed residuals of the points from the element, mm.
    pub residuals: ResidualStats,
    /// Form error (see [`form_error`]), mm.
    pub form_mm: f64,
    /// Iterations of the solver (all starts included).
    pub iterations: usize,
    /// Number of points.
    pub point_count: usize,
}

/// The least-squares element of `kind` fitted to `points`, started from
/// the nominal element `near` as well as from the data: where the points
/// fit more than one element about equally well (within
/// [`FitOptions::nominal_preference_mm`] of RMS residual), the one near the
/// nominal.
pub fn fit_near(
    kind: ElementKind,
    points: &[Point3],
    opts: &FitOptions,
    near: &Element,
) -> Result<FitReport, FitError> {
    let f = lsq::fit_near(kind, points, opts, near)?;
    let residuals = f
        .stats
        .unwrap_or_else(|| residual_stats(&f.element, points));
    Ok(FitReport {
        kind,
        method: Method::Lsq,
        form_mm: form_error(&f.element, &residuals),
        element: f.element,
        residuals,
        iterations: f.iterations,
        point_count: points.len(),
    })
}

/// Fits an element of `kind` to `points` by `method`.
pub fn fit(
    kind: ElementKind,
    method: Method,
    points: &[Point3],
    opts: &FitOptions,
) -> Result<FitReport, FitError> {
    let (element, iterations, stats) = match method {
        Method::Lsq => {
            let f = lsq::fit(kind, points, opts)?;
            (f.element, f.iterations, f.stats)
        }
        _ => {
            let (element, iterations) = zone::fit(kind, method, points, opts)?;
            (element, iterations, None)
        }
    };
    let residuals = stats.unwrap_or_else(|| residual_stats(&element, points));
    let form_mm = form_error(&element, &residuals);
    let point_count = points.len();
    Ok(FitReport {
        kind,
        method,
        element,
        residuals,
        form_mm,
        iterations,
        point_count,
    })
}
