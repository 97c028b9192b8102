//! The motion profile on the control cycle: the arc length, speed and
//! tangential acceleration at every cycle boundary.
//!
//! Every cycle has one constant acceleration, so speed changes happen on
//! cycle boundaries only (active-scanning speed planning). Each cycle takes the largest
//! acceleration in `[-a_tan, a_tan]` (to the resolution of a bisection in
//! `accel_search_iters` steps) that keeps the state under the speed
//! limits: the segment's `v_max`, the joint speeds (at every joint crossed
//! during the cycle), the braking parabola to the next joint, and the
//! shortest stop on whole cycles before the path end.
//! Full braking always satisfies these, so the profile never gets stuck
//! and ends at rest on a cycle boundary exactly at the path end.
//!
//! A cycle that does not repeat the last one's answer tries a closed-form
//! candidate (`candidate.rs`, solved from the same limits); the
//! feasibility predicate accepts it only when the bisection's guarantee
//! holds (feasible, one resolution more not), so the bisection itself runs
//! only on the rare cycles it misses.

use super::ball_path::BallPath;
use super::speed::{SpeedError, SpeedOptions};

mod candidate;

/// The state at one control cycle boundary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionSample {
    /// Time since the scan start, s.
    pub t: f64,
    /// Arc length along the path, mm.
    pub s: f64,
    /// Path speed, mm/s.
    pub v: f64,
    /// Tangential acceleration during the following cycle, mm/s^2 (0 at the
    /// last sample).
    pub a: f64,
}

/// Motion profile along a path: one sample per control cycle boundary,
/// from rest at `s = 0` to rest at `s = length`.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionProfile {
    samples: Vec<MotionSample>,
    cycle_s: f64,
}

/// Speed limits along the path, in the form the profile needs.
pub(crate) struct Limits {
    /// Arc length at the segment joints (segments + 1), mm.
    joints_s: Vec<f64>,
    /// Joint speeds after the forward and backward passes, mm/s.
    joints_v: Vec<f64>,
    /// Largest speed per segment, mm/s.
    v_max: Vec<f64>,
    /// Tangential acceleration limit, mm/s^2.
    a_tan: f64,
    /// Control cycle, s.
    dt: f64,
    /// Slack on the speed limits, mm/s.
    tol: f64,
    /// Path length (the last joint), mm.
    length: f64,
    /// Speed lost in one cycle of full braking, `a_tan dt`, mm/s.
    brake_step: f64,
}

impl Limits {
    /// Limits from per-segment `v_max` and joint speeds.
    pub(crate) fn new(
        path: &BallPath,
        v_max: Vec<f64>,
        joints_v: Vec<f64>,
        opts: &SpeedOptions,
    ) -> Self {
        let joints_s: Vec<f64> = (0..=v_max.len())
            .filter_map(|i| path.segment_start(i))
            .collect();
        Limits {
            length: joints_s.last().copied().unwrap_or(0.0),
            joints_s,
            joints_v,
            v_max,
            a_tan: opts.a_tan_mm_s2,
            dt: opts.cycle_s,
            tol: opts.speed_tol_mm_s,
            brake_step: opts.a_tan_mm_s2 * opts.cycle_s,
        }
    }

    fn length(&self) -> f64 {
        self.length
    }

    /// State after one cycle at acceleration `acc` from `(s, v)`.
    fn step(&self, s: f64, v: f64, acc: f64) -> (f64, f64) {
        let dt = self.dt;
        let v1 = v + acc * dt;
        let v1 = if v1 < self.tol { 0.0 } else { v1 };
        (s + v * dt + 0.5 * acc * dt * dt, v1)
    }

    /// Whether a cycle at `acc` from `at` respects every limit.
    fn feasible(&self, at: &CycleStart, acc: f64) -> bool {
        let (s1, v1) = self.step(at.s, at.v, acc);
        let above1 = self.joints_above(at, s1);
        self.length() - s1 >= self.stop_distance(v1) - self.tol * self.dt
            && v1 <= self.speed_limit(above1, s1) + self.tol
            && self.joints_ok(at, acc, above1)
    }

    /// Where a cycle from `(s, v)` starts.
    fn cycle_start(&self, s: f64, v: f64) -> CycleStart {
        CycleStart {
            s,
            v,
            above: self.joints_s.partition_point(|&x| x <= s),
        }
    }

    /// Number of joints at or before `s1`, counting on from `from` (the
    /// number at or before `at.s <= s1`): a cycle crosses at most a few
    /// joints, and the joints are sorted (cumulative arc lengths).
    fn joints_above(&self, at: &CycleStart, s1: f64) -> usize {
        let from = at.above;
        if s1 < at.s {
            return self.joints_s.partition_point(|&x| x <= s1);
        }
        from + self
            .joints_s
            .get(from..)
            .map_or(0, |rest| rest.iter().take_while(|&&x| x <= s1).count())
    }

