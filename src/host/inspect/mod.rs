//! Inspection: measures a validated part program's features on a machine
//! (behind the [`crate::seam::Cmm`] seam), feature by feature.
//!
//! The supervisor ([`supervisor`]) is the method of JP6484108B2: active
//! design-value scanning with geometric and autonomous corrections.

pub mod align;
pub mod clearance;
pub mod corners;
pub mod correction;
pub mod design_memo;
pub mod feature;
pub mod learned;
pub mod prepared;
pub mod reach;
pub mod record;
pub mod supervisor;

use correction::{Correction, DesignPoint};
use supervisor::SupervisorOptions;

use crate::host::modes::{Attempt, FreeSpace, HostProbe, Measured, ModeOptions, Outcome};
use crate::host::observe::Machine;
use crate::math::Vec3;
use crate::program::{Pose, ScanSettings};
use record::{AttemptMode, AttemptReport, CollisionReport, CorrectionReport};

/// What one feature's measurement needs.
pub struct CurveCtx<'c> {
    /// The machine.
    pub cmm: &'c mut dyn Machine,
    /// Probe as the host knows it.
    pub probe: HostProbe,
    /// Part to machine.
    pub pose: Pose,
    /// Section plane normal (part frame).
    pub plane_normal: Vec3,
    /// Scan parameters.
    pub settings: ScanSettings,
    /// Mode gains and thresholds.
    pub modes: ModeOptions,
    /// Supervisor limits.
    pub supervisor: SupervisorOptions,
    /// A correction learned on an earlier part, applied before the first scan.
    pub learned: Option<Learned>,
    /// Free space around the part for direct moves between measurements
    /// (`None`: every move goes over the clearance height).
    pub free: Option<&'c dyn FreeSpace>,
}

/// Corrections learned per (feature name, curve index), carried from part
/// to part.
pub type LearnedSet = Vec<((String, usize), Learned)>;

/// A correction that can be carried to the next part.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", content = "data", rename_all = "snake_case")]
pub enum Learned {
    /// A fitted geometric correction.
    Geometric(Correction),
    /// Design data replaced by an autonomous scan.
    Replaced(Vec<DesignPoint>),
}

impl Learned {
    /// The design data after this correction.
    pub fn apply(&self, design: &[DesignPoint]) -> Vec<DesignPoint> {
        match self {
            Learned::Geometric(c) => design.iter().map(|d| c.apply(d)).collect(),
            Learned::Replaced(pts) => pts.clone(),
        }
    }

    /// How it appears in a report when reused.
    pub fn report(&self) -> CorrectionReport {
        match self {
            Learned::Geometric(c) => CorrectionReport::Geometric {
                model: c.model.name().into(),
                max_residual_mm: c.max_residual_mm,
                points: c.points,
                source: "learned",
            },
            Learned::Replaced(p) => CorrectionReport::Autonomous { points: p.len() },
        }
    }
}

/// Result of measuring one section curve.
#[derive(Debug, Clone, Default)]
pub struct CurveResult {
    /// Attempts in order.
    pub attempts: Vec<AttemptReport>,
    /// Corrections in order.
    pub corrections: Vec<CorrectionReport>,
    /// Points of the last completed scan (machine frame).
    pub points: Vec<Measured>,
    /// Whether the last scan completed.
    pub complete: bool,
    /// Notes for the report.
    pub notes: Vec<String>,
    /// The last correction made (to carry to later parts).
    pub learned: Option<Learned>,
}

impl CurveResult {
    /// Records an attempt; scans (not touch points) set the final points:
    /// a completed scan's, or those a scan measured before a collision.
    pub fn record(&mut self, mode: AttemptMode, attempt: Attempt, pose: &Pose) -> Outcome {
        let outcome = attempt.outcome;
        if outcome == Outcome::Blocked {
            self.notes.push(format!(
                "{} not started: no route to its start is clear of the part",
                crate::formats::serde_name(&mode)
            ));
        }
        self.attempts.push(AttemptReport {
            mode,
            outcome,
            machine_time_s: attempt.machine_time_s,
            points: attempt.points.len(),
            max_trajectory_error_mm: attempt.max_trajectory_error_mm,
            collision: attempt.collision.map(|c| CollisionReport::new(&c, pose)),
        });
        if mode.is_scan() {
            self.complete = outcome == Outcome::Completed;
            // A scan the collision stop ended keeps what it measured up
            // to the strike (the feature stays incomplete).
            if outcome == Outcome::Collision && !attempt.points.is_empty() {
                self.notes.push(format!(
                    "{} points measured before the collision stop are kept",
                    attempt.points.len()
                ));
                self.points = attempt.points;
            } else if self.complete {
                self.points = attempt.points;
            }
        }
        outcome
    }
}
