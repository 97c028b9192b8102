//! Ball-centre paths and speed planning for design-value scanning.
//!
//! From the nominal section points with outward normals `(x, y, z, i, j, k)`
//! the host offsets every point along its normal by `r - Ep` (ball radius
//! minus the wanted deflection) and joins the offset points into a chain of
//! parametric cubic curve segments (PCC, JP6484108B2): a C2 cubic spline with
//! chord-length parameterisation ([`BallPath`]). Speeds are planned per
//! segment from an effective radius (curvature radius and chord-angle
//! radius, active-scanning speed planning), limited by lateral and tangential acceleration, and
//! sampled on the control cycle ([`SpeedPlan`], [`MotionProfile`]).
//!
//! All lengths are mm, times s, speeds mm/s, accelerations mm/s^2.
//!
//! ```
//! use cmm::host::path::{BallPath, PathOptions, SpeedOptions, SpeedPlan};
//! use cmm::math::{Point3, Vec3};
//!
//! // A quarter circle of radius 10 mm, outward normals, ball r = 1, Ep = 0.2.
//! let points: Vec<(Point3, Vec3)> = (0..=40)
//!     .map(|k| {
//!         let phi = std::f64::consts::FRAC_PI_2 * k as f64 / 40.0;
//!         let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
//!         (Point3::origin() + n * 10.0, n)
//!     })
//!     .collect();
//! let path = BallPath::from_section(&points, false, 1.0 - 0.2, PathOptions::default())?;
//! assert!((path.position(path.length() / 2.0).coords.norm() - 10.8).abs() < 1e-5);
//! let plan = SpeedPlan::new(&path, &SpeedOptions::default())?;
//! let last = plan.samples().last().map(|x| (x.s, x.v));
//! assert_eq!(last, Some((path.length(), 0.0)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod ball_path;
mod closest;
mod offset;
mod options;
mod pcc;
mod profile;
mod radius;
mod speed;
mod spline;

pub use ball_path::{BallPath, PathLocation, PathSample};
pub use options::{ClosestOptions, EndCondition, PathOptions};
pub use pcc::{CubicSegment, MAX_QUAD_PANELS};
pub use profile::{MotionProfile, MotionSample};
pub use radius::chord_angle_radius;
pub use speed::{round_the_loop, SegmentSpeed, SegmentSpeeds, SpeedError, SpeedOptions, SpeedPlan};

/// Why a ball-centre path could not be built or queried.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// Too few points for the path kind.
    #[error("{count} point(s) given, a {kind} path needs at least {min}")]
    TooFewPoints {
        /// Number of points given.
        count: usize,
        /// Minimum number of points.
        min: usize,
        /// `"open"` or `"closed"`.
        kind: &'static str,
    },
    /// A point or normal has a non-finite coordinate.
    #[error("point {index}: non-finite coordinate in point or normal")]
    NonFinite {
        /// Index of the offending point.
        index: usize,
    },
    /// A normal is (nearly) the zero vector.
    #[error("point {index}: normal has length {norm:e}, below {min:e}")]
    ZeroNormal {
        /// Index of the offending point.
        index: usize,
        /// Length of the given normal.
        norm: f64,
        /// Smallest accepted length.
        min: f64,
    },
    /// Two consecutive offset points (ball centres) coincide.
    #[error(
        "points {index} and {next}: offset points {distance_mm:e} mm apart, below {min_mm:e} mm"
    )]
    CoincidentPoints {
        /// Index of the first point.
        index: usize,
        /// Index of the following point (0 for the closing chord).
        next: usize,
        /// Distance between the two offset points, mm.
        distance_mm: f64,
        /// Smallest accepted chord, mm.
        min_mm: f64,
    },
    /// The offset distance is not finite.
    #[error("offset {offset_mm} mm is not finite")]
    NonFiniteOffset {
        /// The offset given, mm.
        offset_mm: f64,
    },
    /// A query point or parameter is not finite.
    #[error("query has a non-finite coordinate or parameter")]
    NonFiniteQuery,
}
