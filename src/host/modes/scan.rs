//! Design-value scanning along a planned ball-centre path (JP6484108B2):
//! passive (follow the path, fail on lost contact or over-deflection) and
//! active (`V = Gf Vf + Ge Ve + Gc Vc2`: follow the path, hold the deflection
//! along the measured normal, correct sideways only; fail when the
//! trajectory error `dL` leaves its tolerance).
use super::approach_standoff;
use super::motion::approach_to;
use super::touch::{finish, line_start, LINE_GAIN};
use super::{reposition, Attempt, FreeSpace, HostProbe, ModeOptions, Outcome, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::host::path::{
    round_the_loop, BallPath, PathLocation, SegmentSpeed, SegmentSpeeds, SpeedError, SpeedOptions,
    SpeedPlan,
};
use crate::math::{Point3, Vec3};

mod closed;
mod settle;
use closed::{close_the_loop, closed_run};
use settle::Settling;

/// Passive or active design-value scanning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanKind {
    /// Follow the planned path only.
    Passive,
    /// Follow the path, control the deflection, correct sideways.
    Active,
}

/// What the scan should hold and report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanTargets {
    /// Wanted deflection, mm.
    pub deflection_mm: f64,
    /// Reported point spacing, mm.
    pub pitch_mm: f64,
    /// Trajectory tolerance (active), mm.
    pub trajectory_tolerance_mm: f64,
    /// Normal of the section plane the path lies in (machine frame), if it
    /// is a plane section: on a surface inclined to the plane the active
    /// scan's sideways correction then holds the measured point on the
    /// design curve across that plane ([`control`]).
    pub plane_normal: Option<Vec3>,
}

/// What a design-value scan follows: passive scanning the speed profile
/// on the control cycle; active scanning the segment speeds only (it sets
/// its own speed every cycle from them and from where the probe is).
#[derive(Debug, Clone, PartialEq)]
pub enum ScanPlan {
    /// The whole speed plan, for passive scanning.
    Passive(SpeedPlan),
    /// The segment speeds, for active scanning.
    Active(SegmentSpeeds),
}

impl ScanPlan {
    /// Plans what a scan of `kind` along `path` needs.
    pub fn new(path: &BallPath, kind: ScanKind, opts: &SpeedOptions) -> Result<Self, SpeedError> {
        Ok(match kind {
            ScanKind::Passive => ScanPlan::Passive(SpeedPlan::new(path, opts)?),
            ScanKind::Active => ScanPlan::Active(SegmentSpeeds::new(path, opts)?),
        })
    }

    /// The kind of scan this plan is for.
    pub fn kind(&self) -> ScanKind {
        match self {
            ScanPlan::Passive(_) => ScanKind::Passive,
            ScanPlan::Active(_) => ScanKind::Active,
        }
    }
}

/// Scans along `path` (machine coordinates, already offset by `r - Ep`),
/// passive or active as planned.
pub fn design_value_scan(
    cmm: &mut dyn Machine,
    (probe, free): (HostProbe, Option<&dyn FreeSpace>),
    path: &BallPath,
    plan: &ScanPlan,
    targets: ScanTargets,
    opts: &ModeOptions,
) -> Attempt {
    let mut tr = Tracker::new(cmm, probe).avoiding(free).escaping(opts);
    let mut max_dl = 0.0;
    let kind = plan.kind();
    let result =
        approach(cmm, &mut tr, path, kind, targets.deflection_mm, opts).and_then(|_| match plan {
            ScanPlan::Passive(p) => passive(cmm, &mut tr, path, p, targets, opts),
            ScanPlan::Active(s) => {
                active(cmm, &mut tr, path, s.segments(), targets, opts, &mut max_dl)
            }
        });
    if matches!(
        result,
        Err(Outcome::TrajectoryError | Outcome::LostContact | Outcome::OverDeflection)
    ) {
        // The machine brakes to rest within the scan: a scan that lost
        // the surface was pressing towards it, and its run-on (0.2 mm at
        // 30 mm/s) belongs to the measuring move, not to the next move's
        // collision watch.
        tr.come_to_rest(cmm);
        tr.back_out_of_design(cmm);
    }
    let mut attempt = finish(tr, result);
    attempt.max_trajectory_error_mm = max_dl;
    attempt
}

