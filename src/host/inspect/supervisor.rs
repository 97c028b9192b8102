//! Error-correcting design-value scanning (JP6484108B2) of one section curve:
//! active scanning; on a trajectory error a geometric correction from touch
//! points (flag 0) or an autonomous correction (flag 1, or when no simple
//! model fits); a bounded number of autonomous corrections.
use super::correction::{fit_correction, section_curvature, DesignPoint, Touches};
use super::moved::{in_moved, leave_moved, moved_by, RigidMap};
use super::prepared::{scan_speed, PreparedScan, ScanInputs};
use super::record::{AttemptMode, CorrectionReport};
use super::{CurveCtx, CurveResult};
use crate::host::modes::{
    autonomous_scan, autonomous_start, design_value_scan, direct_move, move_through, recover,
    scan_start, touch_point, touch_start, Attempt, AutonomousTask, Collision, EndPath, Measured,
    ModeOptions, Outcome, ScanKind, ScanTargets, Tracker, STALL_MOVE_SHARE,
};
use crate::host::path::SpeedOptions;
use crate::math::Point3;
use crate::program::Mode;

/// Limits and thresholds of the correcting supervisor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupervisorOptions {
    /// A geometric correction is accepted when every touch point lies within
    /// this distance of the corrected design data, mm.
    pub geometric_threshold_mm: f64,
    /// ... and its largest residual is at most this share of the touch
    /// points' largest gap to the design data before it (a correction
    /// that leaves the error where it was explains nothing),
    /// dimensionless.
    pub geometric_residual_share: f64,
    /// Autonomous corrections allowed per curve before giving up.
    pub max_autonomous: usize,
    /// Touch points per geometric correction (spread by arc length).
    pub touch_points: usize,
    /// How far past the nominal a touch point searches for contact, mm.
    pub touch_search_mm: f64,
    /// A design-value scan that reaches its end with two consecutive
    /// points further apart than this many pitches lost contact in
    /// between (the stretch is unmeasured), dimensionless.
    pub max_gap_pitches: f64,
    /// A section that its corrections found moved by more than this (mm)
    /// is left by rising to the clearance height through its moved free
    /// space: a route from inside it planned round the design's section
    /// could strike its walls.
    pub leave_moved_mm: f64,
}

impl Default for SupervisorOptions {
    fn default() -> Self {
        SupervisorOptions {
            geometric_threshold_mm: 0.25,
            geometric_residual_share: 0.5,
            max_autonomous: 2,
            touch_points: 16,
            touch_search_mm: 6.0,
            max_gap_pitches: 4.0,
            leave_moved_mm: 0.25,
        }
    }
}

/// Whether an outcome is a trajectory error the corrections address.
fn correctable(o: Outcome) -> bool {
    matches!(
        o,
        Outcome::TrajectoryError | Outcome::LostContact | Outcome::OverDeflection
    )
}

/// Measures one section curve in the given mode.
pub fn scan_curve(
    ctx: &mut CurveCtx,
    design: Vec<DesignPoint>,
    closed: bool,
    mode: Mode,
) -> CurveResult {
    let mut res = CurveResult::default();
    match mode {
        Mode::Active | Mode::Passive => {
            let kind = if mode == Mode::Active {
                ScanKind::Active
            } else {
                ScanKind::Passive
            };
            design_attempt(ctx, &design, closed, kind, &mut res);
        }
        Mode::Autonomous => {
            autonomous_attempt(ctx, &design, closed, &mut res);
        }
        Mode::Auto => correcting(ctx, design, closed, ScanKind::Active, &mut res),
        Mode::AutoPassive => correcting(ctx, design, closed, ScanKind::Passive, &mut res),
    }
    res
}

/// [`corrections`], then out of the section when they found it moved.
fn correcting(
    ctx: &mut CurveCtx,
    design: Vec<DesignPoint>,
    closed: bool,
    kind: ScanKind,
    res: &mut CurveResult,
) {
    // Where the corrections found the section standing: the free space
    // of the moves to its scans goes with it.
    let mut moved = None;
    let design = corrections(ctx, (design, &mut moved), closed, kind, res);
    if let Some(map) = moved {
        leave_moved(ctx, (map, &design), res);
    }
}

