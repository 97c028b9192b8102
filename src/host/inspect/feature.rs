//! One feature of a program measured on the machine, with the
//! supervisor's corrections and fallbacks.
use super::corners::{own_faces, section_design, CornerOptions};
use super::correction::DesignPoint;
use super::design_memo::DesignMemo;
use super::reach::{Reach, Unreachable};
use super::record::{AttemptMode, FeatureKind};
use super::supervisor::{scan_curve, SupervisorOptions};
use super::{CurveCtx, CurveResult, LearnedSet};
use crate::host::modes::{touch_point, FreeSpace, HostProbe, ModeOptions, Outcome};
use crate::host::observe::Machine;
use crate::program::{Feature, Program};

/// What a feature's measurement needs besides the machine.
pub struct Run<'r> {
    /// The program (in its aligned placement).
    pub program: &'r Program,
    /// The probe as the host knows it.
    pub probe: HostProbe,
    /// Mode gains and thresholds.
    pub modes: &'r ModeOptions,
    /// Supervisor limits.
    pub supervisor: SupervisorOptions,
    /// Corrections learned on earlier parts.
    pub learned: &'r LearnedSet,
    /// Free space for direct moves (`None`: always over the clearance
    /// height).
    pub free: Option<&'r dyn FreeSpace>,
    /// Section designs shared with the program's other runs.
    pub designs: &'r DesignMemo,
}

/// A feature as measured, before its points are evaluated.
pub struct MeasuredFeature {
    /// Each section curve's result (one for touch points).
    pub results: Vec<CurveResult>,
    /// The nominal faces the feature's points are evaluated against.
    pub faces: Vec<usize>,
    /// Tolerance band (lower, upper), mm.
    pub tolerance: (f64, f64),
    /// Section scan or touch points.
    pub kind: FeatureKind,
}

/// Measures one feature on the machine (with the supervisor's
/// corrections and fallbacks), recording what it learned.
pub fn measure_feature(
    run: &Run<'_>,
    feature: &Feature,
    cmm: &mut dyn Machine,
    learned_out: &mut LearnedSet,
) -> MeasuredFeature {
    let Run {
        program,
        probe,
        modes,
        supervisor,
        learned: known,
        free,
        designs,
    } = *run;
    let reach = free.map(|free| Reach {
        free,
        pose: program.placement,
        probe,
        modes,
        press_mm: 0.0,
    });
    let (results, faces, tolerance, kind) = match feature {
        Feature::Section {
            name,
            plane,
            faces,
            curves,
            settings,
            tolerance,
            ..
        } => {
            let results: Vec<CurveResult> = curves
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    let r = probe.tip_radius_mm;
                    let design = designs.design((name, k), r, || {
                        let design: Vec<DesignPoint> = (c.points.iter())
                            .map(|p| DesignPoint {
                                point: p.point,
                                normal: p.normal,
                            })
                            .collect();
                        let on = (&program.workpiece, plane.normal());
                        let corners = CornerOptions::default();
                        section_design((&design, &own_faces(c)), c.closed, on, r, &corners)
                    });
                    if design.len() < 2 {
                        return not_measured(Unreachable::TooNarrow);
                    }
                    // No route: not started (the repositioning would refuse
                    // it). A probe that would strike the part on the way is
                    // noted and the scan runs: the machine's own collision
                    // stop ends it where it strikes.
                    let reach = reach.map(|r| Reach {
                        press_mm: settings.deflection_mm,
                        ..r
                    });
                    let (verdict, order) =
                        reach.map_or((Ok(()), None), |r| r.curve_either_way(&design, c.closed));
                    let warning = match verdict {
                        Err(u @ Unreachable::NoRoute { .. }) => return not_measured(u),
                        Err(u) => Some(format!("{u}")),
                        Ok(()) => None,
                    };
                    let mut design = order.unwrap_or_else(|| design.to_vec());
                    // A probe that strikes the part somewhere along the
                    // curve: the scan starts where it measures the
                    // longest clear stretch before the collision stop.
                    if let (Err(Unreachable::Strikes { .. }), Some(r)) = (verdict, reach) {
                        design = r.clearest_order(&design, c.closed).unwrap_or(design);
                    }
                    let key = (name.clone(), k);
                    let learned = known
                        .iter()
                        .find(|(kk, _)| *kk == key)
                        .map(|(_, l)| l.clone());
                    let mut ctx = CurveCtx {
                        cmm: &mut *cmm,
                        probe,
                        pose: program.placement,
                        plane_normal: plane.normal(),
                        settings: *settings,
                        modes: *modes,
                        supervisor,
                        learned,
                        free,
                    };
                    let mut res = scan_curve(&mut ctx, design, c.closed, settings.mode);
                    res.notes.extend(warning);
                    if let Some(l) = &res.learned {
                        learned_out.push((key, l.clone()));
                    }
                    res
                })
                .collect();
            (results, faces.clone(), *tolerance, FeatureKind::SectionScan)
        }
        Feature::Touch {
            points, tolerance, ..
        } => {
            let mut res = CurveResult {
                complete: true,
                ..CurveResult::default()
            };
            for (k, p) in points.iter().enumerate() {
                let d = DesignPoint {
                    point: p.point,
                    normal: p.normal,
                };
                match reach.map(|r| r.touch(&d)) {
                    Some(Err(u @ Unreachable::NoRoute { .. })) => {
                        res.notes.push(format!("touch point not measured: {u}"));
                        res.complete = false;
                        continue;
                    }
                    Some(Err(u)) => res.notes.push(format!("touch point: {u}")),
                    _ => {}
                }
                let (m, n) = (
                    program.placement.to_machine(p.point),
                    program.placement.dir_to_machine(p.normal),
                );
                let a = touch_point(cmm, (probe, free), m, n, 6.0, modes);
                let (ok, struck) = (
                    a.outcome == Outcome::Completed,
                    a.outcome == Outcome::Collision,
                );
                let pts = a.points.clone();
                res.record(AttemptMode::Points, a, &program.placement);
                res.complete &= ok;
                res.points.extend(pts);
                // A machine stops at a crash: the points after it are not
                // driven into the part one by one.
                let left = points.len() - k - 1;
                if struck && left > 0 {
                    let points = if left == 1 { "point" } else { "points" };
                    res.notes.push(format!(
                        "{left} touch {points} after the collision not measured"
                    ));
                    break;
                }
            }
            (
                vec![res],
                (0..program.workpiece.faces.len()).collect(),
                *tolerance,
                FeatureKind::TouchPoints,
            )
        }
    };
    MeasuredFeature {
        results,
        faces,
        tolerance,
        kind,
    }
}

/// The result of a curve the probe cannot measure.
fn not_measured(why: Unreachable) -> CurveResult {
    CurveResult {
        notes: vec![format!("not measured: {why}")],
        ..CurveResult::default()
    }
}
