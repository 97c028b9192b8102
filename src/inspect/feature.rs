//! One feature of a program: its measurement on the machine, then its
//! report from the evaluated points.
use super::behind::Queue;
use super::correction::DesignPoint;
use super::fitted::fit_feature;
use super::prepared::Prepared;
use super::supervisor::scan_curve;
use super::{Ctx, CurveResult, LearnedSet, LivePoints, RunOptions};
use crate::host::machine::Cmm;
use crate::host::modes::{touch_point, FreeSpace, HostProbe, ModeOptions, Outcome};
use crate::program::{Feature, Program};
use crate::report::{FeatureReport, PointReport, Stats, Tolerance, Verdict};

/// What a feature's measurement needs besides the machine.
pub(super) struct Run<'r> {
    pub(super) program: &'r Program,
    pub(super) probe: HostProbe,
    pub(super) modes: &'r ModeOptions,
    pub(super) opts: &'r RunOptions,
    pub(super) free: &'r dyn FreeSpace,
    /// Where scans hand over their points while they run.
    pub(super) live: Option<&'r dyn LivePoints>,
    /// Scans planned before the measuring.
    pub(super) prepared: &'r Prepared,
}

/// A feature as measured, before its points are evaluated.
pub(super) struct MeasuredFeature {
    results: Vec<CurveResult>,
    pub(super) faces: Vec<usize>,
    tolerance: (f64, f64),
    kind: &'static str,
}

impl MeasuredFeature {
    /// The streams that carry the feature's points, in measuring order:
    /// each curve's live stream when its points came in one, else its
    /// points handed over now.
    pub(super) fn hand_over(&self, queue: &Queue) -> Vec<usize> {
        (self.results.iter())
            .filter_map(|r| match r.stream {
                Some(s) => Some(s),
                None if r.points.is_empty() => None,
                None => Some(queue.submit(&self.faces, &r.points)),
            })
            .collect()
    }
}

/// Measures one feature on the machine (with the supervisor's
/// corrections and fallbacks), recording what it learned.
pub(super) fn measure_feature(
    run: &Run<'_>,
    index: usize,
    feature: &Feature,
    cmm: &mut dyn Cmm,
    learned_out: &mut LearnedSet,
) -> MeasuredFeature {
    let Run {
        program,
        probe,
        modes,
        opts,
        free,
        live,
        prepared,
    } = *run;
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
                    let design: Vec<DesignPoint> = c
                        .points
                        .iter()
                        .map(|p| DesignPoint {
                            point: p.point,
                            normal: p.normal,
                        })
                        .collect();
                    let key = (name.clone(), k);
                    let learned = opts
                        .learned
                        .iter()
                        .find(|(kk, _)| *kk == key)
                        .map(|(_, l)| l.clone());
                    let mut ctx = Ctx {
                        cmm: &mut *cmm,
                        probe,
                        pose: program.placement,
                        plane_normal: plane.normal(),
                        settings: *settings,
                        modes: *modes,
                        supervisor: opts.supervisor,
                        learned,
                        free: opts.direct_moves.then_some(free),
                        live: live.map(|l| (l, faces.as_slice())),
                        prepared: prepared.get(index, k),
                    };
                    let res = scan_curve(&mut ctx, design, c.closed, settings.mode);
                    if let Some(l) = &res.learned {
                        learned_out.push((key, l.clone()));
                    }
                    res
                })
                .collect();
            (results, faces.clone(), *tolerance, "section_scan")
        }
        Feature::Touch {
            points, tolerance, ..
        } => {
            let mut res = CurveResult {
                complete: true,
                ..CurveResult::default()
            };
            for p in points {
                let (m, n) = (
                    program.placement.to_machine(p.point),
                    program.placement.dir_to_machine(p.normal),
                );
                let a = touch_point(cmm, probe, m, n, 6.0, modes);
                let ok = a.outcome == Outcome::Completed;
                let pts = a.points.clone();
                res.record("points", a);
                res.complete &= ok;
                res.points.extend(pts);
            }
            (
                vec![res],
                (0..program.workpiece.faces.len()).collect(),
                *tolerance,
                "touch_points",
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

/// The feature's report from its measurement and its evaluated points
/// (with the fitted element, which can fail a feature in tolerance).
pub(super) fn feature_report(
    feature: &Feature,
    measured: MeasuredFeature,
    points: Vec<PointReport>,
) -> FeatureReport {
    let mut report = deviation_report(feature.name(), measured, points);
    if let Some(spec) = feature.fit() {
        report.fit = fit_feature(spec, &report.points);
        if report.status == Verdict::Pass
            && report
                .fit
                .as_ref()
                .is_some_and(|f| f.status != Verdict::Pass)
        {
            report.status = Verdict::Fail;
        }
    }
    report
}

fn deviation_report(
    name: &str,
    measured: MeasuredFeature,
    points: Vec<PointReport>,
) -> FeatureReport {
    let MeasuredFeature {
        results,
        tolerance: (lower, upper),
        kind,
        ..
    } = measured;
    // A feature that measured no point has not been measured.
    let complete = results.iter().all(|r| r.complete) && !points.is_empty();
    let in_tol = points
        .iter()
        .all(|p| p.deviation_mm >= lower && p.deviation_mm <= upper);
    let status = match (complete, in_tol) {
        (false, _) => Verdict::Incomplete,
        (true, true) => Verdict::Pass,
        (true, false) => Verdict::Fail,
    };
    FeatureReport {
        name: name.to_string(),
        kind,
        status,
        attempts: results
            .iter()
            .flat_map(|r| r.attempts.iter().cloned())
            .collect(),
        corrections: results
            .iter()
            .flat_map(|r| r.corrections.iter().cloned())
            .collect(),
        deviation_mm: Stats::of(points.iter().map(|p| p.deviation_mm)),
        tolerance_mm: Tolerance { lower, upper },
        notes: results
            .iter()
            .flat_map(|r| r.notes.iter().cloned())
            .collect(),
        points,
        fit: None,
    }
}