/// Rapid to a standoff above the path start, then approach along the path
/// normal: to the planned start (passive) or to the wanted deflection (active).
fn approach(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    path: &BallPath,
    kind: ScanKind,
    ep: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let (p0, n0) = (path.position(0.0), path.normal(0.0));
    let start = scan_start(path, ep, tr.free(), opts);
    reposition(cmm, tr, start, n0, opts)?;
    if kind == ScanKind::Passive {
        approach_to(cmm, tr, p0, opts.approach_speed_mm_s, opts)?;
        tr.enter(cmm, Phase::Scan);
        return Ok(());
    }
    tr.enter_approach(cmm, Phase::Scan);
    let reach = 2.0 * (ep + opts.standoff_mm) + 2.0;
    let from = line_start(tr, start, n0);
    for _ in 0..opts.max_cycles {
        if tr.deflection() >= ep {
            return Ok(());
        }
        let off = tr.ball_undeflected() - from;
        if off.norm() > reach {
            return Err(Outcome::LostContact);
        }
        // Held on the line through the path's start, as a touch approach
        // is: the scan starts on the section, not where the move before
        // left the servo's following error.
        let sideways = off - n0 * off.dot(&n0);
        if let Some(o) = tr.step(cmm, -n0 * opts.approach_speed_mm_s - sideways * LINE_GAIN) {
            return Err(o);
        }
    }
    Err(Outcome::Aborted)
}

/// Where the approach of a scan along `path` starts (ball centre, the
/// standoff outside the path start, `ep` being the wanted deflection;
/// a shorter one where `free` says the probe would not fit,
/// [`approach_standoff`]).
pub fn scan_start(
    path: &BallPath,
    ep: f64,
    free: Option<&dyn FreeSpace>,
    opts: &ModeOptions,
) -> Point3 {
    let (p0, n0) = (path.position(0.0), path.normal(0.0));
    let touching = p0 + n0 * ep;
    touching + n0 * approach_standoff(free, touching, n0, opts)
}

fn contact_check(
    tr: &Tracker,
    out_of_contact: &mut usize,
    over_mm: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let d = tr.deflection();
    if d > over_mm {
        return Err(Outcome::OverDeflection);
    }
    *out_of_contact = if d < opts.contact_mm {
        *out_of_contact + 1
    } else {
        0
    };
    if *out_of_contact >= opts.lost_contact_cycles {
        return Err(Outcome::LostContact);
    }
    Ok(())
}

fn passive(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    path: &BallPath,
    plan: &SpeedPlan,
    t: ScanTargets,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let mut lost = 0;
    let strict = ModeOptions {
        lost_contact_cycles: 3,
        ..*opts
    };
    for k in 0..plan.profile().cycles() {
        let Some(st) = plan.profile().state_at_cycle(k) else {
            break;
        };
        let (target, tangent, _) = path.frame(&path.location(st.s));
        let v = tangent * st.v + (target - tr.ball_undeflected()) * opts.gain_correction;
        if let Some(o) = tr.step(cmm, v) {
            return Err(o);
        }
        contact_check(tr, &mut lost, opts.over_deflection_mm, &strict)?;
        tr.sample(t.pitch_mm);
    }
    Ok(())
}

/// Planned speed at arc length `s` from the segment speeds; `cursor` is
/// the segment found for the last `s` and moves to the one for this `s`.
fn planned_speed(segs: &[SegmentSpeed], s: f64, a: f64, cursor: &mut usize) -> f64 {
    *cursor = segment_at(segs, s, *cursor);
    let seg = segs.get(*cursor).or(segs.last());
    seg.map_or(0.0, |g| {
        let up = (g.v_start_mm_s.powi(2) + 2.0 * a * (s - g.s_start).max(0.0)).sqrt();
        let down = (g.v_end_mm_s.powi(2) + 2.0 * a * (g.s_end - s).max(0.0)).sqrt();
        g.v_max_mm_s.min(up).min(down)
    })
}

