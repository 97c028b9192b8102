//! A point that lies on the true surface has no measurement error:
//! `deviation_mm - true_deviation_mm` is zero for it, also where it lies
//! past the end of the feature's faces, on a face the feature does not
//! name (the last point of an open scan running on a little). Such a
//! point is an edge point; a point inside the feature's face is not.
//!
//! The true part is the blade moved out by a constant 0.01 mm along its
//! normals, so `p + 0.01 n(p)` is a true surface point for every nominal
//! point `p` (the offset's definition, independent of any search).
mod common;

use cmm::evaluate::model::{FeatureReport, Stats, Tolerance, Verdict};
use cmm::evaluate::nominal::point_reports;
use cmm::evaluate::truth::{fill_true_deviations, Frames};
use cmm::host::inspect::record::FeatureKind;
use cmm::host::modes::Measured;
use cmm::math::{Mat3, Point3, Vec2, Vec3};
use cmm::program::Pose;
use cmm::world::as_machined::{AsMachined, AsMachinedSpec};
use common::*;

const OFFSET_MM: f64 = 0.01;

/// True surface points of face `face` at random parameters, with their
/// true normals.
fn true_points(wp: &cmm::workpiece::Workpiece, face: usize, n: usize, seed: u64) -> Vec<Measured> {
    let mut r = rng(seed);
    let f = &wp.faces[face];
    let ((u0, u1), (v0, v1)) = f.surface.domain();
    (0..n)
        .map(|_| {
            let uv = Vec2::new(uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            let (p, nrm) = (f.surface.point(uv.x, uv.y), f.surface.normal(uv.x, uv.y));
            let point = p + nrm * OFFSET_MM;
            Measured {
                point,
                normal: nrm,
                ball: point + nrm * 1.5,
                scales: point,
                reading: Vec3::zeros(),
                motion: Vec3::zeros(),
            }
        })
        .collect()
}

fn feature(points: Vec<cmm::evaluate::model::PointReport>) -> FeatureReport {
    let zero = Stats {
        min: 0.0,
        max: 0.0,
        mean: 0.0,
        rms: 0.0,
    };
    FeatureReport {
        name: "pressure".into(),
        kind: FeatureKind::SectionScan,
        status: Verdict::Pass,
        attempts: Vec::new(),
        corrections: Vec::new(),
        deviation_mm: zero,
        tolerance_mm: Tolerance {
            lower: -1.0,
            upper: 1.0,
        },
        notes: Vec::new(),
        fit: None,
        points,
    }
}

#[test]
fn points_on_the_true_surface_past_the_feature_s_faces_have_no_measurement_error() {
    let wp = example("blade");
    let spec: AsMachinedSpec = serde_json::from_str(&format!(
        r#"{{"form":[{{"kind":"offset","mm":{OFFSET_MM}}}]}}"#
    ))
    .unwrap();
    let am = AsMachined::from_spec(&spec, &wp).unwrap();
    let (pressure, suction) = (
        wp.face_index("pressure").unwrap(),
        wp.face_index("suction").unwrap(),
    );
    let pose = Pose {
        rotation: Mat3::identity(),
        translation: Vec3::new(350.0, 500.0, 150.0),
    };
    let mut measured = true_points(&wp, pressure, 150, 11);
    measured.extend(true_points(&wp, suction, 600, 12));
    let to_machine: Vec<Measured> = (measured.iter())
        .map(|m| Measured {
            point: pose.to_machine(m.point),
            ball: pose.to_machine(m.ball),
            ..*m
        })
        .collect();
    let reports = point_reports(&wp, &pose, (&[pressure], None), &to_machine);
    assert_eq!(reports.len(), measured.len());
    let mut features = [feature(reports)];
    let frames = Frames {
        reported: pose,
        world: pose,
    };
    fill_true_deviations(&mut features, &[&[pressure]], &wp, &am, frames);
    let (mut inside, mut beyond) = (0, 0);
    for (k, (p, m)) in features[0].points.iter().zip(&measured).enumerate() {
        let err = p.deviation_mm - p.true_deviation_mm;
        assert!(err.abs() < 1e-7, "{:?}: error {err}", m.point);
        let q = Point3::from(p.measured);
        let foot = Point3::from(p.nominal);
        let n = Vec3::from(p.normal);
        let tangential = ((q - foot) - n * (q - foot).dot(&n)).norm();
        // The pressure side's own points are off it by the offset only;
        // suction points past its edge are edge points.
        if k < 150 {
            assert!(!p.edge, "{q}");
            assert!(
                (p.deviation_mm - OFFSET_MM).abs() < 1e-7,
                "{q}: {}",
                p.deviation_mm
            );
            inside += 1;
        } else if tangential > 1e-3 {
            assert!(p.edge, "{q}: {tangential} past the edge");
            beyond += 1;
        }
    }
    assert!(
        inside == 150 && beyond >= 100,
        "{inside} inside, {beyond} beyond"
    );
}
