//! Why a fit could not be made. Every variant carries the numbers behind it.

/// Why a fit could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Fewer points than the element has degrees of freedom.
    #[error("{element} fit needs at least {needed} points, got {found}")]
    TooFewPoints {
        /// Element kind name.
        element: &'static str,
        /// Minimum number of points.
        needed: usize,
        /// Number of points given.
        found: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("point {index} (0-based) has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        /// 0-based index of the point.
        index: usize,
        /// x, mm.
        x: f64,
        /// y, mm.
        y: f64,
        /// z, mm.
        z: f64,
    },
    /// All points coincide (no extent at all).
    #[error("{element} fit: all {count} points coincide (spread {spread_mm:e} mm)")]
    Coincident {
        /// Element kind name.
        element: &'static str,
        /// Number of points.
        count: usize,
        /// RMS distance of the points from their centroid, mm.
        spread_mm: f64,
    },
    /// The points lie on a line, which leaves the element undetermined.
    #[error(
        "{element} fit: the {count} points are collinear (off-line spread {ratio:e} of their extent, limit {limit:e})"
    )]
    Collinear {
        /// Element kind name.
        element: &'static str,
        /// Number of points.
        count: usize,
        /// Second singular value over the first.
        ratio: f64,
        /// The `degenerate_ratio` option in force.
        limit: f64,
    },
    /// The points lie in a plane, which leaves the element undetermined.
    #[error(
        "{element} fit: the {count} points are coplanar (off-plane spread {ratio:e} of their extent, limit {limit:e})"
    )]
    Coplanar {
        /// Element kind name.
        element: &'static str,
        /// Number of points.
        count: usize,
        /// Third singular value over the first.
        ratio: f64,
        /// The `degenerate_ratio` option in force.
        limit: f64,
    },
    /// The iteration did not meet its tolerance within the iteration limit.
    #[error(
        "{element} {method} fit did not converge in {iterations} iterations (last step {last_step_mm:e} mm, tolerance {tolerance_mm:e} mm)"
    )]
    NoConvergence {
        /// Element kind name.
        element: &'static str,
        /// Method name.
        method: &'static str,
        /// Iterations made.
        iterations: usize,
        /// Size of the last step, mm.
        last_step_mm: f64,
        /// Tolerance in force, mm.
        tolerance_mm: f64,
    },
    /// A maximum-inscribed fit kept growing: the points do not enclose the
    /// element (partial data such as an arc or a cap).
    #[error(
        "{element} {method} fit is unbounded: the element kept growing for {iterations} iterations (radius change {growth_mm:e} mm); the points do not enclose it (partial arc or cap?)"
    )]
    Unbounded {
        /// Element kind name.
        element: &'static str,
        /// Method name.
        method: &'static str,
        /// Iterations made.
        iterations: usize,
        /// How much the inscribed size grew over the iterations, mm.
        growth_mm: f64,
    },
    /// No starting value led to a finite solution.
    #[error("{element} fit: none of the {tried} starting values gave a finite solution")]
    NoStart {
        /// Element kind name.
        element: &'static str,
        /// Number of starting values tried.
        tried: usize,
    },
    /// The fitted cone is (numerically) a cylinder: its apex is at infinity.
    #[error("cone fit degenerates to a cylinder (half apex angle {half_angle_deg:e} deg)")]
    DegenerateCone {
        /// Fitted half apex angle, degrees.
        half_angle_deg: f64,
    },
    /// The method is not defined for the element.
    #[error("method {method} is not available for {element} (available: {available})")]
    UnsupportedMethod {
        /// Element kind name.
        element: &'static str,
        /// Method name.
        method: &'static str,
        /// Methods that are available.
        available: &'static str,
    },
    /// The linear program of a minimum-zone iteration failed.
    #[error("{element} {method} fit: linear program failed in iteration {iteration}: {reason}")]
    LinearProgram {
        /// Element kind name.
        element: &'static str,
        /// Method name.
        method: &'static str,
        /// 1-based iteration.
        iteration: usize,
        /// The solver's message.
        reason: String,
    },
    /// The probe radius is negative or not finite.
    #[error("probe radius {radius_mm} mm must be finite and not negative")]
    BadProbeRadius {
        /// The probe radius given, mm.
        radius_mm: f64,
    },
    /// Probe compensation is not defined for the element.
    #[error("probe-radius compensation is not defined for a {element}")]
    NoCompensation {
        /// Element kind name.
        element: &'static str,
    },
    /// Compensation would leave a non-positive radius.
    #[error(
        "probe compensation of {probe_radius_mm} mm turns the fitted radius {radius_mm} mm into {compensated_mm} mm (not positive)"
    )]
    CompensationTooLarge {
        /// Probe ball radius, mm.
        probe_radius_mm: f64,
        /// Fitted (ball-centre) radius, mm.
        radius_mm: f64,
        /// Radius after compensation, mm.
        compensated_mm: f64,
    },
}