/// The first segment that ends at or after `s` (`segs.len()` when none
/// does; segment ends grow along the path), walking from segment `from`:
/// the scan moves on by a fraction of a segment per cycle, so this is the
/// binary search `partition_point(|g| g.s_end < s)` in a step or two.
fn segment_at(segs: &[SegmentSpeed], s: f64, from: usize) -> usize {
    let mut i = from.min(segs.len());
    while i > 0 && segs.get(i - 1).is_some_and(|g| g.s_end >= s) {
        i -= 1;
    }
    while segs.get(i).is_some_and(|g| g.s_end < s) {
        i += 1;
    }
    i
}

/// Slowest speed while the scan is under way (the plan starts at rest), mm/s.
const CREEP_MM_S: f64 = 2.0;

fn active(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    path: &BallPath,
    speeds: &[SegmentSpeed],
    t: ScanTargets,
    opts: &ModeOptions,
    max_dl: &mut f64,
) -> Result<(), Outcome> {
    tr.enter(cmm, Phase::Scan);
    let (length, dt, a) = (path.length(), cmm.cycle_s(), opts.tangential_accel_mm_s2);
    let (mut progress, mut speed, mut lost) = (0.0f64, 0.0f64, 0usize);
    let mut touched_at = 0.0f64;
    let mut cursor = 0;
    let mut here = path.location(0.0);
    let searching = ModeOptions {
        lost_contact_cycles: opts.active_lost_contact_cycles,
        ..*opts
    };
    let stall_cycles = (opts.stall_s / dt).ceil() as usize;
    let mut mark = (0.0f64, 0usize);
    let closed = path.is_closed();
    let (ramp, run_out) = if closed {
        closed_run(speeds, a)
    } else {
        (0.0, 0.0)
    };
    let seamless = closed.then(|| round_the_loop(speeds, a));
    let speeds = seamless.as_deref().unwrap_or(speeds);
    let mut settling = Settling::new(t.plane_normal.is_some(), closed, ramp);
    for cycle in 0..opts.max_cycles {
        let a0 = tr.ball_undeflected();
        here = path
            .closest(&a0, Some(&ahead(path, &here, speed * dt)))
            .map_err(|_| Outcome::Aborted)?;
        progress += wrapped_step(path, progress, here.s);
        if progress >= mark.0 + opts.stall_mm {
            mark = (progress, cycle);
        } else if cycle - mark.1 > stall_cycles {
            return Err(Outcome::TrajectoryError);
        }
        let recorded_end = length + overrun(path, settling.at, progress);
        let remaining = recorded_end + run_out - progress;
        if remaining <= 1e-3 || (remaining < 0.05 && speed < CREEP_MM_S) {
            if closed {
                close_the_loop(&mut tr.points, t.pitch_mm);
            }
            return Ok(());
        }
        let (p, tan, n_path) = path.frame(&here);
        let dl = (a0 - p).dot(&n_path);
        cmm.note_trajectory_error(dl);
        *max_dl = f64::max(*max_dl, dl.abs());
        if dl.abs() > t.trajectory_tolerance_mm {
            return Err(Outcome::TrajectoryError);
        }
        let brake = (2.0 * a * remaining.max(0.0)).sqrt();
        let s_plan = if closed {
            progress.rem_euclid(length.max(f64::MIN_POSITIVE))
        } else {
            progress
        };
        let want = planned_speed(speeds, s_plan, a, &mut cursor)
            .max(CREEP_MM_S)
            .min(brake.max(0.5));
        speed += (want - speed).clamp(-a * dt, a * dt);
        let v = control(
            tr,
            (p, a0),
            tan * speed,
            (n_path, t.plane_normal),
            t.deflection_mm,
            opts,
        );
        if let Some(o) = tr.step(cmm, v) {
            return Err(o);
        }
        contact_check(tr, &mut lost, f64::INFINITY, &searching)?;
        if tr.deflection() >= opts.contact_mm {
            touched_at = progress;
        } else if progress - touched_at > opts.active_lost_contact_mm {
            return Err(Outcome::LostContact);
        }
        let offset = || {
            let m = t.plane_normal?;
            let e = plane_offset(tr, (p, n_path), m, t.deflection_mm)?;
            Some((e, n_path.dot(&m).abs() >= HOLD_INCLINED_MIN))
        };
        // A closed scan's loop ends where it began recording.
        let recording = !closed || progress < recorded_end;
        if settling.update(progress, offset) && recording {
            tr.sample(t.pitch_mm);
        }
    }
    Err(Outcome::Aborted)
}

