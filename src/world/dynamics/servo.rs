//! The servo loop: per-axis first-order velocity following with velocity and
//! acceleration limits, travel limits, and scale readings.
//!
//! Each control cycle of length `dt` every axis moves its actual velocity `v`
//! towards the commanded velocity `c` (clamped to the axis's speed limit) as a
//! first-order lag with time constant `tau`, sampled exactly:
//! `v' = c + (v - c) exp(-dt/tau)`. The change is then clamped to
//! `+-a_max dt` (so the mean acceleration over every cycle stays within
//! `a_max`). The position integrates the velocity exactly over the cycle:
//! the exponential's integral when the lag was not clamped, the trapezoid
//! (exact for constant acceleration) when it was.
use rand::Rng;

use super::axis_cycle::{advance_axes, AxisCycle};
use crate::machine::{Axis, AxisKind, MachineModel};
use crate::machine::{LinearAxesProfile, MachineProfile, RotaryAxesProfile};
use crate::world::noise::Ziggurat;

/// Resolved dynamics of one axis (mm and s for linear axes, rad and s for
/// rotary ones).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisDynamics {
    /// Axis (joint) name.
    pub name: String,
    /// Lowest allowed position.
    pub lower: f64,
    /// Highest allowed position.
    pub upper: f64,
    /// Speed limit: the smaller of the URDF and the profile limit.
    pub max_velocity: f64,
    /// Acceleration limit, per s^2.
    pub max_acceleration: f64,
    /// First-order lag time constant, s (0 = none).
    pub lag_s: f64,
    /// Scale quantum (0 = continuous).
    pub resolution: f64,
    /// Standard deviation of the scale noise.
    pub noise_sigma: f64,
}

impl AxisDynamics {
    /// Combines an axis's URDF limits with the profile for its kind.
    pub fn for_axis(axis: &Axis, profile: &MachineProfile) -> Self {
        let kind = match axis.kind {
            AxisKind::Prismatic => Self::linear(&profile.linear),
            AxisKind::Revolute => Self::rotary(&profile.rotary),
        };
        Self {
            name: axis.name.clone(),
            lower: axis.limits.lower,
            upper: axis.limits.upper,
            max_velocity: kind.max_velocity.min(axis.limits.velocity),
            ..kind
        }
    }

    /// Profile settings of linear axes (name and travel still unset).
    fn linear(l: &LinearAxesProfile) -> Self {
        Self::unnamed([
            l.max_velocity_mm_s,
            l.max_acceleration_mm_s2,
            l.servo_lag_s,
            l.scale_resolution_mm,
            l.scale_noise_mm,
        ])
    }

    /// Profile settings of rotary axes (name and travel still unset).
    fn rotary(r: &RotaryAxesProfile) -> Self {
        Self::unnamed([
            r.max_velocity_rad_s,
            r.max_acceleration_rad_s2,
            r.servo_lag_s,
            r.scale_resolution_rad,
            r.scale_noise_rad,
        ])
    }

    /// From `[max_velocity, max_acceleration, lag_s, resolution, noise]`.
    fn unnamed([max_velocity, max_acceleration, lag_s, resolution, noise_sigma]: [f64; 5]) -> Self {
        let (name, lower, upper) = (String::new(), 0.0, 0.0);
        Self {
            name,
            lower,
            upper,
            max_velocity,
            max_acceleration,
            lag_s,
            resolution,
            noise_sigma,
        }
    }

    /// The lag's velocity decay over one cycle of `dt` s, `exp(-dt / lag)`
    /// (0 without lag).
    fn decay(&self, dt: f64) -> f64 {
        if self.lag_s > 0.0 {
            (-dt / self.lag_s).exp()
        } else {
            0.0
        }
    }
}

/// True axis positions and velocities at one instant (chain order).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisState {
    /// Machine time since the servo started, s.
    pub time_s: f64,
    /// Actual positions, mm or rad.
    pub position: Vec<f64>,
    /// Actual velocities, mm/s or rad/s.
    pub velocity: Vec<f64>,
}

