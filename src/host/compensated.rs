//! A machine whose scale readings the measuring software corrects by its
//! geometric error map (CAA): every reading's scales are moved by the
//! map's error at the stylus tip for the host's probe vector, so that
//! `scales + P` is the corrected undeflected ball centre. The modes then
//! measure and steer in the corrected frame; the commanded velocities go
//! to the machine unchanged (the error's gradient, a few micrometres per
//! metre, is far inside what the modes' feedback corrects every cycle).
use super::compensation::ErrorMap;
use super::observe::{Observe, Phase};
use crate::math::Vec3;
use crate::seam::{Cmm, HeadCommandError, Readings};

/// A [`Cmm`] (and observer) seen through the error map `map` for the probe
/// vector `probe_vector` (machine coordinates, mm).
pub struct Compensated<'a, C: ?Sized> {
    inner: &'a mut C,
    /// The map, `None` when it corrects nothing (decided once, not every
    /// cycle).
    map: Option<&'a ErrorMap>,
    probe_vector: Vec3,
}

impl<'a, C: ?Sized> Compensated<'a, C> {
    /// `inner` seen through `map` for the probe vector `probe_vector`.
    pub fn new(inner: &'a mut C, map: &'a ErrorMap, probe_vector: Vec3) -> Self {
        Compensated {
            inner,
            map: (!map.is_zero()).then_some(map),
            probe_vector,
        }
    }

    fn correct(&self, mut r: Readings) -> Readings {
        if let Some(map) = self.map {
            r.scales = map.compensate(r.scales, &self.probe_vector);
        }
        r
    }
}

impl<C: Cmm + ?Sized> Cmm for Compensated<'_, C> {
    fn cycle_s(&self) -> f64 {
        self.inner.cycle_s()
    }

    fn readings(&self) -> Readings {
        self.correct(self.inner.readings())
    }

    fn step(&mut self, velocity: Vec3) -> Readings {
        let r = self.inner.step(velocity);
        self.correct(r)
    }

    fn head_axes(&self) -> usize {
        self.inner.head_axes()
    }

    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        self.inner.index_head(angles_rad)
    }
}

impl<C: Observe + ?Sized> Observe for Compensated<'_, C> {
    fn note_trajectory_error(&mut self, dl_mm: f64) {
        self.inner.note_trajectory_error(dl_mm);
    }

    fn note_phase(&mut self, phase: Phase) {
        self.inner.note_phase(phase);
    }

    fn note_contact(&mut self, phase: Phase) {
        self.inner.note_contact(phase);
    }
}