/// How far a scan of `path` goes on past its end (mm): a closed path
/// once round from where recording began (`settled_at`, the progress at
/// which the point settled in the plane; while it has not, as far as it
/// has come), so the recorded points close the loop; an open one not at
/// all.
fn overrun(path: &BallPath, settled_at: Option<f64>, progress: f64) -> f64 {
    match path.is_closed() {
        true => settled_at.unwrap_or(progress).max(0.0),
        false => 0.0,
    }
}

/// The closest-point search's start for this cycle: the last location
/// moved `ds` mm along its segment (chord-length parameters, so about `ds`
/// in `u`), where the probe should be now; the search walks on from there.
fn ahead(path: &BallPath, here: &PathLocation, ds: f64) -> PathLocation {
    let end = path
        .segments()
        .get(here.segment)
        .map_or(0.0, |g| g.param_len());
    PathLocation {
        u: (here.u + ds).min(end),
        ..*here
    }
}

/// `V = Gf Vf + Ge Ve + Gc Vc2` with `q = normalize(n x Vf)`, `Vc2 = (Vc1 . q) q`.
///
/// The plane hold: on a plane section (normal `m`) over a surface inclined
/// to the plane, `Vc1 . q` keeps the ball on its path, so where the true
/// surface lies off the design the deflection loop puts the ball off the
/// path along the normal and the measured point off the plane by the
/// offset times `n . m` (a shifted sphere's cap: 0.1 mm). There the
/// correction slides the ball along `q` (the contact slides along the
/// surface) by the measured point's offset `e` across the plane from its
/// design point, `Vc2 = -e / (q . m) q`, and carries away what `Ge Ve`
/// moves across the plane ([`plane_hold`] says when). `Gf Vf` moves the
/// ball along its path, whose contact stays in the plane: its part across
/// the plane (a freeform face whose slope changes along the section) is
/// the path's, and held back it would leave the point off the plane by
/// that speed over `Gc` (75 um at 3 mm/s).
fn control(
    tr: &Tracker,
    (p, a0): (Point3, Point3),
    vf: Vec3,
    (n_path, plane): (Vec3, Option<Vec3>),
    ep: f64,
    opts: &ModeOptions,
) -> Vec3 {
    let d = tr.now.deflection;
    let touching = d.norm() > opts.contact_mm;
    let n = if touching { d.normalize() } else { n_path };
    let ve = -n * (ep - d.norm());
    let along = vf * opts.gain_follow + ve * opts.gain_deflection;
    let Some(q) = n.cross(&vf).try_normalize(1e-12) else {
        return along;
    };
    let held = plane.filter(|&m| touching && plane_hold((a0 - p, n, n_path), q, m));
    let vc2 = held
        .and_then(|m| {
            let e = plane_offset(tr, (p, n_path), m, ep)?;
            // Only the deflection loop moves the point across the plane:
            // following the path (which climbs or falls where the
            // surface's slope changes along the section) slides the
            // contact along the design's section, in the plane.
            let drift = (ve * opts.gain_deflection).dot(&m) / opts.gain_correction;
            Some(q * (-(e + drift) / q.dot(&m)))
        })
        .unwrap_or_else(|| q * (p - a0).dot(&q));
    along + vc2 * opts.gain_correction
}

