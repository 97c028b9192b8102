//! Tolerances and iteration limits of the fits.

/// Tolerances (mm) and iteration limits of the fits. `Default` gives values
/// that reproduce 60-digit reference results to about 1e-12 mm on data of
/// up to a few hundred mm.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Least squares stops when a Gauss-Newton / Levenberg-Marquardt step
    /// moves the element by at most this, mm: lengths (centre, axis point,
    /// radius) directly, angles (axis tilt, cone angle) times the data
    /// extent (largest distance of a point from the centroid). The
    /// effective tolerance is never below the floating-point floor
    /// `64 * f64::EPSILON * extent`.
    pub step_tolerance_mm: f64,
    /// Most Gauss-Newton / Levenberg-Marquardt iterations per start.
    pub max_iterations: usize,
    /// Minimum zone (and circumscribed / inscribed) iterations stop when the
    /// linear model predicts an improvement of the zone below this, mm
    /// (or the trust region shrinks below it).
    pub zone_tolerance_mm: f64,
    /// Most sequential-linear-programming iterations.
    pub max_zone_iterations: usize,
    /// Points are collinear (coplanar) when the second (third) singular
    /// value of the centred point matrix is below this fraction of the
    /// first. Dimensionless; resolution of the test is about 1e-8.
    pub degenerate_ratio: f64,
    /// Most points used to choose among starting values (cylinder, cone);
    /// the chosen start is then refined on all points.
    pub start_sample: usize,
    /// A fit started from the nominal element ([`super::fit_near`]) is
    /// kept unless the fit from the data's own starts leaves an RMS
    /// residual smaller by more than this, mm: points that fit two
    /// elements equally well (eight points on two circles of four lie on
    /// the bore's cylinder and on a narrower tilted one) give the one the
    /// design meant.
    pub nominal_preference_mm: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            step_tolerance_mm: 1e-12,
            max_iterations: 200,
            zone_tolerance_mm: 1e-12,
            max_zone_iterations: 500,
            degenerate_ratio: 1e-6,
            start_sample: 4000,
            nominal_preference_mm: 1e-3,
        }
    }
}