/// Why a servo cycle did not complete normally.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ServoError {
    /// An axis left (or would start outside) its travel range. The machine
    /// halts: every velocity is zeroed and the axis is held at its limit.
    #[error("axis '{axis}' (index {index}) at {position} is outside its travel {lower}..{upper}")]
    AxisLimit {
        /// Axis name.
        axis: String,
        /// Axis index in chain order.
        index: usize,
        /// The position it reached, mm or rad.
        position: f64,
        /// Lower travel limit, mm or rad.
        lower: f64,
        /// Upper travel limit, mm or rad.
        upper: f64,
    },
    /// A command or start vector of the wrong length.
    #[error("expected {expected} axis values, found {found}")]
    AxisCount {
        /// Number of axes.
        expected: usize,
        /// Number given.
        found: usize,
    },
    /// A commanded velocity that is NaN or infinite.
    #[error("commanded velocity {value} for axis index {index} is not finite")]
    NotFinite {
        /// Axis index.
        index: usize,
        /// The value.
        value: f64,
    },
}

/// The machine's axes in motion, one control cycle at a time.
#[derive(Debug, Clone)]
pub struct Servo {
    axes: Vec<AxisDynamics>,
    /// Each axis's constants over one cycle (computed once).
    cycles: Vec<AxisCycle>,
    position: Vec<f64>,
    velocity: Vec<f64>,
    cycle_s: f64,
    time_s: f64,
}

impl Servo {
    /// A servo at rest at `start` (chain order, mm or rad).
    pub fn new(
        model: &MachineModel,
        profile: &MachineProfile,
        start: &[f64],
    ) -> Result<Self, ServoError> {
        let axes: Vec<_> = model
            .axes()
            .iter()
            .map(|a| AxisDynamics::for_axis(a, profile))
            .collect();
        check_count(axes.len(), start.len())?;
        let dt = profile.control_cycle_s;
        let cycles = axes
            .iter()
            .map(|a| AxisCycle::new(a, dt, a.decay(dt)))
            .collect();
        let servo = Self {
            cycles,
            velocity: vec![0.0; axes.len()],
            position: start.to_vec(),
            axes,
            cycle_s: profile.control_cycle_s,
            time_s: 0.0,
        };
        match servo.first_outside() {
            Some(err) => Err(err),
            None => Ok(servo),
        }
    }

    /// Resolved per-axis dynamics, chain order.
    pub fn axes(&self) -> &[AxisDynamics] {
        &self.axes
    }

    /// The control cycle, s.
    pub fn cycle_s(&self) -> f64 {
        self.cycle_s
    }

    /// The true state now.
    pub fn state(&self) -> AxisState {
        AxisState {
            time_s: self.time_s,
            position: self.position.clone(),
            velocity: self.velocity.clone(),
        }
    }

    /// Advances one control cycle with the commanded velocities (mm/s or
    /// rad/s, chain order). Leaving the travel range halts the machine and
    /// returns [`ServoError::AxisLimit`].
    pub fn step(&mut self, commanded_velocity: &[f64]) -> Result<AxisState, ServoError> {
        self.advance(commanded_velocity)?;
        Ok(self.state())
    }

    /// [`Self::step`] without returning (copying) the new state.
    pub fn advance(&mut self, commanded_velocity: &[f64]) -> Result<(), ServoError> {
        check_count(self.axes.len(), commanded_velocity.len())?;
        check_finite(commanded_velocity)?;
        let inside = advance_axes(
            &self.cycles,
            &mut self.position,
            &mut self.velocity,
            commanded_velocity,
        );
        self.time_s += self.cycle_s;
        if inside {
            return Ok(());
        }
        match self.first_outside() {
            Some(err) => Err(self.halt(err)),
            None => Ok(()),
        }
    }

    /// True axis positions now (chain order, mm or rad).
    pub fn position(&self) -> &[f64] {
        &self.position
    }

    /// True axis velocities now (chain order, mm/s or rad/s).
    pub fn velocity(&self) -> &[f64] {
        &self.velocity
    }