/// Least `|n . m|` of the path's normal across the plane for the plane
/// hold: a wall square to the plane keeps its points in it with the ball
/// on its path.
const HOLD_INCLINED_MIN: f64 = 0.1;

/// Least `|q . m|` for the plane hold: where the surface's sideways
/// direction runs nearly along the plane, sliding cannot move the point
/// across it.
const HOLD_SLIDE_MIN: f64 = 0.2;

/// Least cosine between the measured and the path's normal for the plane
/// hold (10 degrees): past it the ball touches an edge or a face the path
/// does not follow, the contact does not slide with the ball, and the
/// hold would drive the ball up the wall.
const HOLD_ALIGNED_COS: f64 = 0.984_807_753_012_208;

/// How far (mm) the ball may stand sideways off its path for the plane
/// hold; beyond, it is held on its path again.
const HOLD_SLIDE_MAX_MM: f64 = 0.3;

/// Whether the plane hold applies with the ball `off` its path, the
/// measured normal `n`, the path's `n_path`, the sideways direction `q`
/// and the plane's normal `m`.
fn plane_hold((off, n, n_path): (Vec3, Vec3, Vec3), q: Vec3, m: Vec3) -> bool {
    n_path.dot(&m).abs() >= HOLD_INCLINED_MIN
        && q.dot(&m).abs() >= HOLD_SLIDE_MIN
        && n.dot(&n_path) >= HOLD_ALIGNED_COS
        && off.dot(&q).abs() <= HOLD_SLIDE_MAX_MM
}

/// The measured point's offset across the plane (normal `m`) from the
/// design point under the path point `p` (path normal `n_path`), mm;
/// `None` while the stylus is free.
fn plane_offset(tr: &Tracker, (p, n_path): (Point3, Vec3), m: Vec3, ep: f64) -> Option<f64> {
    let measured = tr.measured()?;
    let design = p - n_path * (tr.probe_radius() - ep);
    Some((measured.point - design).dot(&m))
}

/// Signed arc-length step from `progress` to the local parameter `s_loc`,
/// unwrapped across the start of a closed path.
fn wrapped_step(path: &BallPath, progress: f64, s_loc: f64) -> f64 {
    let len = path.length();
    let mut ds = s_loc - path.wrap(progress);
    if path.is_closed() {
        if ds > 0.5 * len {
            ds -= len;
        } else if ds < -0.5 * len {
            ds += len;
        }
    }
    ds
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// From any starting segment the walk finds what the binary search
    /// finds, on segment ends with repeats (zero-length segments), for
    /// arc lengths before, inside and past the path.
    #[test]
    fn segment_walk_agrees_with_the_binary_search() {
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(5);
        for case in 0..200 {
            let n = rng.random_range(0..12usize);
            let mut end = 0.0;
            let segs: Vec<SegmentSpeed> = (0..n)
                .map(|_| {
                    let start = end;
                    end += [0.0, 0.3, 0.5][rng.random_range(0..3usize)];
                    SegmentSpeed {
                        s_start: start,
                        s_end: end,
                        r_curv_mm: 1.0,
                        r_angle_mm: 1.0,
                        r_eff_mm: 1.0,
                        v_max_mm_s: 10.0,
                        v_start_mm_s: 0.0,
                        v_end_mm_s: 0.0,
                    }
                })
                .collect();
            for _ in 0..20 {
                let s = rng.random_range(-0.5..end + 0.5);
                let s = if rng.random_range(0..4usize) == 0 {
                    (s * 10.0).round() / 10.0
                } else {
                    s
                };
                let from = rng.random_range(0..n + 3);
                let want = segs.partition_point(|g| g.s_end < s);
                assert_eq!(
                    segment_at(&segs, s, from),
                    want,
                    "case {case}, s {s}, from {from}"
                );
            }
        }
    }
}