/// The attempts and corrections of the method; returns the design data
/// of the last attempt, and leaves in `moved` the motion the corrections
/// found.
fn corrections(
    ctx: &mut CurveCtx,
    (mut design, moved): (Vec<DesignPoint>, &mut Option<RigidMap>),
    closed: bool,
    kind: ScanKind,
    res: &mut CurveResult,
) -> Vec<DesignPoint> {
    let mut flag = 0;
    let mut autonomous = 0;
    if let Some(learned) = ctx.learned.clone() {
        design = learned.apply(&design);
        res.corrections.push(learned.report());
        *moved = moved_by(ctx, &learned, *moved);
    }
    // Whether the design in hand is the points of an autonomous scan of
    // this part that completed (and are the feature's points until a
    // design-value scan completes).
    let mut measured_autonomously = false;
    loop {
        let outcome = in_moved(ctx, *moved, |c| {
            design_attempt(c, &design, closed, kind, res)
        });
        if outcome == Outcome::Completed || !correctable(outcome) {
            return design;
        }
        if measured_autonomously {
            // The design-value scan cannot follow even the surface as
            // measured (a curve too tight for its speed and deflection
            // loop): corrections would repeat the same, so the autonomous
            // scan's points are the measurement.
            res.complete = true;
            res.notes.push(
                "measured by the autonomous scan: the design-value scan failed on its points too"
                    .into(),
            );
            return design;
        }
        if flag == 0 {
            if let Some(corrected) = in_moved(ctx, *moved, |c| geometric(c, &design, res)) {
                design = corrected;
                if let Some(learned) = res.learned.clone() {
                    *moved = moved_by(ctx, &learned, *moved);
                }
                flag = 1;
                continue;
            }
        }
        if autonomous >= ctx.supervisor.max_autonomous {
            res.notes
                .push(format!("gave up after {autonomous} autonomous corrections"));
            return design;
        }
        autonomous += 1;
        match in_moved(ctx, *moved, |c| autonomous_design(c, &design, closed, res)) {
            Some(new_design) => {
                design = new_design;
                measured_autonomously = true;
            }
            None => return design,
        }
        flag = 0;
    }
}

fn design_attempt(
    ctx: &mut CurveCtx,
    design: &[DesignPoint],
    closed: bool,
    kind: ScanKind,
    res: &mut CurveResult,
) -> Outcome {
    let speed = scan_speed(
        base_speed(&ctx.modes),
        ctx.settings.speed_mm_s,
        ctx.cmm.cycle_s(),
    );
    let offset = ctx.probe.tip_radius_mm - ctx.settings.deflection_mm;
    let inputs = ScanInputs::new(design, &ctx.pose, closed, offset, speed, kind);
    let scan = match PreparedScan::new(inputs) {
        Ok(p) => p,
        Err(failure) => {
            res.notes.push(failure.note().into());
            return Outcome::Aborted;
        }
    };
    let (path, plan) = (&scan.path, &scan.plan);
    let targets = ScanTargets {
        deflection_mm: ctx.settings.deflection_mm,
        pitch_mm: ctx.settings.pitch_mm,
        trajectory_tolerance_mm: ctx.settings.trajectory_tolerance_mm,
        plane_normal: Some(ctx.pose.dir_to_machine(ctx.plane_normal)),
    };
    let t0 = ctx.cmm.readings().time_s;
    let mode = if kind == ScanKind::Active {
        AttemptMode::Active
    } else {
        AttemptMode::Passive
    };
    let start = scan_start(path, targets.deflection_mm, ctx.free, &ctx.modes);
    if let Some(c) = position(ctx, start) {
        return res.record(mode, struck_on_the_way(ctx, c, t0), &ctx.pose);
    }
    let mut attempt = design_value_scan(
        ctx.cmm,
        (ctx.probe, ctx.free),
        path,
        plan,
        targets,
        &ctx.modes,
    );
    attempt.machine_time_s = ctx.cmm.readings().time_s - t0;
    // The design's own gaps are no loss: a concave corner the ball
    // bridges, trimmed from the section where it would touch both walls,
    // leaves at most the ball's diameter between its last point on one
    // wall and its first on the other.
    let design_gap = (design.windows(2))
        .map(|w| (w[1].point - w[0].point).norm())
        .fold(0.0, f64::max)
        .min(2.0 * ctx.probe.tip_radius_mm);
    let gap_limit = ctx.supervisor.max_gap_pitches * targets.pitch_mm + design_gap;
    let gap = largest_gap(&attempt.points);
    if attempt.outcome == Outcome::Completed && gap > gap_limit {
        attempt.outcome = Outcome::LostContact;
        res.notes.push(format!(
            "the scan left a {gap:.2} mm stretch without points (more than {gap_limit:.2} mm): the stylus lost contact"
        ));
    }
    res.record(mode, attempt, &ctx.pose)
}

