//! A closed-form guess of a cycle's largest feasible acceleration.
//!
//! Each limit that [`Limits::feasible`] tests is solved for the
//! acceleration `acc` (mm/s^2) of the cycle from `(s, v)`, with
//! `x = acc dt` the speed gained (mm/s), `v1 = v + x` and
//! `s1 = s + dt (v + x / 2)`:
//!
//! 1. the segment cap `v1 <= cap + tol`;
//! 2. the braking parabola to the segment's end joint,
//!    `v1 <= sqrt(v_next^2 + 2 a_tan (s_next - s1)) + tol`, a quadratic
//!    in `x`;
//! 3. the stop before the path end, `length - s1 >= stop_distance(v1) -
//!    tol dt`, linear in `x` while `k = floor(v1 / (a_tan dt))` is fixed;
//! 4. every interior joint `j` crossed in `(s, s1]`,
//!    `v^2 + 2 acc (s_j - s) <= (w_j + tol)^2`.
//!
//! Limits 1 and 2 are taken in the segment where the cycle ends by the
//! first estimate. The result is only a candidate: the caller accepts it
//! by the feasibility predicate itself and bisects when it misses.

use super::{CycleStart, Limits};

/// Rounds of `k` in [`Limits::stop_bound`]: a cycle changes the speed by
/// at most one braking step `q`, so `k` moves by about one (a miss only
/// costs the bisection).
const STOP_ROUNDS: usize = 3;

impl Limits {
    /// Closed-form estimate of the largest feasible acceleration of the
    /// cycle from `at`, within `[lo, a_tan]`, mm/s^2.
    pub(super) fn candidate(&self, at: &CycleStart, lo: f64) -> f64 {
        let stop = self.stop_bound(at);
        let here = self.segment_of(at.above);
        let first = self.clamp(self.segment_bound(at, here).min(stop), lo);
        let s1 = self.step(at.s, at.v, first).0;
        let there = self.segment_of(self.joints_above(at, s1));
        let acc = if there == here {
            first
        } else {
            self.clamp(self.segment_bound(at, there).min(stop), lo)
        };
        let s1 = self.step(at.s, at.v, acc).0;
        self.clamp(acc.min(self.crossing_bound(at, s1)), lo)
    }

    /// `acc` within `[lo, a_tan]` (NaN gives `a_tan`: `f64::min` takes the
    /// number), mm/s^2.
    fn clamp(&self, acc: f64, lo: f64) -> f64 {
        acc.min(self.a_tan).max(lo)
    }

    /// Largest acceleration under limits 1 and 2 of segment `i`, mm/s^2
    /// (a missing segment allows no speed, as in `speed_limit`).
    fn segment_bound(&self, at: &CycleStart, i: usize) -> f64 {
        let (Some(&cap), Some(&s_next), Some(&v_next)) = (
            self.v_max.get(i),
            self.joints_s.get(i + 1),
            self.joints_v.get(i + 1),
        ) else {
            return self.cap_bound(at.v, 0.0);
        };
        self.cap_bound(at.v, cap)
            .min(self.parabola_bound(at, s_next, v_next))
    }

    /// Limit 1: `v + acc dt <= cap + tol` with `cap` in mm/s, mm/s^2.
    fn cap_bound(&self, v: f64, cap: f64) -> f64 {
        (cap + self.tol - v) / self.dt
    }

    /// Limit 2: braking to `v_next` (mm/s) at joint `s_next` (mm). With
    /// `w = v - tol`, `q = a_tan dt` and `e = v_next^2 + 2 a_tan (s_next -
    /// s - v dt)` it reads `x^2 + (2 w + q) x + w^2 - e <= 0`; the larger
    /// root in the form without cancellation, mm/s^2 (NaN without a real
    /// root: no bound).
    fn parabola_bound(&self, at: &CycleStart, s_next: f64, v_next: f64) -> f64 {
        let (w, q) = (at.v - self.tol, self.brake_step);
        let e = v_next * v_next + 2.0 * self.a_tan * (s_next - at.s - at.v * self.dt);
        let b = 2.0 * w + q;
        let disc = q * q + 4.0 * (w * q + e);
        2.0 * (e - w * w) / (b + disc.sqrt()) / self.dt
    }

    /// Limit 3: the stop before the path end, solved with the number `k`
    /// of full braking cycles at `v1` taken from the current speed, then
    /// from the speed it gives until `k` no longer changes, mm/s^2.
    fn stop_bound(&self, at: &CycleStart) -> f64 {
        let q = self.brake_step;
        let mut k = super::floor_non_negative(at.v / q);
        let mut x = self.stop_gain(at, k);
        for _ in 0..STOP_ROUNDS {
            let v1 = (at.v + x.min(q)).max(0.0);
            let next = super::floor_non_negative(v1 / q);
            if next == k {
                break;
            }
            k = next;
            x = self.stop_gain(at, k);
        }
        x / self.dt
    }

