//! Speed planning per segment (active-scanning speed planning) and its motion profile on the
//! control cycle (active-scanning speed planning and multi-axis timing).
//!
//! Per segment `i`: `R_eff = min(R_curv, R_angle)` with `R_curv` the
//! smallest curvature radius over the segment and `R_angle` the chord-angle
//! radius between chord `i` and chord `i + 1` (see
//! [`chord_angle_radius`]); `v_max = min(v_cmd, sqrt(a_lat R_eff))`. Speeds
//! at the segment joints start as the smaller neighbouring `v_max`, zero at
//! both ends, then a forward pass `v_{j+1}^2 <= v_j^2 + 2 a_tan ds_j` and a
//! backward pass `v_j^2 <= v_{j+1}^2 + 2 a_tan ds_j` bound them; segment `i`
//! starts at joint speed `i` and ends at joint speed `i + 1`, so a
//! segment's end speed is the next segment's start speed.

use super::ball_path::BallPath;
use super::profile::{Limits, MotionProfile, MotionSample};
use super::radius::{chord_angle_radius, max_curvature};

/// Limits and tolerances of speed planning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedOptions {
    /// Commanded scanning speed, mm/s.
    pub speed_mm_s: f64,
    /// Largest lateral (centripetal) acceleration `v^2 / R`, mm/s^2.
    pub a_lat_mm_s2: f64,
    /// Largest tangential acceleration, mm/s^2.
    pub a_tan_mm_s2: f64,
    /// Control cycle, s.
    pub cycle_s: f64,
    /// Chords turning by no more than this give an infinite chord-angle
    /// radius, rad.
    pub min_chord_angle_rad: f64,
    /// Evenly spaced curvature evaluations per segment.
    pub curvature_samples: usize,
    /// Golden-section steps refining the largest curvature of a segment
    /// (only where it can limit the speed and does not provably peak at a
    /// sample, see `SegmentSpeed::r_curv_mm`).
    pub curvature_refine_iters: usize,
    /// Bisection steps choosing each cycle's acceleration (30 resolve it to
    /// `2 a_tan / 2^30`, about 2e-6 mm/s^2 at 1000 mm/s^2: a speed error
    /// of 2e-9 mm/s per cycle; the bisection keeps only feasible values).
    pub accel_search_iters: usize,
    /// The profile has ended when at rest within this of the path end, mm.
    pub end_tol_mm: f64,
    /// Slack on the speed limits in the per-cycle feasibility test, mm/s.
    pub speed_tol_mm_s: f64,
    /// Planning fails beyond this many control cycles.
    pub max_cycles: usize,
}

impl Default for SpeedOptions {
    fn default() -> Self {
        SpeedOptions {
            speed_mm_s: 80.0,
            a_lat_mm_s2: 1000.0,
            a_tan_mm_s2: 500.0,
            cycle_s: 0.001,
            min_chord_angle_rad: 1e-9,
            curvature_samples: 8,
            curvature_refine_iters: 40,
            accel_search_iters: 30,
            end_tol_mm: 1e-9,
            speed_tol_mm_s: 1e-9,
            max_cycles: 10_000_000,
        }
    }
}

/// Why speeds could not be planned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpeedError {
    /// An option is not a positive finite number.
    #[error("speed option {name} = {value} must be positive and finite")]
    InvalidOption {
        /// Field name in [`SpeedOptions`].
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The profile did not reach the path end within the cycle budget.
    #[error("profile stopped at s = {s_mm} mm of {length_mm} mm after {cycles} cycles")]
    NotConverged {
        /// Control cycles planned.
        cycles: usize,
        /// Arc length reached, mm.
        s_mm: f64,
        /// Path length, mm.
        length_mm: f64,
    },
}

/// The planned speeds of one path segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentSpeed {
    /// Arc length at the segment start, mm.
    pub s_start: f64,
    /// Arc length at the segment end, mm.
    pub s_end: f64,
    /// Smallest curvature radius over the segment, mm, exact (to the
    /// refinement) where it can limit the speed: the smallest of the evenly
    /// spaced samples, refined by golden-section search unless the
    /// curvature provably peaks at that sample. Elsewhere (when the whole
    /// segment provably allows the commanded speed, or its curvature radius
    /// provably exceeds `r_angle_mm`) the radius at the segment's middle or
    /// the smallest of the samples, an upper bound of it.
    pub r_curv_mm: f64,
    /// Chord-angle radius with the next segment, mm (infinite for the last
    /// segment of an open path).
    pub r_angle_mm: f64,
    /// Effective radius `min(r_curv_mm, r_angle_mm)`, mm.
    pub r_eff_mm: f64,
    /// Largest speed on the segment, mm/s.
    pub v_max_mm_s: f64,
    /// Speed at the segment start after both passes, mm/s.
    pub v_start_mm_s: f64,
    /// Speed at the segment end after both passes, mm/s.
    pub v_end_mm_s: f64,
}