/// The largest distance between consecutive points, mm (0 for fewer than
/// two).
fn largest_gap(points: &[Measured]) -> f64 {
    (points.windows(2))
        .map(|w| (w[1].point - w[0].point).norm())
        .fold(0.0, f64::max)
}

/// Goes straight to a probing start point (ball centre) when the line is
/// clear of the part; otherwise the measuring mode repositions over the
/// clearance height by itself, which also handles any other failure
/// here. Returns the collision that stopped the move, if one did.
fn position(ctx: &mut CurveCtx, start: Point3) -> Option<Collision> {
    let free = ctx.free?;
    let stop = direct_move(ctx.cmm, ctx.probe, start, free, &ctx.modes).err()?;
    stop.collision
        .filter(|_| stop.outcome == Outcome::Collision)
}

/// An attempt that the collision `c` on the move to its start ended
/// before it measured, from machine time `t0` on.
fn struck_on_the_way(ctx: &CurveCtx, c: Collision, t0: f64) -> Attempt {
    Attempt {
        outcome: Outcome::Collision,
        points: Vec::new(),
        machine_time_s: ctx.cmm.readings().time_s - t0,
        max_trajectory_error_mm: 0.0,
        collision: Some(c),
    }
}

/// Indices of `n` design points spread evenly by arc length.
fn spread(design: &[DesignPoint], n: usize) -> Vec<usize> {
    let mut acc = vec![0.0];
    for w in design.windows(2) {
        let last = acc.last().copied().unwrap_or(0.0);
        acc.push(last + (w[1].point - w[0].point).norm());
    }
    let total = acc.last().copied().unwrap_or(0.0);
    let mut out: Vec<usize> = (0..n)
        .map(|k| {
            let target = total * (k as f64 + 0.5) / n as f64;
            acc.partition_point(|&a| a < target)
                .min(design.len().saturating_sub(1))
        })
        .collect();
    out.dedup();
    out
}

fn geometric(
    ctx: &mut CurveCtx,
    design: &[DesignPoint],
    res: &mut CurveResult,
) -> Option<Vec<DesignPoint>> {
    let picks = spread(design, ctx.supervisor.touch_points);
    let t0 = ctx.cmm.readings().time_s;
    let mut touched = Vec::new();
    let mut measured = Vec::new();
    let mut curvature = Vec::new();
    let mut attempt = Attempt {
        outcome: Outcome::Completed,
        points: Vec::new(),
        machine_time_s: 0.0,
        max_trajectory_error_mm: 0.0,
        collision: None,
    };
    for (k, &i) in picks.iter().enumerate() {
        let d = design[i];
        let (p, n) = (
            ctx.pose.to_machine(d.point),
            ctx.pose.dir_to_machine(d.normal),
        );
        let struck = match k.checked_sub(1).and_then(|j| picks.get(j)) {
            Some(&prev) => travel_outside(ctx, design, prev, i),
            None => position(ctx, touch_start(ctx.probe, p, n, ctx.free, &ctx.modes)),
        };
        // A strike ends the attempt (a machine stops there); the points
        // touched before it still go to the fit below.
        if let Some(c) = struck {
            attempt.outcome = Outcome::Collision;
            attempt.collision = attempt.collision.or(Some(c));
            break;
        }
        let a = touch_point(
            ctx.cmm,
            (ctx.probe, ctx.free),
            p,
            n,
            ctx.supervisor.touch_search_mm,
            &ctx.modes,
        );
        attempt.machine_time_s += a.machine_time_s;
        if let (Outcome::Completed, Some(m)) = (a.outcome, a.points.first()) {
            touched.push(d);
            curvature.push(section_curvature(design, i));
            measured.push(ctx.pose.to_part(m.point));
            attempt.points.push(*m);
        } else if matches!(a.outcome, Outcome::AxisLimit | Outcome::Collision) {
            attempt.outcome = a.outcome;
            attempt.collision = a.collision.or(attempt.collision);
            break;
        }
    }
    attempt.machine_time_s = ctx.cmm.readings().time_s - t0;
    res.record(AttemptMode::Points, attempt, &ctx.pose);
    let touches = Touches {
        design: &touched,
        curvature: &curvature,
        measured: &measured,
    };
    let sup = &ctx.supervisor;
    let limits = (sup.geometric_threshold_mm, sup.geometric_residual_share);
    let fit = fit_correction(touches, ctx.plane_normal, limits);
    let Some(c) = fit else {
        res.notes.push(if touched.is_empty() {
            format!("none of the {} touch points could be measured", picks.len())
        } else {
            format!(
                "no simple correction fits the {} touch points",
                touched.len()
            )
        });
        return None;
    };
    res.corrections.push(CorrectionReport::Geometric {
        model: c.model.name().into(),
        max_residual_mm: c.max_residual_mm,
        points: c.points,
        source: "fitted",
    });
    res.learned = Some(super::Learned::Geometric(c.clone()));
    Some(design.iter().map(|d| c.apply(d)).collect())
}