    /// Machine time since the start, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// Indexes axes to fixed positions and locks them there (a probe head
    /// that turns to an orientation and clamps): `targets` are (axis index,
    /// position) pairs, mm or rad. The axes arrive at rest; the machine time
    /// advances by the longest move at its axis's speed limit. A target
    /// outside an axis's travel (or a wrong index) changes nothing and is
    /// returned as an error.
    pub fn index_to(&mut self, targets: &[(usize, f64)]) -> Result<AxisState, ServoError> {
        let mut longest_s: f64 = 0.0;
        for &(index, target) in targets {
            let axis = self.axes.get(index).ok_or(ServoError::AxisCount {
                expected: self.axes.len(),
                found: index + 1,
            })?;
            if !target.is_finite() {
                return Err(ServoError::NotFinite {
                    index,
                    value: target,
                });
            }
            if !(axis.lower..=axis.upper).contains(&target) {
                return Err(ServoError::AxisLimit {
                    axis: axis.name.clone(),
                    index,
                    position: target,
                    lower: axis.lower,
                    upper: axis.upper,
                });
            }
            let from = self.position.get(index).copied().unwrap_or(target);
            longest_s = longest_s.max((target - from).abs() / axis.max_velocity.max(1e-12));
        }
        for &(index, target) in targets {
            if let (Some(p), Some(v)) = (self.position.get_mut(index), self.velocity.get_mut(index))
            {
                (*p, *v) = (target, 0.0);
            }
        }
        self.time_s += longest_s;
        Ok(self.state())
    }

    /// Scale readings of the current positions (quantised, with noise drawn
    /// from `rng` in axis order; an ideal profile draws nothing).
    pub fn read_scales(&self, rng: &mut impl Rng) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.axes.len());
        self.read_scales_into(rng, &mut out);
        out
    }

    /// [`Self::read_scales`] into a reused buffer (overwritten with one
    /// value per axis).
    #[inline(always)]
    pub fn read_scales_into(&self, rng: &mut impl Rng, out: &mut Vec<f64>) {
        out.resize(self.axes.len(), 0.0);
        let normal = Ziggurat::new();
        // Three axes without a loop (the draws in axis order all the same).
        if let ([a, b, c], [pa, pb, pc], [oa, ob, oc]) = (
            self.axes.as_slice(),
            self.position.as_slice(),
            out.as_mut_slice(),
        ) {
            *oa = a.read(*pa, rng, normal);
            *ob = b.read(*pb, rng, normal);
            *oc = c.read(*pc, rng, normal);
            return;
        }
        let pairs = self.axes.iter().zip(&self.position);
        for (o, (axis, p)) in out.iter_mut().zip(pairs) {
            *o = axis.read(*p, rng, normal);
        }
    }

    /// The first axis outside its travel, as an error.
    fn first_outside(&self) -> Option<ServoError> {
        let mut pairs = self.axes.iter().zip(&self.position).enumerate();
        let (index, (axis, &position)) =
            pairs.find(|(_, (a, p))| !(a.lower..=a.upper).contains(*p))?;
        let (axis, lower, upper) = (axis.name.clone(), axis.lower, axis.upper);
        Some(ServoError::AxisLimit {
            axis,
            index,
            position,
            lower,
            upper,
        })
    }

    /// Stops every axis and holds each inside its travel.
    fn halt(&mut self, err: ServoError) -> ServoError {
        self.velocity.iter_mut().for_each(|v| *v = 0.0);
        for (p, axis) in self.position.iter_mut().zip(&self.axes) {
            *p = p.clamp(axis.lower, axis.upper);
        }
        err
    }
}

fn check_count(expected: usize, found: usize) -> Result<(), ServoError> {
    if expected == found {
        Ok(())
    } else {
        Err(ServoError::AxisCount { expected, found })
    }
}

fn check_finite(values: &[f64]) -> Result<(), ServoError> {
    // `v * 0` is NaN exactly when `v` is infinite or NaN (and a signed
    // zero otherwise): one test for all values in the common case, without
    // a loop for three axes.
    let all_finite = match values {
        [a, b, c] => a * 0.0 + b * 0.0 + c * 0.0 == 0.0,
        _ => values.iter().fold(0.0, |acc, &v| acc + v * 0.0) == 0.0,
    };
    if all_finite {
        return Ok(());
    }
    match values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((index, &value)) => Err(ServoError::NotFinite { index, value }),
        None => Ok(()),
    }
}
