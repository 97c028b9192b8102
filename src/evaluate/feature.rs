//! A feature's report from its measurement and its evaluated points:
//! statistics, the tolerance verdict and the fitted element.
use super::fitted::{fit_feature, FitResult};
use super::model::{FeatureReport, PointReport, Stats, Tolerance, Verdict};
use crate::formats::serde_name;
use crate::host::inspect::feature::MeasuredFeature;
use crate::host::inspect::record::AttemptReport;
use crate::host::modes::Outcome;
use crate::program::Feature;

/// The feature's report from its measurement and its evaluated points
/// (with the fitted element, which can fail a feature in tolerance).
pub fn feature_report(
    feature: &Feature,
    measured: MeasuredFeature,
    points: Vec<PointReport>,
) -> FeatureReport {
    let report = deviation_report(feature.name(), measured, points);
    match feature.fit() {
        Some(spec) => {
            let fit = fit_feature(spec, &report.points);
            with_fit(report, fit)
        }
        None => report,
    }
}

/// `report` with its fitted element. A fit out of tolerance fails a
/// feature in tolerance; a fit that could not be made leaves it incomplete
/// (its points out of tolerance still fail it). The fit of a feature whose
/// measuring did not complete is shown but not judged: its points cover
/// only part of the element (a circle measured over a fifth of its
/// round), so its size, form and position say little of the element's.
fn with_fit(mut report: FeatureReport, mut fit: Option<FitResult>) -> FeatureReport {
    if report.status == Verdict::Incomplete {
        if let Some(f) = fit.as_mut() {
            f.not_judged();
        }
    }
    if report.status == Verdict::Pass {
        report.status = fit.as_ref().map_or(Verdict::Pass, |f| f.status);
    }
    report.fit = fit;
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
    // A feature that measured no point off the design's edges has not
    // been measured: it has no deviation to judge.
    let on_surface = points.iter().filter(|p| p.on_surface()).count();
    let complete = results.iter().all(|r| r.complete) && on_surface > 0;
    let in_tol = (points.iter().filter(|p| p.on_surface()))
        .all(|p| p.deviation_mm >= lower && p.deviation_mm <= upper);
    let status = match (complete, in_tol) {
        (false, _) => Verdict::Incomplete,
        (true, true) => Verdict::Pass,
        (true, false) => Verdict::Fail,
    };
    let attempts: Vec<AttemptReport> = results
        .iter()
        .flat_map(|r| r.attempts.iter().cloned())
        .collect();
    let mut notes: Vec<String> = results
        .iter()
        .flat_map(|r| r.notes.iter().cloned())
        .collect();
    let off_section = points.iter().filter(|p| p.off_section).count();
    if status == Verdict::Incomplete && on_surface == 0 && !points.is_empty() {
        notes.push(format!(
            "not evaluated: each of the {} measured points lies on an edge of the design \
             (the ball rolled over it), so none has a deviation",
            points.len()
        ));
    }
    if off_section > 0 {
        notes.push(format!(
            "{off_section} of the {} points lie off the section plane by more than {} mm \
             (the probe's contact could not be held in the plane there): fits leave them out",
            points.len(),
            crate::evaluate::nominal::OFF_SECTION_MM
        ));
    }
    if status == Verdict::Incomplete && notes.is_empty() {
        notes.push(why_incomplete(&attempts, points.len()));
    }
    FeatureReport {
        name: name.to_string(),
        kind,
        status,
        attempts,
        corrections: results
            .iter()
            .flat_map(|r| r.corrections.iter().cloned())
            .collect(),
        deviation_mm: Stats::of((points.iter().filter(|p| p.on_surface())).map(|p| p.deviation_mm)),
        tolerance_mm: Tolerance { lower, upper },
        notes,
        points,
        fit: None,
    }
}