/// Spacing of waypoints when travelling around a section, mm.
const TRAVEL_STEP_MM: f64 = 6.0;

/// From the standoff position of design point `from` to that of `to`,
/// following the design data offset outward by the ball radius plus the
/// standoff (no detour over the part). Failures are left to the next
/// touch point, which repositions by itself; a collision on the way is
/// returned (the geometric correction's attempt reports it).
fn travel_outside(
    ctx: &mut CurveCtx,
    design: &[DesignPoint],
    from: usize,
    to: usize,
) -> Option<Collision> {
    let clear = ctx.probe.tip_radius_mm + ctx.modes.standoff_mm;
    let mut waypoints = Vec::new();
    let mut since = 0.0;
    for w in design.get(from..=to).unwrap_or(&[]).windows(2) {
        since += (w[1].point - w[0].point).norm();
        if since >= TRAVEL_STEP_MM {
            waypoints.push(ctx.pose.to_machine(w[1].point + w[1].normal * clear));
            since = 0.0;
        }
    }
    if let Some(d) = design.get(to) {
        waypoints.push(ctx.pose.to_machine(d.point + d.normal * clear));
    }
    let mut tr = Tracker::new(ctx.cmm, ctx.probe)
        .avoiding(ctx.free)
        .escaping(&ctx.modes);
    if let Some(free) = ctx.free {
        // Along the outside only where that is clear; the touch point's
        // own repositioning routes around the part otherwise.
        let mut from = tr.ball_undeflected();
        let clear = waypoints.iter().all(|&w| {
            let ok = free.segment_clear_with(from, w, true);
            from = w;
            ok
        });
        if !clear {
            let _ = recover(ctx.cmm, &mut tr, &ctx.modes);
            return tr.collision;
        }
    }
    let moved = recover(ctx.cmm, &mut tr, &ctx.modes).and_then(|_| {
        move_through(
            ctx.cmm,
            &mut tr,
            &waypoints,
            ctx.modes.rapid_speed_mm_s,
            &ctx.modes,
        )
    });
    if moved.is_err() {
        let _ = recover(ctx.cmm, &mut tr, &ctx.modes);
    }
    tr.collision
}

fn autonomous_task(ctx: &CurveCtx, design: &[DesignPoint], closed: bool) -> Option<AutonomousTask> {
    let first = design.first()?;
    let second = design.get(1)?;
    let last = design.last()?;
    let m = |p: Point3| ctx.pose.to_machine(p);
    let length: f64 = design
        .windows(2)
        .map(|w| (w[1].point - w[0].point).norm())
        .sum();
    let end_tangent = ctx
        .pose
        .dir_to_machine(last.point - design.get(design.len().checked_sub(2)?)?.point)
        .try_normalize(1e-12)?;
    Some(AutonomousTask {
        start: m(first.point),
        start_normal: ctx.pose.dir_to_machine(first.normal),
        direction: (m(second.point) - m(first.point)).try_normalize(1e-12)?,
        plane: (m(first.point), ctx.pose.dir_to_machine(ctx.plane_normal)),
        end: (!closed).then_some((m(last.point), end_tangent)),
        end_path: end_path(ctx, design),
        nominal_length_mm: length,
        deflection_mm: ctx.settings.deflection_mm,
        pitch_mm: ctx.settings.pitch_mm.min(0.5),
    })
}

