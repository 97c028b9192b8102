//! The inspection report (`cmm-report/1`, DESIGN.md 6.3): the data every
//! writer renders. Field order is the JSON key order; output is
//! deterministic for the same inputs and seed (apart from `wall_time_s`).
use serde::Serialize;

/// Format tag of `report.json`.
pub const REPORT_FORMAT: &str = "cmm-report/1";

/// Pass, fail or incomplete (a part, a feature).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Everything measured and in tolerance.
    Pass,
    /// Measured, some deviation out of tolerance.
    Fail,
    /// A measurement could not be completed even after all fallbacks.
    Incomplete,
}

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

/// One measuring attempt of a feature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttemptReport {
    /// `active`, `passive`, `autonomous` or `points`.
    pub mode: &'static str,
    /// `completed`, `trajectory_error`, `lost_contact`, `over_deflection`,
    /// `axis_limit` or `aborted`.
    pub outcome: crate::host::modes::Outcome,
    /// Machine time of the attempt, s.
    pub machine_time_s: f64,
    /// Points measured in it.
    pub points: usize,
    /// Largest |trajectory error| seen, mm.
    pub max_trajectory_error_mm: f64,
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

/// Deviation statistics, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stats {
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
    /// Mean.
    pub mean: f64,
    /// Root mean square.
    pub rms: f64,
}

/// Allowed deviation band, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// Lower limit.
    pub lower: f64,
    /// Upper limit.
    pub upper: f64,
}

/// One reported point (part coordinates).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointReport {
    /// Measured surface point.
    pub measured: [f64; 3],
    /// Closest nominal point.
    pub nominal: [f64; 3],
    /// Outward unit normal there.
    pub normal: [f64; 3],
    /// Signed distance measured - nominal along the normal, mm.
    pub deviation_mm: f64,
    /// The same for the true surface point nearest the measured one, mm.
    pub true_deviation_mm: f64,
}

/// One feature's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeatureReport {
    /// Name.
    pub name: String,
    /// `section_scan` or `touch_points`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// Verdict.
    pub status: Verdict,
    /// Attempts in order.
    pub attempts: Vec<AttemptReport>,
    /// Corrections in order.
    pub corrections: Vec<CorrectionReport>,
    /// Statistics of `deviation_mm` over the points (zeros when none).
    pub deviation_mm: Stats,
    /// The tolerance band.
    pub tolerance_mm: Tolerance,
    /// Human-readable notes (why incomplete, what was corrected).
    pub notes: Vec<String>,
    /// The fitted element, when the feature asks for one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<crate::inspect::fitted::FitResult>,
    /// The points.
    pub points: Vec<PointReport>,
}

impl Stats {
    /// Statistics of a set of values (zeros for none).
    pub fn of(values: impl Iterator<Item = f64> + Clone) -> Stats {
        let n = values.clone().count();
        if n == 0 {
            return Stats {
                min: 0.0,
                max: 0.0,
                mean: 0.0,
                rms: 0.0,
            };
        }
        let min = values.clone().fold(f64::INFINITY, f64::min);
        let max = values.clone().fold(f64::NEG_INFINITY, f64::max);
        let mean = values.clone().sum::<f64>() / n as f64;
        let rms = (values.map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        Stats {
            min,
            max,
            mean,
            rms,
        }
    }
}
