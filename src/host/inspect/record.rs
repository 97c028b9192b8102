//! What the measuring records of each feature: its attempts, the
//! corrections made between them, and the alignment.
use serde::Serialize;

use crate::host::modes::{Collision, MoveStop, Outcome};
use crate::program::Pose;

/// What kind of feature was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureKind {
    /// A section scan.
    SectionScan,
    /// Touch points.
    TouchPoints,
}

/// How an attempt measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AttemptMode {
    /// Active design-value scanning.
    Active,
    /// Passive design-value scanning.
    Passive,
    /// Autonomous scanning.
    Autonomous,
    /// Touch points.
    Points,
}

impl AttemptMode {
    /// Whether the attempt is a scan (its points are a curve's points).
    pub fn is_scan(self) -> bool {
        self != AttemptMode::Points
    }
}

/// One measuring attempt of a feature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttemptReport {
    /// How the attempt measured.
    pub mode: AttemptMode,
    /// `completed`, `trajectory_error`, `lost_contact`, `over_deflection`,
    /// `axis_limit`, `collision` or `aborted`.
    pub outcome: Outcome,
    /// Machine time of the attempt, s.
    pub machine_time_s: f64,
    /// Points measured in it.
    pub points: usize,
    /// Largest |trajectory error| seen, mm.
    pub max_trajectory_error_mm: f64,
    /// Where the probe struck the part (outcome `collision`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionReport>,
}

/// Where and how the probe struck the part, as reported.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CollisionReport {
    /// `ball`, `shaft` or `body`.
    pub probe_part: &'static str,
    /// Where, part coordinates, mm.
    pub at_mm: [f64; 3],
    /// Speed when it struck, mm/s.
    pub speed_mm_s: f64,
    /// What the software was doing (`position`, `retract`, `scan`, ...).
    pub phase: &'static str,
}

impl CollisionReport {
    /// The report of `c` (machine coordinates) on a part placed by `pose`.
    pub fn new(c: &Collision, pose: &Pose) -> CollisionReport {
        CollisionReport {
            probe_part: c.probe_part.name(),
            at_mm: pose.to_part(c.at).into(),
            speed_mm_s: c.speed_mm_s,
            phase: c.phase.name(),
        }
    }
}

/// The move that ends a program: the stylus freed from the part and the
/// probe up at the clearance height, at rest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EndMoveReport {
    /// `completed`, or why the move stopped short (`collision`, ...).
    pub outcome: Outcome,
    /// Machine time of the move, s.
    pub machine_time_s: f64,
    /// Where the probe struck the part (outcome `collision`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionReport>,
}

impl EndMoveReport {
    /// The report of the end move that ended as `result` after
    /// `machine_time_s`, on a part placed by `pose`.
    pub fn new(result: Result<(), MoveStop>, machine_time_s: f64, pose: &Pose) -> EndMoveReport {
        let (outcome, collision) = match result {
            Ok(()) => (Outcome::Completed, None),
            Err(stop) => (stop.outcome, stop.collision),
        };
        EndMoveReport {
            outcome,
            machine_time_s,
            collision: collision.map(|c| CollisionReport::new(&c, pose)),
        }
    }
}

/// A correction of the feature's design data between attempts.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum CorrectionReport {
    /// A simple model fitted to touch points.
    Geometric {
        /// `translation`, `rotation`, `uniform_scale`, ... (simplest that fits).
        model: String,
        /// Largest residual of the touch points after the correction, mm.
        max_residual_mm: f64,
        /// Touch points used.
        points: usize,
        /// Where it came from: `fitted` now or `learned` from earlier parts.
        source: &'static str,
    },
    /// The section's design data replaced by an autonomous scan.
    Autonomous {
        /// Surface points the new design data was built from.
        points: usize,
    },
}

/// Result of the best-fit alignment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AlignmentReport {
    /// Touch points used.
    pub points: usize,
    /// RMS distance of the touch points from the design data after the fit, mm.
    pub rms_mm: f64,
    /// Largest such distance, mm.
    pub max_mm: f64,
    /// Gauss-Newton iterations.
    pub iterations: usize,
    /// Machine time of the alignment, s.
    pub machine_time_s: f64,
    /// How the alignment's touch points ended when it failed (the
    /// features were then measured at the nominal placement and the run is
    /// incomplete); absent when it succeeded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<crate::host::modes::Outcome>,
    /// Which alignment point could not be measured (0-based), when it
    /// failed; `points` were measured before it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed_point: Option<usize>,
    /// Where the probe struck the part, when the alignment ended in a
    /// collision (as an attempt's `collision`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionReport>,
    /// What the alignment points leave undetermined (a turn about an axis
    /// every point's surface is round about), one note each.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}