/// The design's points within [`ModeOptions::autonomous_end_reach_mm`]
/// (and a pitch) of its end along it, machine coordinates.
fn end_path(ctx: &CurveCtx, design: &[DesignPoint]) -> EndPath {
    let reach = ctx.modes.autonomous_end_reach_mm + ctx.settings.pitch_mm;
    let mut along = 0.0;
    let mut stretch: Vec<Point3> = Vec::new();
    for w in design.windows(2).rev() {
        if stretch.is_empty() {
            stretch.push(ctx.pose.to_machine(w[1].point));
        }
        along += (w[1].point - w[0].point).norm();
        stretch.push(ctx.pose.to_machine(w[0].point));
        if along > reach {
            break;
        }
    }
    stretch.reverse();
    EndPath::new(&stretch)
}

fn autonomous_attempt(
    ctx: &mut CurveCtx,
    design: &[DesignPoint],
    closed: bool,
    res: &mut CurveResult,
) -> Option<Vec<Measured>> {
    let task = autonomous_task(ctx, design, closed)?;
    let t0 = ctx.cmm.readings().time_s;
    let start = autonomous_start(ctx.probe, &task, ctx.free, &ctx.modes);
    if let Some(c) = position(ctx, start) {
        res.record(
            AttemptMode::Autonomous,
            struck_on_the_way(ctx, c, t0),
            &ctx.pose,
        );
        return None;
    }
    let (mut attempt, stalled) = autonomous_scan(ctx.cmm, (ctx.probe, ctx.free), &task, &ctx.modes);
    attempt.machine_time_s = ctx.cmm.readings().time_s - t0;
    if let Some(at) = stalled {
        let p = ctx.pose.to_part(at);
        let drive = ctx.modes.autonomous_stall_mm;
        res.notes.push(format!(
            "the autonomous scan stalled with the ball centre at ({:.3}, {:.3}, {:.3}) (part frame): it moved less than {:.1} mm while driven {:.1} mm along",
            p.x, p.y, p.z, STALL_MOVE_SHARE * drive, drive
        ));
    } else if attempt.outcome == Outcome::Aborted {
        res.notes.push(format!(
            "the autonomous scan did not come back to its start or reach its end within {:.1} mm (three times the section's {:.1} mm and 10 mm)",
            task.longest_mm(),
            task.nominal_length_mm
        ));
    }
    let points = attempt.points.clone();
    (res.record(AttemptMode::Autonomous, attempt, &ctx.pose) == Outcome::Completed)
        .then_some(points)
}

/// Replaces the design data by an autonomous scan's surface points.
fn autonomous_design(
    ctx: &mut CurveCtx,
    design: &[DesignPoint],
    closed: bool,
    res: &mut CurveResult,
) -> Option<Vec<DesignPoint>> {
    let points = autonomous_attempt(ctx, design, closed, res)?;
    let new: Vec<DesignPoint> = points
        .iter()
        .map(|m| DesignPoint {
            point: ctx.pose.to_part(m.point),
            normal: ctx.pose.rotation.transpose() * m.normal,
        })
        .collect();
    let new = trim_overlap(new, closed, ctx.settings.pitch_mm);
    res.corrections
        .push(CorrectionReport::Autonomous { points: new.len() });
    res.learned = Some(super::Learned::Replaced(new.clone()));
    (new.len() >= 4).then_some(new)
}

/// A closed autonomous trace ends near its start: drop the overlap.
fn trim_overlap(mut pts: Vec<DesignPoint>, closed: bool, pitch: f64) -> Vec<DesignPoint> {
    if closed {
        while pts.len() > 4
            && pts
                .last()
                .zip(pts.first())
                .is_some_and(|(a, b)| (a.point - b.point).norm() < 0.75 * pitch)
        {
            pts.pop();
        }
    }
    pts
}

/// Speed planning options from the mode's acceleration limits (speed and
/// control cycle still to be set).
pub fn base_speed(modes: &ModeOptions) -> SpeedOptions {
    SpeedOptions {
        a_lat_mm_s2: modes.lateral_accel_mm_s2,
        a_tan_mm_s2: modes.tangential_accel_mm_s2,
        ..SpeedOptions::default()
    }
}