    /// Shortest distance to rest on whole cycles of braking at most
    /// `a_tan`: full cycles at `-a_tan`, then one weaker cycle, mm.
    fn stop_distance(&self, v: f64) -> f64 {
        let q = self.brake_step;
        let full = floor_non_negative(v / q);
        let rest = v - full * q;
        self.dt * (full * v - 0.5 * q * full * full + 0.5 * rest)
    }

    /// Speed limit at `s` (with `above` joints at or before it): segment
    /// `v_max` and braking to the next joint.
    fn speed_limit(&self, above: usize, s: f64) -> f64 {
        let i = self.segment_of(above);
        let (Some(&cap), Some(&s_next), Some(&v_next)) = (
            self.v_max.get(i),
            self.joints_s.get(i + 1),
            self.joints_v.get(i + 1),
        ) else {
            return 0.0;
        };
        let brake = (v_next * v_next + 2.0 * self.a_tan * (s_next - s).max(0.0)).sqrt();
        cap.min(brake)
    }

    /// Speed at every interior joint crossed in `(s, s1]` within its limit
    /// (`above1` joints at or before `s1`).
    fn joints_ok(&self, at: &CycleStart, acc: f64, above1: usize) -> bool {
        let first = at.above.max(1);
        let last = above1.min(self.joints_s.len().saturating_sub(1));
        let (s, v) = (at.s, at.v);
        (first..last).all(|j| {
            let v2 = v * v + 2.0 * acc * (self.joints_s[j] - s);
            let w = self.joints_v[j] + self.tol;
            v2 <= w * w
        })
    }

    /// Segment index at an arc length with `above` joints at or before it.
    fn segment_of(&self, above: usize) -> usize {
        above
            .saturating_sub(1)
            .min(self.v_max.len().saturating_sub(1))
    }

    /// Largest feasible acceleration for the cycle from `(s, v)` (full
    /// braking, or the weaker braking that just stops, if none is).
    fn best_accel(&self, s: f64, v: f64, iters: usize, last: f64) -> f64 {
        self.search(s, v, iters, last).0
    }

    /// [`Limits::best_accel`] and how it was found: full acceleration,
    /// the lowest, the last cycle's answer, the closed-form candidate (see
    /// `candidate.rs`), or bisection. Every answer but the lowest is
    /// feasible with one resolution more infeasible (or is `a_tan`).
    fn search(&self, s: f64, v: f64, iters: usize, last: f64) -> (f64, Found) {
        let at = self.cycle_start(s, v);
        let lo = self.lowest(v);
        if self.feasible(&at, self.a_tan) {
            return (self.a_tan, Found::Full);
        }
        if !self.feasible(&at, lo) {
            return (lo, Found::Lowest);
        }
        let res = self.resolution(lo, iters);
        if self.cruise(&at, last, lo, res) {
            return (last, Found::Cruise);
        }
        if let Some(c) = self.accept(&at, self.candidate(&at, lo), lo, res) {
            return (c, Found::Candidate);
        }
        (self.bisect(&at, lo, iters), Found::Bisection)
    }

    /// Strongest braking from speed `v`: `a_tan`, or the weaker braking
    /// that stops within the cycle, mm/s^2.
    fn lowest(&self, v: f64) -> f64 {
        (-self.a_tan).max(-v / self.dt)
    }

    /// Bisection resolution on `[lo, a_tan]` after `iters` steps, mm/s^2.
    fn resolution(&self, lo: f64, iters: usize) -> f64 {
        (self.a_tan - lo) * 0.5f64.powi(iters.min(1000) as i32)
    }

    /// `c` if feasible and `c + res` is not, else `c - res` (not below
    /// `lo`) if `c` is infeasible and that is feasible: the bisection's
    /// guarantee, checked by the same predicate; `None` otherwise.
    fn accept(&self, at: &CycleStart, c: f64, lo: f64, res: f64) -> Option<f64> {
        if self.feasible(at, c) {
            return (!self.feasible(at, (c + res).min(self.a_tan))).then_some(c);
        }
        let below = (c - res).max(lo);
        self.feasible(at, below).then_some(below)
    }

    /// Cruising repeats the last cycle's answer: keep it when it is still
    /// feasible and one resolution `res` more is not.
    fn cruise(&self, at: &CycleStart, last: f64, lo: f64, res: f64) -> bool {
        last > lo && last < self.a_tan && self.feasible(at, last) && !self.feasible(at, last + res)
    }