/// Why a feature whose measuring left no note is incomplete: the last
/// attempt that did not complete (and what struck, for a collision), or
/// that no point was measured.
fn why_incomplete(attempts: &[AttemptReport], points: usize) -> String {
    let failed = attempts
        .iter()
        .rev()
        .find(|a| a.outcome != Outcome::Completed);
    match (failed, points) {
        (Some(a), _) => {
            let struck = (a.collision.as_ref())
                .map(|c| {
                    format!(
                        " (the {} struck the part while the probe was in phase {})",
                        c.probe_part, c.phase
                    )
                })
                .unwrap_or_default();
            format!(
                "not measured: the last attempt that did not complete, {}, ended in {}{struck}",
                serde_name(&a.mode),
                serde_name(&a.outcome)
            )
        }
        (None, 0) if attempts.is_empty() => "not measured: nothing to measure".to_string(),
        (None, 0) => "not measured: the attempts completed without measuring a point".to_string(),
        (None, _) => "not every curve of the feature was measured".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::inspect::record::{AttemptMode, CollisionReport, FeatureKind};
    use crate::host::inspect::CurveResult;
    use crate::program::FitSpec;

    fn attempt(mode: AttemptMode, outcome: Outcome) -> AttemptReport {
        AttemptReport {
            mode,
            outcome,
            machine_time_s: 1.0,
            points: 0,
            max_trajectory_error_mm: 0.0,
            collision: None,
        }
    }

    /// An incomplete feature with no note from its measuring says what
    /// ended it: the last attempt that did not complete (what struck, in
    /// which phase), or that the attempts measured no point.
    #[test]
    fn an_incomplete_feature_says_why() {
        let mut struck = attempt(AttemptMode::Points, Outcome::Collision);
        struck.collision = Some(CollisionReport {
            probe_part: "shaft",
            at_mm: [0.0; 3],
            speed_mm_s: 10.0,
            phase: "touch",
        });
        let done = attempt(AttemptMode::Active, Outcome::Completed);
        let note = why_incomplete(&[struck, done.clone()], 0);
        assert!(note.contains("points, ended in collision"), "{note}");
        assert!(
            note.contains("shaft struck the part") && note.contains("touch"),
            "{note}"
        );
        let note = why_incomplete(&[done.clone(), done], 0);
        assert!(note.contains("without measuring a point"), "{note}");
        let lost = attempt(AttemptMode::Autonomous, Outcome::LostContact);
        assert!(why_incomplete(&[lost], 3).contains("autonomous, ended in lost_contact"));
    }

    /// Touch points that all landed on edges of the design leave nothing
    /// to judge: the feature is incomplete and says so, whatever its
    /// tolerance; one point off the edges makes it pass.
    #[test]
    fn a_feature_with_only_edge_points_is_incomplete() {
        let point = |edge: bool| PointReport {
            measured: [0.0; 3],
            nominal: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            deviation_mm: 0.001,
            true_deviation_mm: 0.001,
            edge,
            off_section: false,
            in_section: None,
            measured_in_section: None,
        };
        let measured = || MeasuredFeature {
            results: vec![CurveResult {
                attempts: vec![attempt(AttemptMode::Points, Outcome::Completed)],
                corrections: Vec::new(),
                points: Vec::new(),
                complete: true,
                notes: Vec::new(),
                learned: None,
                points_before_stop: false,
            }],
            faces: vec![0],
            tolerance: (-0.01, 0.01),
            kind: FeatureKind::TouchPoints,
        };
        let all_edge = deviation_report("top", measured(), vec![point(true); 3]);
        assert_eq!(all_edge.status, Verdict::Incomplete);
        assert!(
            all_edge
                .notes
                .iter()
                .any(|n| n.contains("each of the 3 measured points lies on an edge")),
            "{:?}",
            all_edge.notes
        );
        let one_off = deviation_report("top", measured(), vec![point(true), point(false)]);
        assert_eq!(one_off.status, Verdict::Pass);
    }

    /// A circle's points over a fifth of its round, measured by a scan
    /// that ended early: the fit is made and shown, but neither passes nor
    /// fails the feature; the same points from a scan that completed do.
    #[test]
    fn the_fit_of_an_incomplete_feature_is_not_judged() {
        let arc: Vec<PointReport> = (0..20)
            .map(|k| {
                let t = 0.4 * std::f64::consts::PI * k as f64 / 19.0;
                let p = [5.0 * t.cos(), 5.0 * t.sin(), 0.0];
                PointReport {
                    measured: p,
                    nominal: p,
                    normal: [t.cos(), t.sin(), 0.0],
                    deviation_mm: 0.0,
                    true_deviation_mm: 0.0,
                    edge: false,
                    off_section: false,
                    in_section: None,
                    measured_in_section: None,
                }
            })
            .collect();
        let spec = FitSpec {
            element: crate::program::FitElement::Circle,
            size_mm: Some([-0.01, 0.01]),
            form_mm: Some(0.01),
            position_mm: Some(0.01),
        };
        let report = |complete: bool| {
            let measured = MeasuredFeature {
                results: vec![CurveResult {
                    attempts: vec![attempt(AttemptMode::Active, Outcome::Completed)],
                    corrections: Vec::new(),
                    points: Vec::new(),
                    complete,
                    notes: Vec::new(),
                    learned: None,
                    points_before_stop: false,
                }],
                faces: vec![0],
                tolerance: (-0.01, 0.01),
                kind: FeatureKind::SectionScan,
            };
            let r = deviation_report("bore", measured, arc.clone());
            with_fit(r, fit_feature(&spec, &arc))
        };
        let done = report(true);
        assert_eq!(done.status, Verdict::Pass);
        assert_eq!(done.fit.as_ref().map(|f| f.status), Some(Verdict::Pass));
        let cut = report(false);
        assert_eq!(cut.status, Verdict::Incomplete);
        let fit = cut.fit.unwrap_or_else(|| panic!("no fit"));
        assert_eq!(fit.status, Verdict::Incomplete);
        assert!(fit.measured.is_some(), "{fit:?}");
        assert!(fit.error.is_some_and(|e| e.contains("not judged")));
    }
}
