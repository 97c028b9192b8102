//! One axis's servo arithmetic for a fixed control cycle (see
//! [`super::servo`] for the model), with what every cycle would otherwise
//! recompute done once, in a compact record for the per-cycle loop. The
//! numbers are those of the model's formulas as written there, bit for bit.
use super::servo::AxisDynamics;

/// An axis's constants over control cycles of one length `dt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct AxisCycle {
    /// Speed limit.
    max_velocity: f64,
    /// The largest `|target - v|` the lag follows without exceeding the
    /// acceleration limit, `max_acceleration * lag_s`; `-inf` without lag
    /// (never followed).
    lag_reach: f64,
    /// Lag time constant, s.
    lag_s: f64,
    /// The lag's velocity decay over one cycle, `exp(-dt / lag)`.
    decay: f64,
    /// `1 - decay`.
    rest: f64,
    /// The largest velocity change in one cycle, `max_acceleration * dt`.
    max_change: f64,
    /// Cycle length, s.
    dt: f64,
    /// Travel.
    lower: f64,
    upper: f64,
}

impl AxisCycle {
    /// The constants of `axis` for cycles of `dt` s whose lag decay is
    /// `decay`.
    pub(super) fn new(axis: &AxisDynamics, dt: f64, decay: f64) -> AxisCycle {
        let lag_reach = if axis.lag_s > 0.0 {
            axis.max_acceleration * axis.lag_s
        } else {
            f64::NEG_INFINITY
        };
        AxisCycle {
            max_velocity: axis.max_velocity,
            lag_reach,
            lag_s: axis.lag_s,
            decay,
            rest: 1.0 - decay,
            max_change: axis.max_acceleration * dt,
            dt,
            lower: axis.lower,
            upper: axis.upper,
        }
    }

    /// One cycle from `(position, velocity)` under `command`: the new
    /// (position, velocity).
    ///
    /// The lag's acceleration is largest at the start of the cycle,
    /// `|target - v| / lag`. Within the limit the exact exponential is
    /// integrated; beyond it the axis ramps at the limit (trapezoid), so
    /// the acceleration never exceeds the limit at any instant.
    #[inline(always)]
    pub(super) fn advance(&self, position: f64, velocity: f64, command: f64) -> (f64, f64) {
        let target = command.clamp(-self.max_velocity, self.max_velocity);
        let (next, distance) = if (target - velocity).abs() <= self.lag_reach {
            let next = target + (velocity - target) * self.decay;
            let distance = target * self.dt + (velocity - target) * self.lag_s * self.rest;
            (next, distance)
        } else {
            let max_change = self.max_change;
            let next = velocity + (target - velocity).clamp(-max_change, max_change);
            (next, 0.5 * (velocity + next) * self.dt)
        };
        (position + distance, next)
    }

    /// Whether `position` is within the travel.
    #[inline(always)]
    pub(super) fn holds(&self, position: f64) -> bool {
        (self.lower <= position) & (position <= self.upper)
    }
}