/// The planned speeds of every segment of a [`BallPath`], without the
/// cycle-by-cycle profile: what active scanning needs, which sets its own
/// speed every cycle from these (and is spared planning the profile).
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSpeeds {
    segments: Vec<SegmentSpeed>,
}

impl SegmentSpeeds {
    /// Plans the segment speeds along `path`, starting and ending at rest.
    pub fn new(path: &BallPath, opts: &SpeedOptions) -> Result<SegmentSpeeds, SpeedError> {
        validate(opts)?;
        let radii = radii(path, opts);
        let v_max: Vec<f64> = radii.iter().map(|r| segment_v_max(r.2, opts)).collect();
        let joints = joint_speeds(path, &v_max, opts.a_tan_mm_s2);
        let segments = (0..v_max.len())
            .map(|i| segment_speed(path, i, radii[i], v_max[i], &joints))
            .collect();
        Ok(SegmentSpeeds { segments })
    }

    /// Planned speeds per segment, in path order.
    pub fn segments(&self) -> &[SegmentSpeed] {
        &self.segments
    }
}

/// Speeds planned along a [`BallPath`] and the motion profile sampled on
/// the control cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedPlan {
    speeds: SegmentSpeeds,
    profile: MotionProfile,
}

impl SpeedPlan {
    /// Plans speeds along `path`, starting and ending at rest.
    pub fn new(path: &BallPath, opts: &SpeedOptions) -> Result<SpeedPlan, SpeedError> {
        let speeds = SegmentSpeeds::new(path, opts)?;
        let v_max = speeds.segments.iter().map(|g| g.v_max_mm_s).collect();
        let joints = (speeds.segments.iter().map(|g| g.v_start_mm_s))
            .chain([speeds.segments.last().map_or(0.0, |g| g.v_end_mm_s)])
            .collect();
        let limits = Limits::new(path, v_max, joints, opts);
        let profile = MotionProfile::plan(&limits, opts)?;
        Ok(SpeedPlan { speeds, profile })
    }

    /// Planned speeds per segment, in path order.
    pub fn segments(&self) -> &[SegmentSpeed] {
        self.speeds.segments()
    }

    /// The segment speeds alone.
    pub fn speeds(&self) -> &SegmentSpeeds {
        &self.speeds
    }

    /// The motion profile on the control cycle.
    pub fn profile(&self) -> &MotionProfile {
        &self.profile
    }

    /// The motion profile's samples, one per control cycle boundary.
    pub fn samples(&self) -> impl Iterator<Item = MotionSample> + '_ {
        self.profile.samples().iter().copied()
    }

    /// Total planned time, s.
    pub fn duration(&self) -> f64 {
        self.profile.duration()
    }
}

/// Rejects options that are not positive and finite.
fn validate(opts: &SpeedOptions) -> Result<(), SpeedError> {
    let fields = [
        ("speed_mm_s", opts.speed_mm_s),
        ("a_lat_mm_s2", opts.a_lat_mm_s2),
        ("a_tan_mm_s2", opts.a_tan_mm_s2),
        ("cycle_s", opts.cycle_s),
    ];
    match fields.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        Some(&(name, value)) => Err(SpeedError::InvalidOption { name, value }),
        None => Ok(()),
    }
}

/// `(R_curv, R_angle, R_eff)` per segment, mm.
fn radii(path: &BallPath, opts: &SpeedOptions) -> Vec<(f64, f64, f64)> {
    let segs = path.segments();
    let chords: Vec<_> = segs
        .iter()
        .map(|s| s.position(s.param_len()) - s.position(0.0))
        .collect();
    let n = segs.len();
    // Up to this curvature the commanded speed holds, 1/mm.
    let commanded = opts.a_lat_mm_s2 / (opts.speed_mm_s * opts.speed_mm_s);
    segs.iter()
        .enumerate()
        .map(|(i, seg)| {
            let next = if path.is_closed() { (i + 1) % n } else { i + 1 };
            let r_angle = chords.get(next).map_or(f64::INFINITY, |c| {
                chord_angle_radius(&chords[i], c, opts.min_chord_angle_rad)
            });
            // Up to this curvature, `R_eff` and so `v_max` do not depend on
            // the curvature radius (1/mm; NaN `r_angle` is ignored).
            let enough = commanded.max(1.0 / r_angle);
            let k = max_curvature(
                seg,
                opts.curvature_samples,
                opts.curvature_refine_iters,
                enough,
            );
            let r_curv = if k > 0.0 { 1.0 / k } else { f64::INFINITY };
            (r_curv, r_angle, r_curv.min(r_angle))
        })
        .collect()
}

