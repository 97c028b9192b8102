//! What the measuring software notes about its own work while it drives a
//! machine: the phase it is in and, during active scanning, the trajectory
//! error. Observers (a motion trace) wrap a [`Cmm`] and implement
//! [`Observe`]; the measuring modes drive any [`Machine`] (a `Cmm` that can
//! be told these notes).
use crate::seam::Cmm;

/// Notes the measuring software gives whoever watches it; the default
/// methods ignore them.
pub trait Observe {
    /// The software's current trajectory error, mm.
    fn note_trajectory_error(&mut self, _dl_mm: f64) {}
    /// What the software is doing from the next cycle on.
    fn note_phase(&mut self, _phase: Phase) {}
    /// The last cycle read the ball on the surface, and the approach turns
    /// into the measuring move `phase` it starts: the approach's cycles
    /// since the ball first read a deflection and the next ones belong to
    /// it.
    fn note_contact(&mut self, phase: Phase) {
        self.note_phase(phase);
    }
}

/// A machine as the measuring modes drive it: a [`Cmm`] that takes the
/// software's notes.
pub trait Machine: Cmm + Observe {}

impl<T: Cmm + Observe + ?Sized> Machine for T {}

/// A [`Cmm`] driven without an observer: every note is dropped.
pub struct Unobserved<'a, C: Cmm + ?Sized>(pub &'a mut C);

impl<C: Cmm + ?Sized> Observe for Unobserved<'_, C> {}

impl<C: Cmm + ?Sized> Cmm for Unobserved<'_, C> {
    fn cycle_s(&self) -> f64 {
        self.0.cycle_s()
    }

    fn readings(&self) -> crate::seam::Readings {
        self.0.readings()
    }

    fn step(&mut self, velocity: crate::math::Vec3) -> crate::seam::Readings {
        self.0.step(velocity)
    }

    fn head_axes(&self) -> usize {
        self.0.head_axes()
    }

    fn index_head(
        &mut self,
        angles_rad: &[f64],
    ) -> Result<Vec<f64>, crate::seam::HeadCommandError> {
        self.0.index_head(angles_rad)
    }
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
