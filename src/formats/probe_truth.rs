//! The simulator's true probe values, written beside a simulated probe
//! calibration (`simulation_truth` in `cmm-probe-cal/1`) for comparison
//! only: plain numbers that the measuring side never reads back.
use crate::math::Vec3;

/// The simulator's true probe values, for comparison only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeTruth {
    /// True probe vector, mm.
    pub probe_vector: Vec3,
    /// True tip radius, mm.
    pub tip_radius_mm: f64,
}

/// The simulator's true probe at one orientation, for comparison only.
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationTruth {
    /// Head angles, deg.
    pub angles_deg: Vec<f64>,
    /// True probe vector (spindle reference point to ball centre), mm.
    pub probe_vector: Vec3,
    /// True tip radius, mm.
    pub tip_radius_mm: f64,
}
