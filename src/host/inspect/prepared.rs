//! A scan's plan: its ball-centre path and speed plan, made from the
//! design points in the machine frame, the ball-centre offset, the path
//! and speed options (with the machine's control cycle) and the scan kind.
use super::correction::DesignPoint;
use crate::host::modes::{ScanKind, ScanPlan};
use crate::host::path::{BallPath, PathOptions, SpeedOptions};
use crate::math::{Point3, Vec3};
use crate::program::Pose;

/// Everything a scan's path and speed plan are made from.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanInputs {
    /// Design points (position, outward normal), machine frame.
    pub design: Vec<(Point3, Vec3)>,
    /// Whether the section curve is closed.
    pub closed: bool,
    /// Offset of the ball centre along the normal, `r - Ep`, mm.
    pub offset_mm: f64,
    /// Path construction options.
    pub path: PathOptions,
    /// Speed planning options.
    pub speed: SpeedOptions,
    /// Passive or active.
    pub kind: ScanKind,
}

impl ScanInputs {
    /// The inputs of a scan of `design` (part frame) placed by `pose`.
    pub fn new(
        design: &[DesignPoint],
        pose: &Pose,
        closed: bool,
        offset_mm: f64,
        speed: SpeedOptions,
        kind: ScanKind,
    ) -> ScanInputs {
        let design = (design.iter())
            .map(|d| (pose.to_machine(d.point), pose.dir_to_machine(d.normal)))
            .collect();
        ScanInputs {
            design,
            closed,
            offset_mm,
            path: PathOptions::default(),
            speed,
            kind,
        }
    }
}

/// Why a scan could not be planned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanFailure {
    /// No ball-centre path could be built from the design data.
    Path,
    /// Speed planning failed on the path.
    Speed,
}

impl PlanFailure {
    /// The note a failed attempt carries in the report.
    pub fn note(self) -> &'static str {
        match self {
            PlanFailure::Path => "could not build a scanning path from the design data",
            PlanFailure::Speed => "speed planning failed",
        }
    }
}

/// A scan's path and speed plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedScan {
    /// The ball-centre path (machine frame).
    pub path: BallPath,
    /// What the scan needs of the speed planning.
    pub plan: ScanPlan,
}

impl PreparedScan {
    /// Plans a scan from its inputs.
    pub fn new(inputs: ScanInputs) -> Result<PreparedScan, PlanFailure> {
        let path =
            BallPath::from_section(&inputs.design, inputs.closed, inputs.offset_mm, inputs.path)
                .map_err(|_| PlanFailure::Path)?;
        let plan =
            ScanPlan::new(&path, inputs.kind, &inputs.speed).map_err(|_| PlanFailure::Speed)?;
        Ok(PreparedScan { path, plan })
    }
}

/// Speed options of a scan at `speed_mm_s` from the mode's accelerations
/// (`base`) and the machine's control cycle.
pub fn scan_speed(base: SpeedOptions, speed_mm_s: f64, cycle_s: f64) -> SpeedOptions {
    SpeedOptions {
        speed_mm_s,
        cycle_s,
        ..base
    }
}
