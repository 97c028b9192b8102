//! Motion traces (`--trace FILE.csv`): every control cycle's time, scale
//! positions, commanded and actual velocity, deflection reading and, during
//! active scanning, the trajectory error. Recorded at the seam, so it shows
//! exactly what the measuring software commanded and saw.
use super::observe::{Observe, Phase};
use crate::math::{Point3, Vec3};
use crate::seam::{Cmm, HeadCommandError, Readings};

/// One control cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceRow {
    /// Machine time, s.
    pub t: f64,
    /// Scale positions X, Y, Z, mm.
    pub scales: Point3,
    /// Commanded velocity, mm/s.
    pub commanded: Vec3,
    /// Actual velocity from the scales, mm/s.
    pub actual: Vec3,
    /// Deflection reading, mm.
    pub deflection: Vec3,
    /// Trajectory error dL, mm (NaN outside active scanning).
    pub dl: f64,
    /// What the software was doing.
    pub phase: Phase,
}

/// A [`Cmm`] that records every cycle of the machine it wraps (of a type
/// known at compile time, or `dyn Cmm`: the simulator's step then inlines
/// into this one, without a second virtual call and copy of the readings).
pub struct TracingCmm<'a, C: Cmm + ?Sized> {
    inner: &'a mut C,
    rows: Vec<TraceRow>,
    enabled: bool,
    phase: Phase,
}

impl<'a, C: Cmm + ?Sized> TracingCmm<'a, C> {
    /// Wraps `inner`; records only when `enabled`.
    pub fn new(inner: &'a mut C, enabled: bool) -> TracingCmm<'a, C> {
        TracingCmm {
            inner,
            rows: Vec::new(),
            enabled,
            phase: Phase::Idle,
        }
    }

    /// The recorded rows.
    pub fn into_rows(self) -> Vec<TraceRow> {
        self.rows
    }
}

impl<C: Cmm + ?Sized> Cmm for TracingCmm<'_, C> {
    fn cycle_s(&self) -> f64 {
        self.inner.cycle_s()
    }

    fn readings(&self) -> Readings {
        self.inner.readings()
    }

    fn step(&mut self, velocity: Vec3) -> Readings {
        // Only a trace needs the readings before the step.
        let before = self.enabled.then(|| self.inner.readings());
        let now = self.inner.step(velocity);
        if let Some(before) = before {
            let dt = (now.time_s - before.time_s).max(f64::MIN_POSITIVE);
            self.rows.push(TraceRow {
                t: now.time_s,
                scales: now.scales,
                commanded: velocity,
                actual: (now.scales - before.scales) / dt,
                deflection: now.deflection,
                dl: f64::NAN,
                phase: self.phase,
            });
        }
        now
    }

    fn head_axes(&self) -> usize {
        self.inner.head_axes()
    }

    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        self.inner.index_head(angles_rad)
    }
}

impl<C: Cmm + ?Sized> Observe for TracingCmm<'_, C> {
    fn note_trajectory_error(&mut self, dl: f64) {
        if let Some(last) = self.rows.last_mut() {
            last.dl = dl;
        }
    }

    fn note_phase(&mut self, phase: Phase) {
        self.phase = phase;
    }

    fn note_contact(&mut self, phase: Phase) {
        let approach = self.phase;
        let touching = |r: &&mut TraceRow| r.phase == approach && r.deflection != Vec3::zeros();
        for r in self.rows.iter_mut().rev().take_while(touching) {
            r.phase = phase;
        }
        self.phase = phase;
    }
}

/// Header of the trace CSV.
pub const TRACE_HEADER: &str =
    "t_s,x_mm,y_mm,z_mm,vx_cmd,vy_cmd,vz_cmd,vx,vy,vz,dx_mm,dy_mm,dz_mm,dl_mm,phase";

/// The trace as CSV (shortest exact decimal numbers; empty `dl_mm` where
/// no trajectory error applies; `phase` names what the software was doing).
pub fn trace_csv(rows: &[TraceRow]) -> String {
    let mut out = String::with_capacity(rows.len() * 160 + 100);
    out.push_str(TRACE_HEADER);
    out.push('\n');
    for r in rows {
        let dl = if r.dl.is_finite() {
            r.dl.to_string()
        } else {
            String::new()
        };
        let cols = [
            r.t,
            r.scales.x,
            r.scales.y,
            r.scales.z,
            r.commanded.x,
            r.commanded.y,
            r.commanded.z,
        ];
        let more = [
            r.actual.x,
            r.actual.y,
            r.actual.z,
            r.deflection.x,
            r.deflection.y,
            r.deflection.z,
        ];
        for v in cols.iter().chain(&more) {
            out.push_str(&v.to_string());
            out.push(',');
        }
        out.push_str(&dl);
        out.push(',');
        out.push_str(r.phase.name());
        out.push('\n');
    }
    out
}

/// Machine time per phase, s, in the order of [`Phase::ALL`].
pub fn time_by_phase(rows: &[TraceRow]) -> [(Phase, f64); 7] {
    let mut out = Phase::ALL.map(|p| (p, 0.0));
    let mut before = 0.0;
    for r in rows {
        if let Some(slot) = out.iter_mut().find(|(p, _)| *p == r.phase) {
            slot.1 += r.t - before;
        }
        before = r.t;
    }
    out
}
