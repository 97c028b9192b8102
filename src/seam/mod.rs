//! The seam between the measuring software and a machine: a commanded
//! ball-centre velocity goes in every control cycle, readings come out.
//!
//! This module depends on math types only. The simulator implements
//! [`Cmm`] (`world::cmm::SimulatedCmm`); a real machine (e.g. over
//! I++ DME) can implement it the same way. Whoever watches the measuring
//! (a motion trace) wraps a `Cmm` on the host side; watching is no part of
//! the machine.
use crate::math::{Point3, Vec3};

/// Machine state as the software sees it after a control cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum MachineStatus {
    /// Moving normally.
    Ok,
    /// An axis reached its travel limit; the machine halted.
    AxisLimit {
        /// Axis name.
        axis: String,
        /// Where it stopped, mm.
        position: f64,
    },
    /// The stylus was pushed past its mechanical range; the machine halted.
    ProbeOverrange {
        /// Deflection magnitude reached, mm.
        deflection_mm: f64,
    },
    /// A part of the probe other than the stylus ball struck the part (the
    /// probe's crash protection); the machine halted.
    Collision {
        /// Which part of the probe.
        probe_part: ProbePart,
        /// Where the contact is, machine coordinates, mm.
        at: Point3,
        /// Speed of the probe mount when it struck, mm/s.
        speed_mm_s: f64,
    },
}

/// The parts of a probe that can strike a workpiece.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProbePart {
    /// The stylus ball.
    Ball,
    /// The stylus shaft between the ball and the probe.
    Shaft,
    /// The probe body above the stylus.
    Body,
}

impl ProbePart {
    /// Lower-case name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            ProbePart::Ball => "ball",
            ProbePart::Shaft => "shaft",
            ProbePart::Body => "body",
        }
    }
}

/// What the machine reports each control cycle (machine coordinates, mm).
#[derive(Debug, Clone, PartialEq)]
pub struct Readings {
    /// Machine time, s.
    pub time_s: f64,
    /// Scale readings of the X, Y, Z axes (the probe mount), mm.
    pub scales: Point3,
    /// Probe deflection reading, mm (how far the ball is pushed, as sensed).
    pub deflection: Vec3,
    /// Status.
    pub status: MachineStatus,
}

/// A CMM driven one control cycle at a time.
pub trait Cmm {
    /// Control cycle, s.
    fn cycle_s(&self) -> f64;
    /// The readings now, without moving.
    fn readings(&self) -> Readings;
    /// Commands the ball-centre velocity (mm/s, machine axes) for one cycle
    /// and returns the readings at its end.
    fn step(&mut self, velocity: Vec3) -> Readings;
    /// Number of probe-head axes (0: no head).
    fn head_axes(&self) -> usize {
        0
    }
    /// Turns an indexing probe head to `angles_rad` (one per head axis, in
    /// the machine's chain order), locks it and returns the head's encoder
    /// readings, rad. The linear axes stay where they are, so the ball
    /// moves with the head: the caller first brings it to free air.
    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        let _ = angles_rad;
        Err(HeadCommandError::NoHead)
    }
}

/// Why a head orientation command was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HeadCommandError {
    /// The machine has no probe head.
    #[error("the machine has no probe head")]
    NoHead,
    /// Wrong number of angles.
    #[error("the head has {expected} axes, {found} angles were given")]
    Count {
        /// Head axes.
        expected: usize,
        /// Angles given.
        found: usize,
    },
    /// An angle outside the axis's travel (or not finite).
    #[error("head axis '{axis}': {angle_rad} rad is outside its travel {lower}..{upper} rad")]
    Travel {
        /// Axis name.
        axis: String,
        /// The angle commanded, rad.
        angle_rad: f64,
        /// Lowest angle, rad.
        lower: f64,
        /// Highest angle, rad.
        upper: f64,
    },
}
