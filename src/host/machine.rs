//! The seam between the measuring software and a machine: a commanded
//! ball-centre velocity goes in every control cycle, readings come out. The
//! simulator implements it ([`crate::world::cmm::SimulatedCmm`]); a real
//! machine (e.g. over I++ DME) could later.
use crate::host::modes::Measured;
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
    /// The software's current trajectory error, for traces; machines that
    /// keep no trace ignore it.
    fn note_trajectory_error(&mut self, _dl_mm: f64) {}
    /// What the software is doing from the next cycle on, for traces;
    /// machines that keep no trace ignore it.
    fn note_phase(&mut self, _phase: Phase) {}
    /// A point the software has just taken (a scan's measured points, in
    /// order), for whoever watches the measuring (a live evaluation, a
    /// trace); machines ignore it.
    fn note_point(&mut self, _point: &Measured) {}
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

/// What the measuring software is doing, as recorded in motion traces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Phase {
    /// Not said (before the first note).
    #[default]
    Idle,
    /// Positioning in free air.
    Position,
    /// Backing the stylus off the surface.
    Retract,
    /// Approaching the surface to start a scan.
    Approach,
    /// Approaching the surface for a touch point.
    Touch,
    /// Design-value scanning (passive or active).
    Scan,
    /// Autonomous scanning.
    Autonomous,
}

impl Phase {
    /// Every phase, in the order of [`Phase::name`] tables.
    pub const ALL: [Phase; 7] = [
        Phase::Idle,
        Phase::Position,
        Phase::Retract,
        Phase::Approach,
        Phase::Touch,
        Phase::Scan,
        Phase::Autonomous,
    ];

    /// Lower-case name used in trace files.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Idle => "idle",
            Phase::Position => "position",
            Phase::Retract => "retract",
            Phase::Approach => "approach",
            Phase::Touch => "touch",
            Phase::Scan => "scan",
            Phase::Autonomous => "autonomous",
        }
    }
}
