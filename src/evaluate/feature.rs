//! A feature's report from its measurement and its evaluated points:
//! statistics, the tolerance verdict and the fitted element.
use super::fitted::fit_feature;
use super::model::{FeatureReport, PointReport, Stats, Tolerance, Verdict};
use crate::host::inspect::feature::MeasuredFeature;
use crate::program::Feature;

/// The feature's report from its measurement and its evaluated points
/// (with the fitted element, which can fail a feature in tolerance).
pub fn feature_report(
    feature: &Feature,
    measured: MeasuredFeature,
    points: Vec<PointReport>,
) -> FeatureReport {
    let mut report = deviation_report(feature.name(), measured, points);
    if let Some(spec) = feature.fit() {
        report.fit = fit_feature(spec, &report.points);
        // A fit out of tolerance fails a feature in tolerance; a fit that
        // could not be made leaves it incomplete (its points out of
        // tolerance still fail it).
        let fit_status = report.fit.as_ref().map(|f| f.status);
        if report.status == Verdict::Pass {
            report.status = fit_status.unwrap_or(Verdict::Pass);
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
    let in_tol = (points.iter().filter(|p| p.on_surface()))
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
        deviation_mm: Stats::of((points.iter().filter(|p| p.on_surface())).map(|p| p.deviation_mm)),
        tolerance_mm: Tolerance { lower, upper },
        notes: results
            .iter()
            .flat_map(|r| r.notes.iter().cloned())
            .collect(),
        points,
        fit: None,
    }
}