/// `min(v_cmd, sqrt(a_lat R_eff))`, mm/s.
fn segment_v_max(r_eff: f64, opts: &SpeedOptions) -> f64 {
    opts.speed_mm_s.min((opts.a_lat_mm_s2 * r_eff).sqrt())
}

/// Speeds at the segment joints (one more than segments): smaller
/// neighbouring `v_max`, zero at both ends, then forward and backward
/// tangential-acceleration passes.
fn joint_speeds(path: &BallPath, v_max: &[f64], a_tan: f64) -> Vec<f64> {
    let n = v_max.len();
    let mut w: Vec<f64> = (0..=n)
        .map(|j| match j {
            0 => 0.0,
            j if j == n => 0.0,
            j => v_max[j - 1].min(v_max[j]),
        })
        .collect();
    let ds: Vec<f64> = path.segments().iter().map(|s| s.arc_len()).collect();
    for j in 0..n {
        w[j + 1] = w[j + 1].min((w[j] * w[j] + 2.0 * a_tan * ds[j]).sqrt());
    }
    for j in (0..n).rev() {
        w[j] = w[j].min((w[j + 1] * w[j + 1] + 2.0 * a_tan * ds[j]).sqrt());
    }
    w
}

/// The segment speeds `segments` of a closed path run round and round:
/// the joint where the path closes at the smaller top speed of the
/// segments that meet there (not at rest, as a plan that starts and ends
/// there has it), and the tangential-acceleration passes (`a_tan`,
/// mm/s^2) carried on across it. What a scan that passes its start at
/// speed follows; the machine's own speed still starts from rest.
pub fn round_the_loop(segments: &[SegmentSpeed], a_tan: f64) -> Vec<SegmentSpeed> {
    let n = segments.len();
    if n == 0 {
        return Vec::new();
    }
    let top = |i: usize| segments.get(i % n).map_or(0.0, |g| g.v_max_mm_s);
    let ds = |i: usize| segments.get(i % n).map_or(0.0, |g| g.s_end - g.s_start);
    // Joint j is the start of segment j (mod n).
    let mut w: Vec<f64> = (0..n).map(|j| top(j + n - 1).min(top(j))).collect();
    let reach = |from: f64, i: usize| (from * from + 2.0 * a_tan * ds(i)).sqrt();
    // Twice round each way carries every limit across the seam.
    for k in 0..2 * n {
        let (j, next) = (k % n, (k + 1) % n);
        let limit = w.get(j).map_or(0.0, |&v| reach(v, j));
        if let Some(v) = w.get_mut(next) {
            *v = v.min(limit);
        }
    }
    for k in (0..2 * n).rev() {
        let (j, next) = (k % n, (k + 1) % n);
        let limit = w.get(next).map_or(0.0, |&v| reach(v, j));
        if let Some(v) = w.get_mut(j) {
            *v = v.min(limit);
        }
    }
    (segments.iter().enumerate())
        .map(|(i, g)| SegmentSpeed {
            v_start_mm_s: w.get(i).copied().unwrap_or(0.0),
            v_end_mm_s: w.get((i + 1) % n).copied().unwrap_or(0.0),
            ..*g
        })
        .collect()
}

fn segment_speed(
    path: &BallPath,
    i: usize,
    (r_curv_mm, r_angle_mm, r_eff_mm): (f64, f64, f64),
    v_max_mm_s: f64,
    joints: &[f64],
) -> SegmentSpeed {
    SegmentSpeed {
        s_start: path.segment_start(i).unwrap_or(0.0),
        s_end: path.segment_start(i + 1).unwrap_or(0.0),
        r_curv_mm,
        r_angle_mm,
        r_eff_mm,
        v_max_mm_s,
        v_start_mm_s: joints[i],
        v_end_mm_s: joints[i + 1],
    }
}

#[cfg(test)]
mod tests {
    use super::super::radius::reference;
    use super::*;
    use crate::host::path::PathOptions;
    use crate::math::{Point3, Vec3};
    use crate::program::{load, Feature};