/// One cycle of every axis (positions and velocities in place) under
/// `commands`; whether every axis stayed in its travel (the error, when
/// there is one, is looked up afterwards). Three axes without a loop.
#[inline(always)]
pub(super) fn advance_axes(
    cycles: &[AxisCycle],
    position: &mut [f64],
    velocity: &mut [f64],
    commands: &[f64],
) -> bool {
    if let ([a, b, c], [pa, pb, pc], [va, vb, vc], [ca, cb, cc]) =
        (cycles, &mut *position, &mut *velocity, commands)
    {
        (*pa, *va) = a.advance(*pa, *va, *ca);
        (*pb, *vb) = b.advance(*pb, *vb, *cb);
        (*pc, *vc) = c.advance(*pc, *vc, *cc);
        return a.holds(*pa) & b.holds(*pb) & c.holds(*pc);
    }
    let states = position.iter_mut().zip(velocity.iter_mut());
    let mut inside = true;
    for ((axis, (p, v)), c) in cycles.iter().zip(states).zip(commands) {
        (*p, *v) = axis.advance(*p, *v, *c);
        inside &= axis.holds(*p);
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The model's step as first written (per call, from the axis's
    /// dynamics): the reference.
    fn reference(a: &AxisDynamics, p: f64, v: f64, c: f64, dt: f64, decay: f64) -> (f64, f64) {
        let target = c.clamp(-a.max_velocity, a.max_velocity);
        let within = a.lag_s > 0.0 && (target - v).abs() <= a.max_acceleration * a.lag_s;
        let (next, distance) = if within {
            let next = target + (v - target) * decay;
            (next, target * dt + (v - target) * a.lag_s * (1.0 - decay))
        } else {
            let max_change = a.max_acceleration * dt;
            let next = v + (target - v).clamp(-max_change, max_change);
            (next, 0.5 * (v + next) * dt)
        };
        (p + distance, next)
    }

    /// Bit for bit the reference over a seeded sweep of states and
    /// commands (followed by the lag, clamped by the acceleration and the
    /// speed limits), with and without lag.
    #[test]
    fn matches_the_model_step() {
        let mut x: u64 = 0x853c_49e6_748f_ea9b;
        let mut next = |scale: f64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale
        };
        let (mut followed, mut clamped) = (0, 0);
        for lag_s in [0.008, 0.0] {
            let axis = AxisDynamics {
                name: "x".into(),
                lower: -1e3,
                upper: 1e3,
                max_velocity: 500.0,
                max_acceleration: 2000.0,
                lag_s,
                resolution: 1e-4,
                noise_sigma: 0.0,
            };
            let dt = 1e-3;
            let decay = if lag_s > 0.0 {
                (-dt / lag_s).exp()
            } else {
                0.0
            };
            let cycle = AxisCycle::new(&axis, dt, decay);
            for _ in 0..20_000 {
                let (p, v, c) = (next(2e3), next(1.2e3), next(1.4e3));
                let expected = reference(&axis, p, v, c, dt, decay);
                let found = cycle.advance(p, v, c);
                assert_eq!(found.0.to_bits(), expected.0.to_bits(), "{p} {v} {c}");
                assert_eq!(found.1.to_bits(), expected.1.to_bits(), "{p} {v} {c}");
                let target = c.clamp(-500.0, 500.0);
                if lag_s > 0.0 && (target - v).abs() <= 16.0 {
                    followed += 1;
                } else {
                    clamped += 1;
                }
            }
        }
        assert!(followed > 100 && clamped > 100, "{followed} {clamped}");
    }

    /// Three axes advanced without a loop give the loop's numbers and
    /// travel verdict (the loop runs for four axes, the fourth staying
    /// inside its travel), bit for bit.
    #[test]
    fn three_axes_match_the_loop() {
        let axis = |lag_s: f64, lower: f64| AxisDynamics {
            name: String::new(),
            lower,
            upper: 700.0,
            max_velocity: 500.0,
            max_acceleration: 2000.0,
            lag_s,
            resolution: 1e-4,
            noise_sigma: 0.0,
        };
        let dt = 1e-3;
        let cycles: Vec<AxisCycle> = [axis(0.008, 0.0), axis(0.0, 0.0), axis(0.02, -5.0)]
            .iter()
            .map(|a| {
                let decay = if a.lag_s > 0.0 {
                    (-dt / a.lag_s).exp()
                } else {
                    0.0
                };
                AxisCycle::new(a, dt, decay)
            })
            .collect();
        let four: Vec<AxisCycle> = cycles.iter().chain(cycles.first()).copied().collect();
        let mut x: u64 = 0x6c07_8965_2dd4_1e3b;
        let mut next = |scale: f64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 11) as f64 / (1u64 << 53) as f64) * scale
        };
        let (mut p3, mut v3) = (vec![1.0, 350.0, 0.5], vec![0.0; 3]);
        let (mut p4, mut v4) = (vec![1.0, 350.0, 0.5, 350.0], vec![0.0; 4]);
        let mut outside = 0;
        for _ in 0..5000 {
            let c = [
                next(1200.0) - 600.0,
                next(1200.0) - 600.0,
                next(1200.0) - 600.0,
            ];
            let inside3 = advance_axes(&cycles, &mut p3, &mut v3, &c);
            let inside4 = advance_axes(&four, &mut p4, &mut v4, &[c[0], c[1], c[2], 0.0]);
            assert_eq!(inside3, inside4);
            outside += usize::from(!inside3);
            let bits = |w: &[f64]| w.iter().take(3).map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!((bits(&p3), bits(&v3)), (bits(&p4), bits(&v4)));
        }
        assert!(outside > 10, "the travel was never left ({outside})");
    }
}
