#![allow(dead_code)]
//! A hand-built report for the writer tests: a passing scan on a circle
//! (with a failed first attempt and a correction), a failing open section
//! whose name needs escaping, and an incomplete feature without points.
use std::f64::consts::PI;

use cmm::host::modes::Outcome;
use cmm::report::*;

/// Tolerance of every feature, mm.
pub const TOL: f64 = 0.05;

/// Name of the failing feature (needs CSV quoting and XML escaping).
pub const FAIL_NAME: &str = "edge \"A\", <B&C>";

fn attempt(mode: AttemptMode, outcome: Outcome, time: f64, points: usize) -> AttemptReport {
    AttemptReport {
        mode,
        outcome,
        machine_time_s: time,
        points,
        max_trajectory_error_mm: 0.01,
        collision: None,
    }
}

fn point(nominal: [f64; 3], normal: [f64; 3], dev: f64, true_dev: f64) -> PointReport {
    let measured = [0, 1, 2].map(|k| nominal[k] + normal[k] * dev);
    PointReport {
        measured,
        nominal,
        normal,
        deviation_mm: dev,
        true_deviation_mm: true_dev,
        edge: false,
        off_section: false,
        in_section: None,
        measured_in_section: None,
    }
}

fn feature(name: &str, status: Verdict, points: Vec<PointReport>) -> FeatureReport {
    FeatureReport {
        fit: None,
        name: name.to_string(),
        kind: FeatureKind::SectionScan,
        status,
        attempts: vec![],
        corrections: vec![],
        deviation_mm: Stats::of(points.iter().map(|p| p.deviation_mm)),
        tolerance_mm: Tolerance {
            lower: -TOL,
            upper: TOL,
        },
        notes: vec![],
        points,
    }
}

/// 72 points on a circle of radius 20 mm in the plane z = 5, normals radial.
fn ring() -> FeatureReport {
    let points = (0..72)
        .map(|k| {
            let t = k as f64 * 2.0 * PI / 72.0;
            let (s, c) = t.sin_cos();
            let dev = 0.03 * (3.0 * t).sin() + 0.001 / 3.0;
            point(
                [20.0 * c, 20.0 * s, 5.0],
                [c, s, 0.0],
                dev,
                dev - 0.0003 * c,
            )
        })
        .collect();
    let mut f = feature("ring", Verdict::Pass, points);
    f.attempts = vec![
        attempt(AttemptMode::Active, Outcome::TrajectoryError, 2.5, 20),
        attempt(AttemptMode::Active, Outcome::Completed, 7.25, 72),
    ];
    f.corrections = vec![CorrectionReport::Geometric {
        model: "translation".into(),
        max_residual_mm: 0.0123,
        points: 6,
        source: "fitted",
    }];
    f.notes = vec!["trajectory error in the first attempt; corrected".into()];
    f
}

/// An open S-shaped section in the x-z plane with a bump out of tolerance.
fn edge() -> FeatureReport {
    let points = (0..40)
        .map(|k| {
            let x = k as f64 * 1.5;
            let z = 4.0 * (x / 10.0).sin();
            let slope = 0.4 * (x / 10.0).cos();
            let len = (1.0 + slope * slope).sqrt();
            let dev = 0.09 * (-((x - 30.0) / 6.0).powi(2)).exp() - 0.01;
            point([x, 2.0, z], [-slope / len, 0.0, 1.0 / len], dev, dev + 1e-4)
        })
        .collect();
    let mut f = feature(FAIL_NAME, Verdict::Fail, points);
    f.attempts = vec![attempt(AttemptMode::Passive, Outcome::Completed, 4.125, 40)];
    f
}

/// Nothing measured: contact lost, then the autonomous scan was aborted.
fn pocket() -> FeatureReport {
    let mut f = feature("pocket", Verdict::Incomplete, vec![]);
    f.attempts = vec![
        attempt(AttemptMode::Active, Outcome::LostContact, 1.5, 0),
        attempt(AttemptMode::Autonomous, Outcome::Aborted, 3.0, 0),
    ];
    f.corrections = vec![CorrectionReport::Autonomous { points: 0 }];
    f.notes = vec!["stylus lost contact at the pocket edge".into()];
    f
}

/// The whole report.
pub fn report() -> Report {
    let features = vec![ring(), edge(), pocket()];
    let machine_time_s = features
        .iter()
        .flat_map(|f| &f.attempts)
        .map(|a| a.machine_time_s)
        .sum();
    Report {
        format: REPORT_FORMAT,
        program: "blade-7 <demo>".into(),
        seed: 42,
        status: Verdict::Incomplete,
        machine_time_s,
        wall_time_s: 0.0125,
        part_to_machine: PartToMachine {
            rotation: [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            translation_mm: [250.0, 120.5, -30.25],
        },
        ideal: false,
        alignment: None,
        probe: ProbeUsed {
            source: "nominal".into(),
            tip_radius_mm: 1.5,
            probe_vector_mm: [0.0, 0.0, -60.0],
        },
        features,
        end_move: EndMoveReport {
            outcome: Outcome::Completed,
            machine_time_s: 0.0,
            collision: None,
        },
    }
}