    /// Largest speed gain `x` (mm/s) with `length - s1 >= stop_distance(v1)
    /// - tol dt` while `v1` has `k` full braking cycles, where
    /// `stop_distance(v1) = dt ((k + 1/2) v1 - q k (k + 1) / 2)`.
    fn stop_gain(&self, at: &CycleStart, k: f64) -> f64 {
        let q = self.brake_step;
        let room = (self.length - at.s) / self.dt + self.tol;
        (room + 0.5 * q * k * (k + 1.0) - (k + 1.5) * at.v) / (k + 1.0)
    }

    /// Limit 4: the joint speeds at the interior joints in `(s, s1]`,
    /// mm/s^2 (infinite when none is crossed).
    fn crossing_bound(&self, at: &CycleStart, s1: f64) -> f64 {
        let interior = self.joints_s.len().saturating_sub(1);
        (at.above.max(1)..interior)
            .map_while(|j| {
                let (&s_j, &w_j) = (self.joints_s.get(j)?, self.joints_v.get(j)?);
                let w = w_j + self.tol;
                (s_j <= s1).then(|| (w * w - at.v * at.v) / (2.0 * (s_j - at.s)))
            })
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Found, Limits, MotionProfile};
    use crate::host::path::{BallPath, PathOptions, SpeedOptions, SpeedPlan};
    use crate::math::{Point3, Vec3};
    use crate::program::{load, Feature};
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};

    fn opts(speed: f64, a_lat: f64) -> SpeedOptions {
        SpeedOptions {
            speed_mm_s: speed,
            a_lat_mm_s2: a_lat,
            ..Default::default()
        }
    }

    fn path(points: &[(Point3, Vec3)], closed: bool, offset: f64) -> BallPath {
        BallPath::from_section(points, closed, offset, PathOptions::default()).unwrap()
    }

    /// Points every `spacing` mm from `a` to `b` (both included), normal `n`.
    fn line(a: Point3, b: Point3, spacing: f64, n: Vec3) -> Vec<(Point3, Vec3)> {
        let count = ((b - a).norm() / spacing).round() as usize;
        (0..=count)
            .map(|k| (a + (b - a) * (k as f64 / count as f64), n))
            .collect()
    }

    fn circle(r: f64, spacing: f64) -> Vec<(Point3, Vec3)> {
        let n = (std::f64::consts::TAU * r / spacing).ceil() as usize;
        (0..n)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / n as f64;
                let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
                (Point3::origin() + radial * r, radial)
            })
            .collect()
    }

    fn corner() -> Vec<(Point3, Vec3)> {
        let c = Point3::new(20.0, 0.0, 0.0);
        let mut pts = line(Point3::origin(), c, 0.5, Vec3::z());
        pts.pop();
        pts.extend(line(c, Point3::new(20.0, 20.0, 0.0), 0.5, Vec3::z()));
        pts
    }

    fn wave() -> Vec<(Point3, Vec3)> {
        (0..300)
            .map(|k| {
                let x = 0.5 * k as f64;
                let n = Vec3::new(-0.9 * (0.3 * x).cos(), 1.0, 0.0);
                (Point3::new(x, 3.0 * (0.3 * x).sin(), 0.0), n)
            })
            .collect()
    }

    /// The z60 section of the blade program, machine frame, at its speed.
    fn blade_z60() -> (BallPath, SpeedOptions) {
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("part-programs")
            .join("blade-z60.json");
        let p = load(&file).unwrap();
        let Some(Feature::Section {
            curves, settings, ..
        }) = p.features.first()
        else {
            panic!("no section")
        };
        let c = &curves[0];
        let pts: Vec<(Point3, Vec3)> = c
            .points
            .iter()
            .map(|q| {
                let n = p.placement.dir_to_machine(q.normal);
                (p.placement.to_machine(q.point), n)
            })
            .collect();
        let offset = p.probe.tip_radius_mm - settings.deflection_mm;
        let o = SpeedOptions {
            speed_mm_s: settings.speed_mm_s,
            ..Default::default()
        };
        (path(&pts, c.closed, offset), o)
    }

    /// Named test paths with their options.
    fn cases() -> Vec<(&'static str, BallPath, SpeedOptions)> {
        let (o, x, z) = (Point3::origin(), Vec3::x(), Vec3::z());
        let (blade, blade_opts) = blade_z60();
        vec![
            (
                "circle",
                path(&circle(20.0, 0.5), true, 0.0),
                opts(80.0, 100.0),
            ),
            (
                "circle fast",
                path(&circle(20.0, 0.5), true, 0.0),
                opts(80.0, 1000.0),
            ),
            (
                "line",
                path(&line(o, Point3::new(60.0, 80.0, 0.0), 0.5, z), false, 0.0),
                opts(80.0, 1000.0),
            ),
            (
                "short line",
                path(&line(o, Point3::new(5.0, 0.0, 0.0), 0.5, x), false, 0.0),
                opts(80.0, 1000.0),
            ),
            ("corner", path(&corner(), false, 0.0), opts(80.0, 1000.0)),
            ("wave", path(&wave(), false, 1.0), opts(80.0, 500.0)),
            ("blade z60", blade, blade_opts),
        ]
    }

    /// The limits `SpeedPlan::new` plans with, from its segment speeds.
    fn limits(path: &BallPath, o: &SpeedOptions) -> Limits {
        let plan = SpeedPlan::new(path, o).unwrap();
        let segs = plan.segments();
        let v_max = segs.iter().map(|x| x.v_max_mm_s).collect();
        let first = segs.first().map(|x| x.v_start_mm_s);
        let joints = first.into_iter().chain(segs.iter().map(|x| x.v_end_mm_s));
        Limits::new(path, v_max, joints.collect(), o)
    }

    /// The search without the candidate (as before it): full, lowest, the
    /// last cycle's answer, bisection.
    fn without_candidate(l: &Limits, s: f64, v: f64, iters: usize, last: f64) -> f64 {
        let at = l.cycle_start(s, v);
        let lo = l.lowest(v);
        if l.feasible(&at, l.a_tan) {
            return l.a_tan;
        }
        if !l.feasible(&at, lo) {
            return lo;
        }
        let res = l.resolution(lo, iters);
        if l.cruise(&at, last, lo, res) {
            return last;
        }
        l.bisect(&at, lo, iters)
    }

    /// On random states near the speed limit (not only reachable ones) an
    /// accepted candidate is feasible and within one resolution of the
    /// bisection's answer, and almost every candidate is accepted.
    #[test]
    fn accepted_candidates_agree_with_the_bisection() {
        let mut rng = ChaCha8Rng::seed_from_u64(60);
        for (name, p, o) in cases() {
            let l = limits(&p, &o);
            let iters = o.accel_search_iters;
            let (mut tried, mut accepted) = (0, 0);
            for _ in 0..4000 {
                let s = p.length() * rng.random::<f64>();
                let limit = l.speed_limit(l.cycle_start(s, 0.0).above, s);
                let v = (limit + l.brake_step * (3.0 * rng.random::<f64>() - 2.0)).max(0.0);
                let (at, lo) = (l.cycle_start(s, v), l.lowest(v));
                if l.feasible(&at, l.a_tan) || !l.feasible(&at, lo) {
                    continue;
                }
                tried += 1;
                let res = l.resolution(lo, iters);
                let Some(c) = l.accept(&at, l.candidate(&at, lo), lo, res) else {
                    continue;
                };
                accepted += 1;
                let b = l.bisect(&at, lo, iters);
                assert!(l.feasible(&at, c), "{name}: s = {s}, v = {v}");
                assert!((c - b).abs() <= res, "{name}: s = {s}, v = {v}: {c} vs {b}");
            }
            assert!(tried > 100, "{name}: {tried} states");
            assert!(
                accepted as f64 > 0.95 * tried as f64,
                "{name}: {accepted} of {tried}"
            );
        }
    }

    /// Profiles planned with the candidate and without it (bisection) have
    /// the same cycles and speeds, and every cycle is feasible.
    #[test]
    fn profiles_match_the_bisection_profiles() {
        for (name, p, o) in cases() {
            let l = limits(&p, &o);
            let iters = o.accel_search_iters;
            let new = MotionProfile::plan(&l, &o).unwrap();
            let old = MotionProfile::plan_with(&l, &o, |s, v, last| {
                without_candidate(&l, s, v, iters, last)
            })
            .unwrap();
            assert!(new.cycles().abs_diff(old.cycles()) <= 1, "{name}");
            for (a, b) in new.samples().iter().zip(old.samples()) {
                assert!((a.v - b.v).abs() < 1e-6, "{name}: {a:?} vs {b:?}");
            }
            // Feasible, or the strongest braking when nothing is (as the
            // bisection does where the discrete braking runs a rounding
            // above the continuous parabola).
            let last = new.samples().len() - 1;
            for x in &new.samples()[..last] {
                let at = l.cycle_start(x.s, x.v);
                let lowest = x.a == l.lowest(x.v) && !l.feasible(&at, x.a);
                assert!(l.feasible(&at, x.a) || lowest, "{name}: {x:?}");
            }
        }
    }

    /// How each cycle's acceleration is found along a planned profile.
    fn tally(l: &Limits, o: &SpeedOptions) -> [usize; 5] {
        let mut counts = [0; 5];
        let plan = MotionProfile::plan_with(l, o, |s, v, last| {
            let (a, found) = l.search(s, v, o.accel_search_iters, last);
            counts[found as usize] += 1;
            a
        });
        assert!(plan.is_ok());
        counts
    }

    /// The candidate is what makes planning cheap: almost no cycle of a
    /// real section (or of the test paths) needs the bisection, and the
    /// candidate almost never misses where it is tried (after the cruise
    /// shortcut).
    #[test]
    fn the_bisection_is_rare() {
        for (name, p, o) in cases() {
            let counts = tally(&limits(&p, &o), &o);
            let cycles: usize = counts.iter().sum();
            let bisected = counts[Found::Bisection as usize];
            let tried = counts[Found::Candidate as usize] + bisected;
            println!("{name}: {cycles} cycles, [full, lowest, cruise, candidate, bisection] = {counts:?}");
            assert!(bisected * 50 < cycles, "{name}: {counts:?}");
            assert!(bisected * 50 <= tried, "{name}: {counts:?}");
        }
    }
}
