//! Inspection: measures a validated part program's features on a machine
//! (behind the [`crate::seam::Cmm`] seam), feature by feature.
//!
//! The supervisor ([`supervisor`]) is the method of JP6484108B2: active
//! design-value scanning with geometric and autonomous corrections.

pub mod align;
pub mod align_weak;
pub mod clearance;
pub mod corners;
pub mod correction;
pub mod design_memo;
pub mod feature;
pub mod learned;
pub mod moved;
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

impl CurveCtx<'_> {
    /// This context with the free space `free` in place of its own.
    pub fn with_free<'d>(&'d mut self, free: Option<&'d dyn FreeSpace>) -> CurveCtx<'d> {
        CurveCtx {
            cmm: &mut *self.cmm,
            probe: self.probe,
            pose: self.pose,
            plane_normal: self.plane_normal,
            settings: self.settings,
            modes: self.modes,
            supervisor: self.supervisor,
            learned: self.learned.clone(),
            free,
        }
    }
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

    /// The rigid part of the correction (part frame, see
    /// [`Correction::rigid`]); `None` for design data replaced.
    pub fn rigid(&self) -> Option<(crate::math::Mat3, Vec3)> {
        match self {
            Learned::Geometric(c) => Some(c.rigid()),
            Learned::Replaced(_) => None,
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
    /// Whether `points` are those a scan measured before it stopped
    /// (a later scan replaces them; a completed scan's stay).
    pub points_before_stop: bool,
}

/// How the note on the points a stopped scan keeps ends (it goes when a
/// later scan replaces them).
const KEPT_NOTE_END: &str = "stop are kept";

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
            // A scan that stopped before its end (the collision stop, a
            // trajectory error, lost contact, over-deflection) keeps what
            // it measured up to the stop until a later scan replaces it
            // (the feature stays incomplete unless one completes); it
            // does not replace the points of a completed scan.
            let stopped = matches!(
                outcome,
                Outcome::Collision
                    | Outcome::TrajectoryError
                    | Outcome::LostContact
                    | Outcome::OverDeflection
            );
            let replaceable = self.points.is_empty() || self.points_before_stop;
            if stopped && !attempt.points.is_empty() && replaceable {
                self.notes.retain(|n| !n.ends_with(KEPT_NOTE_END));
                self.notes.push(format!(
                    "{} points measured before the {} {KEPT_NOTE_END}",
                    attempt.points.len(),
                    crate::formats::serde_name(&outcome).replace('_', " ")
                ));
                self.points = attempt.points;
                self.points_before_stop = true;
            } else if self.complete {
                self.notes.retain(|n| !n.ends_with(KEPT_NOTE_END));
                self.points = attempt.points;
                self.points_before_stop = false;
            }
        }
        outcome
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::modes::{Attempt, Measured};
    use crate::math::{Mat3, Point3, Vec3};

    fn attempt(outcome: Outcome, n: usize) -> Attempt {
        let m = Measured {
            point: Point3::origin(),
            normal: Vec3::z(),
            ball: Point3::origin(),
            scales: Point3::origin(),
            reading: Vec3::zeros(),
            motion: Vec3::zeros(),
        };
        Attempt {
            outcome,
            points: vec![m; n],
            machine_time_s: 1.0,
            max_trajectory_error_mm: 0.0,
            collision: None,
        }
    }

    /// A scan that stops before its end keeps its points, with a note,
    /// until a later scan replaces them: a later stop's, or a completed
    /// scan's (whose points leave no note).
    #[test]
    fn a_stopped_scan_keeps_its_points_until_a_later_scan_replaces_them() {
        let pose = Pose {
            rotation: Mat3::identity(),
            translation: Vec3::zeros(),
        };
        let mut res = CurveResult::default();
        res.record(
            AttemptMode::Active,
            attempt(Outcome::TrajectoryError, 513),
            &pose,
        );
        assert!(!res.complete);
        assert_eq!(res.points.len(), 513);
        assert_eq!(
            res.notes,
            ["513 points measured before the trajectory error stop are kept"]
        );
        res.record(
            AttemptMode::Passive,
            attempt(Outcome::LostContact, 40),
            &pose,
        );
        assert_eq!(res.points.len(), 40);
        assert_eq!(
            res.notes,
            ["40 points measured before the lost contact stop are kept"]
        );
        res.record(AttemptMode::Active, attempt(Outcome::Completed, 700), &pose);
        assert!(res.complete);
        assert_eq!(res.points.len(), 700);
        assert!(res.notes.is_empty(), "{:?}", res.notes);
        // A later scan that stops keeps the completed scan's points.
        res.record(
            AttemptMode::Active,
            attempt(Outcome::LostContact, 26),
            &pose,
        );
        assert_eq!(res.points.len(), 700);
        assert!(res.notes.is_empty(), "{:?}", res.notes);
    }
}
