//! The inspection report (`cmm-report/1`, the cmm-report/1 format): the data every
//! writer renders. Field order is the JSON key order; output is
//! deterministic for the same inputs and seed (apart from `wall_time_s`).
use serde::Serialize;

/// Format tag of `report.json`.
pub const REPORT_FORMAT: &str = "cmm-report/1";

pub use crate::evaluate::model::{FeatureReport, PointReport, Stats, Tolerance, Verdict};
pub use crate::host::inspect::record::{
    AlignmentReport, AttemptMode, AttemptReport, CollisionReport, CorrectionReport, EndMoveReport,
    FeatureKind,
};

/// A whole-part report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Always [`REPORT_FORMAT`].
    pub format: &'static str,
    /// Program name.
    pub program: String,
    /// Random seed of the simulation.
    pub seed: u64,
    /// Overall verdict.
    pub status: Verdict,
    /// Simulated machine time, s.
    pub machine_time_s: f64,
    /// Wall-clock time of the run, s (the only non-deterministic field).
    pub wall_time_s: f64,
    /// Part frame to machine frame (the alignment's result, else the placement).
    pub part_to_machine: PartToMachine,
    /// Whether every simulated error and noise was off (`--ideal`).
    pub ideal: bool,
    /// Probe values the measuring side used and where they came from.
    pub probe: ProbeUsed,
    /// The best-fit alignment, when the program has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alignment: Option<AlignmentReport>,
    /// Features in program order.
    pub features: Vec<FeatureReport>,
    /// The move that ended the program (stylus freed, probe up at the
    /// clearance height).
    pub end_move: EndMoveReport,
}

/// `x_machine = rotation x_part + translation_mm`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartToMachine {
    /// Row-major rotation matrix.
    pub rotation: [[f64; 3]; 3],
    /// Translation, mm.
    pub translation_mm: [f64; 3],
}

/// The probe as the measuring side knew it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeUsed {
    /// `"nominal"` (no calibration file) or the calibration file's path.
    pub source: String,
    /// Tip radius used, mm.
    pub tip_radius_mm: f64,
    /// Probe vector used, mm.
    pub probe_vector_mm: [f64; 3],
}