    /// The ball-centre paths of every section curve of every part program
    /// (machine frame), each with its commanded speed.
    fn part_program_paths() -> Vec<(String, BallPath, f64)> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("part-programs");
        let mut files: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        files.sort();
        let mut out = Vec::new();
        for file in files {
            let p = load(&file).unwrap();
            for f in &p.features {
                let Feature::Section {
                    name,
                    curves,
                    settings,
                    ..
                } = f
                else {
                    continue;
                };
                for c in curves {
                    let pts: Vec<(Point3, Vec3)> = (c.points.iter())
                        .map(|q| {
                            let n = p.placement.dir_to_machine(q.normal);
                            (p.placement.to_machine(q.point), n)
                        })
                        .collect();
                    let offset = p.probe.tip_radius_mm - settings.deflection_mm;
                    let path =
                        BallPath::from_section(&pts, c.closed, offset, PathOptions::default())
                            .unwrap();
                    let label = format!("{} {name}", file.display());
                    out.push((label, path, settings.speed_mm_s));
                }
            }
        }
        out
    }

    /// `v_max` per segment as planned before the curvature maximisation was
    /// sped up (commit e4de353), with [`reference::max_curvature`].
    fn reference_v_max(path: &BallPath, opts: &SpeedOptions) -> Vec<f64> {
        let segs = path.segments();
        let chords: Vec<_> = (segs.iter())
            .map(|s| s.position(s.param_len()) - s.position(0.0))
            .collect();
        let n = segs.len();
        let enough = opts.a_lat_mm_s2 / (opts.speed_mm_s * opts.speed_mm_s);
        (segs.iter().enumerate())
            .map(|(i, seg)| {
                let (s, it) = (opts.curvature_samples, opts.curvature_refine_iters);
                let k = reference::max_curvature(seg, s, it, enough);
                let r_curv = if k > 0.0 { 1.0 / k } else { f64::INFINITY };
                let next = if path.is_closed() { (i + 1) % n } else { i + 1 };
                let r_angle = chords.get(next).map_or(f64::INFINITY, |c| {
                    chord_angle_radius(&chords[i], c, opts.min_chord_angle_rad)
                });
                segment_v_max(r_curv.min(r_angle), opts)
            })
            .collect()
    }

    /// On every section of every part program, at its speed and at 40 and
    /// 150 mm/s, the planned speeds are exactly those of the old
    /// maximisation: the same largest speed per segment, so the same joint
    /// speeds.
    #[test]
    fn speeds_as_before_on_part_programs() {
        let mut limited = 0;
        for (label, path, speed) in part_program_paths() {
            for v in [speed, 40.0, 150.0] {
                let opts = SpeedOptions {
                    speed_mm_s: v,
                    ..SpeedOptions::default()
                };
                let old = reference_v_max(&path, &opts);
                let new = SegmentSpeeds::new(&path, &opts).unwrap();
                let got: Vec<f64> = new.segments().iter().map(|g| g.v_max_mm_s).collect();
                assert_eq!(got, old, "{label} at {v} mm/s");
                let joints = joint_speeds(&path, &old, opts.a_tan_mm_s2);
                for (i, g) in new.segments().iter().enumerate() {
                    assert_eq!((g.v_start_mm_s, g.v_end_mm_s), (joints[i], joints[i + 1]));
                }
                limited += old.iter().filter(|&&x| x < v).count();
            }
        }
        assert!(limited > 500, "{limited} limited segments");
    }

    /// Four segments round a loop, the first slow (a tight corner after
    /// the seam): the seam's joint takes the first segment's top speed,
    /// the last segment brakes into it over its own length
    /// (`sqrt(v^2 + 2 a ds)` before it), and no joint asks for more than
    /// the tangential acceleration allows between its neighbours.
    #[test]
    fn a_loop_runs_through_its_seam_at_speed() {
        let seg = |s0: f64, s1: f64, v: f64| SegmentSpeed {
            s_start: s0,
            s_end: s1,
            r_curv_mm: 1.0,
            r_angle_mm: 1.0,
            r_eff_mm: 1.0,
            v_max_mm_s: v,
            v_start_mm_s: 0.0,
            v_end_mm_s: 0.0,
        };
        let a = 500.0;
        let segs = [
            seg(0.0, 2.0, 20.0),
            seg(2.0, 12.0, 60.0),
            seg(12.0, 22.0, 60.0),
            seg(22.0, 23.0, 60.0),
        ];
        let out = round_the_loop(&segs, a);
        assert_eq!(out[0].v_start_mm_s, 20.0);
        assert_eq!(out[3].v_end_mm_s, 20.0);
        let before = (20.0f64 * 20.0 + 2.0 * a * 1.0).sqrt();
        assert!((out[3].v_start_mm_s - before).abs() < 1e-9, "{out:?}");
        assert!((out[2].v_end_mm_s - before).abs() < 1e-9);
        for (g, next) in out.iter().zip(out.iter().cycle().skip(1)) {
            let ds = g.s_end - g.s_start;
            assert!(g.v_end_mm_s <= (g.v_start_mm_s.powi(2) + 2.0 * a * ds).sqrt() + 1e-9);
            assert!(g.v_start_mm_s <= (g.v_end_mm_s.powi(2) + 2.0 * a * ds).sqrt() + 1e-9);
            assert!(g.v_start_mm_s <= g.v_max_mm_s && g.v_end_mm_s <= g.v_max_mm_s);
            assert_eq!(g.v_end_mm_s, next.v_start_mm_s);
        }
        assert!(round_the_loop(&[], a).is_empty());
    }
}