    /// Bisection on `[lo, a_tan]` (`lo` feasible, `a_tan` not) in `iters`
    /// steps: the last feasible lower end, mm/s^2.
    fn bisect(&self, at: &CycleStart, lo: f64, iters: usize) -> f64 {
        let (mut lo, mut hi) = (lo, self.a_tan);
        for _ in 0..iters {
            let mid = 0.5 * (lo + hi);
            if self.feasible(at, mid) {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    }
}

/// How [`Limits::search`] found a cycle's acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// `a_tan` is feasible.
    Full,
    /// Not even the strongest braking is feasible.
    Lowest,
    /// The last cycle's answer passed the check.
    Cruise,
    /// The closed-form candidate passed the check.
    Candidate,
    /// Neither did: full bisection.
    Bisection,
}

/// `x.floor()`, by an integer conversion where that is exact (`0 < x <
/// 2^52`): the same value without a call to the software `floor` of
/// targets without a rounding instruction. Through `i64`, not `u64`: on
/// x86-64 that is one conversion instruction each way, where `u64` takes a
/// multi-instruction sequence.
fn floor_non_negative(x: f64) -> f64 {
    /// Below this every `f64` converts to `i64` and back exactly.
    const EXACT: f64 = 4_503_599_627_370_496.0;
    if x > 0.0 && x < EXACT {
        x as i64 as f64
    } else {
        x.floor()
    }
}

/// The state a cycle starts from, with its place among the joints.
struct CycleStart {
    /// Arc length, mm.
    s: f64,
    /// Speed, mm/s.
    v: f64,
    /// Number of joints at or before `s`.
    above: usize,
}

impl MotionProfile {
    /// Plans the profile cycle by cycle from rest at `s = 0`.
    pub(crate) fn plan(limits: &Limits, opts: &SpeedOptions) -> Result<MotionProfile, SpeedError> {
        let iters = opts.accel_search_iters;
        Self::plan_with(limits, opts, |s, v, last| {
            limits.best_accel(s, v, iters, last)
        })
    }

    /// Plans the profile with `choose(s, v, last)` giving each cycle's
    /// acceleration from arc length `s` (mm), speed `v` (mm/s) and the
    /// last cycle's acceleration (mm/s^2, NaN at the start).
    fn plan_with(
        limits: &Limits,
        opts: &SpeedOptions,
        mut choose: impl FnMut(f64, f64, f64) -> f64,
    ) -> Result<MotionProfile, SpeedError> {
        let length = limits.length();
        let dt = opts.cycle_s;
        let mut samples = Vec::new();
        let (mut s, mut v, mut a_last) = (0.0, 0.0, f64::NAN);
        for k in 0..opts.max_cycles {
            let t = k as f64 * dt;
            if v == 0.0 && length - s <= opts.end_tol_mm {
                let a = 0.0;
                samples.push(MotionSample { t, s: length, v, a });
                return Ok(MotionProfile {
                    samples,
                    cycle_s: dt,
                });
            }
            let a = choose(s, v, a_last);
            a_last = a;
            samples.push(MotionSample { t, s, v, a });
            (s, v) = limits.step(s, v, a);
        }
        let cycles = opts.max_cycles;
        Err(SpeedError::NotConverged {
            cycles,
            s_mm: s,
            length_mm: length,
        })
    }

    /// Samples at the cycle boundaries, from `t = 0` to `duration()`.
    pub fn samples(&self) -> &[MotionSample] {
        &self.samples
    }

    /// Control cycle, s.
    pub fn cycle_s(&self) -> f64 {
        self.cycle_s
    }

    /// Number of control cycles from start to rest at the end.
    pub fn cycles(&self) -> usize {
        self.samples.len().saturating_sub(1)
    }

    /// Total time, s.
    pub fn duration(&self) -> f64 {
        self.cycles() as f64 * self.cycle_s
    }

    /// State at cycle boundary `k` (`None` beyond the end).
    pub fn state_at_cycle(&self, k: usize) -> Option<MotionSample> {
        self.samples.get(k).copied()
    }

    /// State at time `t` (constant acceleration within a cycle), clamped to
    /// `[0, duration()]`.
    pub fn state_at_time(&self, t: f64) -> Option<MotionSample> {
        let t = t.clamp(0.0, self.duration());
        let k = ((t / self.cycle_s).floor() as usize).min(self.cycles());
        let base = self.samples.get(k)?;
        let tau = t - base.t;
        let s = base.s + base.v * tau + 0.5 * base.a * tau * tau;
        Some(MotionSample {
            t,
            s,
            v: base.v + base.a * tau,
            a: base.a,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::floor_non_negative;

    #[test]
    fn floor_by_conversion_is_floor() {
        let cases = [
            0.0,
            -0.0,
            0.5,
            1.0 - f64::EPSILON / 2.0,
            1.0,
            79.999_999_999,
            123_456.75,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            1e300,
            -0.5,
            -3.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in cases {
            assert_eq!(floor_non_negative(x).to_bits(), x.floor().to_bits(), "{x}");
        }
        assert!(floor_non_negative(f64::NAN).is_nan());
    }
}
