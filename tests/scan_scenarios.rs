//! The simulated CMM and the error-correcting scan, end to end with an ideal
//! machine: points on the true surface, the right failures, the right
//! corrections.
mod common;

use cmm::app::{load, run_program, RunOptions};
use cmm::formats::serde_name;
use cmm::report::{CorrectionReport, Report, Verdict};
use serde_json::{json, Value};

fn program(as_machined: Value, features: Value) -> Value {
    json!({
        "format": "cmm-program/1", "name": "t",
        "workpiece": common::repo("workpieces/blade.json").to_string_lossy(),
        "placement": { "translate_mm": [350, 500, 150], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "as_machined": as_machined,
        "features": features
    })
}

fn section(name: &str, z: f64, mode: &str) -> Value {
    json!({ "name": name, "type": "section_scan", "plane": { "origin_mm": [0, 0, z], "normal": [0, 0, 1] },
            "mode": mode, "tolerance_mm": [-3.0, 3.0] })
}

fn run(v: &Value, seed: u64, ideal: bool) -> Report {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("p.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let prog = load(&p).unwrap();
    run_program(
        &prog,
        &RunOptions {
            seed,
            ideal,
            ..RunOptions::default()
        },
    )
    .unwrap()
    .0
}

fn outcomes(r: &Report, k: usize) -> Vec<String> {
    r.features[k]
        .attempts
        .iter()
        .map(|a| format!("{}:{}", serde_name(&a.mode), serde_name(&a.outcome)))
        .collect()
}

/// Ideal machine: measured points on the true surface and reported
/// deviations equal to the true ones, within 0.5 um.
fn assert_exact(r: &Report, k: usize) {
    let f = &r.features[k];
    assert!(!f.points.is_empty());
    for p in &f.points {
        assert!(
            (p.deviation_mm - p.true_deviation_mm).abs() < 5e-4,
            "{}: measured {} true {}",
            f.name,
            p.deviation_mm,
            p.true_deviation_mm
        );
    }
}

#[test]
fn small_deviations_scan_in_one_active_attempt_open_and_closed() {
    let am = json!({ "form": [ { "kind": "bump", "center_mm": [30, 12, 60], "radius_mm": 8, "height_mm": 0.3 },
                               { "kind": "offset", "mm": -0.2 } ] });
    let r = run(
        &program(
            am,
            json!([section("closed", 60.0, "active"), { "name": "open", "type": "section_scan",
        "plane": { "origin_mm": [0, 0, 40], "normal": [0, 0, 1] }, "surfaces": ["suction"], "mode": "passive", "tolerance_mm": [-1, 1] }]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&r, 0), ["active:completed"]);
    assert_eq!(outcomes(&r, 1), ["passive:completed"]);
    for k in 0..2 {
        assert_exact(&r, k);
    }
    // The closed section is covered all round (0.5 mm pitch over ~112 mm).
    assert!(
        r.features[0].points.len() > 180,
        "{}",
        r.features[0].points.len()
    );
    assert_eq!(r.status, Verdict::Pass);
}

#[test]
fn active_tolerates_one_millimetre_and_fails_at_two() {
    let ok = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": 1.0 } ] }),
            json!([section("a", 60.0, "active")]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&ok, 0), ["active:completed"]);
    assert_exact(&ok, 0);
    let bad = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": 2.0 } ] }),
            json!([section("a", 60.0, "active")]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&bad, 0), ["active:trajectory_error"]);
    assert_eq!(bad.status, Verdict::Incomplete);
}

#[test]
fn passive_fails_beyond_its_deflection_margin() {
    let under = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": -0.6 } ] }),
            json!([section("a", 60.0, "passive")]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&under, 0), ["passive:lost_contact"]);
    let over = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": 0.7 } ] }),
            json!([section("a", 60.0, "passive")]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&over, 0), ["passive:over_deflection"]);
}

#[test]
fn autonomous_scanning_closes_a_section_without_design_data() {
    let r = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": 0.5 } ] }),
            json!([section("a", 60.0, "autonomous")]),
        ),
        1,
        true,
    );
    assert_eq!(outcomes(&r, 0), ["autonomous:completed"]);
    assert_exact(&r, 0);
    assert!(r.features[0].points.len() > 180);
}

fn geometric_models(r: &Report, k: usize) -> Vec<String> {
    r.features[k]
        .corrections
        .iter()
        .map(|c| match c {
            CorrectionReport::Geometric { model, .. } => model.clone(),
            CorrectionReport::Autonomous { .. } => "autonomous".into(),
        })
        .collect()
}

#[test]
fn uniform_undercut_shift_and_scale_get_one_geometric_correction() {
    let cases = [
        json!({ "form": [ { "kind": "offset", "mm": 2.5 } ] }),
        json!({ "transform": { "translate_mm": [2.0, 0, 0] } }),
        json!({ "transform": { "scale": 1.07, "about_mm": [30, 5, 60] } }),
    ];
    for am in cases {
        let r = run(
            &program(am.clone(), json!([section("a", 60.0, "auto")])),
            1,
            true,
        );
        assert_eq!(
            outcomes(&r, 0),
            [
                "active:trajectory_error",
                "points:completed",
                "active:completed"
            ],
            "{am}"
        );
        assert_eq!(geometric_models(&r, 0).len(), 1, "{am}");
        assert_exact(&r, 0);
    }
}

#[test]
fn a_local_gouge_needs_an_autonomous_correction() {
    // Centre the gouge on the suction side at z = 60 (mid-chord).
    let wp = common::example("blade");
    let plane =
        cmm::geometry::Plane::try_new([0.0, 0.0, 60.0].into(), [0.0, 0.0, 1.0].into()).unwrap();
    let curve = &cmm::workpiece::section_faces(&wp, &[1], &plane, &Default::default())[0];
    let c = curve.points[curve.points.len() / 2].point;
    // 0.6 mm deep: shallower than the ball radius less the shaft's, so
    // the vertical stylus follows it (a deeper gouge on a wall makes the
    // shaft strike the wall above it); past the 0.3 mm trajectory
    // tolerance.
    let am = json!({ "form": [ { "kind": "bump", "center_mm": [c.x, c.y, c.z], "radius_mm": 5, "height_mm": -0.6 } ] });
    let mut feature = section("a", 60.0, "auto");
    feature["trajectory_tolerance_mm"] = json!(0.3);
    let r = run(&program(am, json!([feature])), 1, true);
    let o = outcomes(&r, 0);
    assert_eq!(
        o.first().map(String::as_str),
        Some("active:trajectory_error"),
        "{o:?}"
    );
    assert!(o.contains(&"autonomous:completed".to_string()), "{o:?}");
    assert_eq!(
        o.last().map(String::as_str),
        Some("active:completed"),
        "{o:?}"
    );
    assert!(geometric_models(&r, 0).contains(&"autonomous".to_string()));
    assert_exact(&r, 0);
}

#[test]
fn same_seed_same_report_other_seed_other_noise() {
    let am = json!({ "form": [ { "kind": "offset", "mm": 0.1 } ], "roughness_um": 0.5 });
    let v = program(am, json!([section("a", 60.0, "active")]));
    let strip = |mut r: Report| {
        r.wall_time_s = 0.0;
        serde_json::to_string(&r).unwrap()
    };
    let (a, b, c) = (
        strip(run(&v, 7, false)),
        strip(run(&v, 7, false)),
        strip(run(&v, 8, false)),
    );
    assert_eq!(a, b);
    assert_ne!(a, c);
}

fn bore_program(as_machined: Value, features: Value) -> Value {
    let mut v = program(as_machined, features);
    v["workpiece"] = json!(common::repo("workpieces/bore.json").to_string_lossy());
    v
}

#[test]
fn bore_undercut_across_the_seam_and_a_shift_on_two_arcs() {
    // Closed section crossing the seam at u = 0: the bore 2 mm too large.
    let ring = json!([{ "name": "ring", "type": "section_scan", "plane": { "origin_mm": [0, 0, 10], "normal": [0, 0, 1] },
                        "mode": "auto", "tolerance_mm": [-3, 3] }]);
    let r = run(
        &bore_program(
            json!({ "form": [ { "kind": "offset", "mm": -2.0 } ] }),
            ring,
        ),
        1,
        true,
    );
    assert_eq!(
        outcomes(&r, 0),
        [
            "active:trajectory_error",
            "points:completed",
            "active:completed"
        ]
    );
    assert_exact(&r, 0);
    // A vertical plane cuts the wall twice: both arcs measured after one shift correction each.
    let arcs = json!([{ "name": "arcs", "type": "section_scan", "plane": { "origin_mm": [10, 0, 0], "normal": [1, 0, 0] },
                        "mode": "auto", "tolerance_mm": [-3, 3] }]);
    let r = run(
        &bore_program(
            json!({ "transform": { "translate_mm": [0, 2.0, 0] } }),
            arcs,
        ),
        1,
        true,
    );
    let o = outcomes(&r, 0);
    assert_eq!(
        o.iter().filter(|s| *s == "active:completed").count(),
        2,
        "{o:?}"
    );
    assert_eq!(r.features[0].status, Verdict::Pass, "{o:?}");
    assert_exact(&r, 0);
    let ys: Vec<f64> = r.features[0].points.iter().map(|p| p.measured[1]).collect();
    assert!(
        ys.iter().any(|&y| y > 0.0) && ys.iter().any(|&y| y < 0.0),
        "both arcs have points"
    );
}

#[test]
fn the_passive_variant_corrects_too() {
    let r = run(
        &program(
            json!({ "form": [ { "kind": "offset", "mm": 1.5 } ] }),
            json!([section("a", 60.0, "auto_passive")]),
        ),
        1,
        true,
    );
    let o = outcomes(&r, 0);
    assert_eq!(
        o,
        [
            "passive:over_deflection",
            "points:completed",
            "passive:completed"
        ],
        "{o:?}"
    );
    assert_exact(&r, 0);
}

#[test]
fn best_fit_alignment_absorbs_a_fixture_error() {
    let wp = common::example("blade");
    let mut pts = Vec::new();
    for (face, uvs) in [
        (0usize, [(0.2, 0.2), (0.5, 0.5), (0.8, 0.8), (0.3, 0.9)]),
        (1, [(0.2, 0.8), (0.5, 0.3), (0.8, 0.5), (0.6, 0.95)]),
    ] {
        for (u, v) in uvs {
            let p = wp.faces[face].surface.point(u, v);
            pts.push(json!([p.x, p.y, p.z]));
        }
    }
    let am = json!({ "transform": { "translate_mm": [0.4, -0.3, 0.2], "rotate_deg": [0.2, -0.1, 0.5] } });
    let mut v = program(am, json!([section("a", 60.0, "auto")]));
    v["alignment"] = json!({ "points_mm": pts });
    let r = run(&v, 1, true);
    let a = &serde_json::to_value(&r).unwrap()["alignment"];
    assert_eq!(a["points"], 8);
    assert!(a["max_mm"].as_f64().unwrap() < 1e-6, "{a}");
    // Aligned part frame = placement (translation only) after the transform.
    let rot = cmm::math::rotation_xyz_deg([0.2, -0.1, 0.5]);
    let want_t = cmm::math::Vec3::new(350.4, 499.7, 150.2);
    let got = &r.part_to_machine;
    for i in 0..3 {
        assert!(
            (got.translation_mm[i] - want_t[i]).abs() < 1e-6,
            "{:?}",
            got.translation_mm
        );
        for j in 0..3 {
            assert!((got.rotation[i][j] - rot[(i, j)]).abs() < 1e-8);
        }
    }
    // Measured in the aligned frame the part shows no deviation, and the
    // true deviations are those of the same frame (ideal machine: equal to
    // the measured ones within 0.5 um).
    assert_eq!(outcomes(&r, 0), ["active:completed"]);
    assert_exact(&r, 0);
    let f = &r.features[0];
    assert!(
        f.deviation_mm.max.abs() < 1e-4 && f.deviation_mm.min.abs() < 1e-4,
        "{:?}",
        f.deviation_mm
    );
}

#[test]
fn fitted_circle_reports_diameter_and_centre_of_a_scaled_shifted_bore() {
    // Scale about the axis: diameter 50 -> 50.06; then shift by (0.03, -0.04).
    let am = json!({ "transform": { "scale": [1.0012, 1.0012, 1.0], "translate_mm": [0.03, -0.04, 0.0] } });
    let feature = json!([{ "name": "ring", "type": "section_scan", "plane": { "origin_mm": [0, 0, 10], "normal": [0, 0, 1] },
        "mode": "active", "tolerance_mm": [-0.1, 0.1],
        "fit": { "element": "circle", "size_mm": [-0.05, 0.05], "position_mm": 0.1 } }]);
    let r = run(&bore_program(am, feature), 1, true);
    let fit = serde_json::to_value(&r.features[0]).unwrap()["fit"].clone();
    let size = fit["size_deviation_mm"].as_f64().unwrap();
    assert!((size - 0.06).abs() < 1e-6, "{fit}");
    assert!(
        (fit["position_deviation_mm"].as_f64().unwrap() - 0.05).abs() < 1e-6,
        "{fit}"
    );
    let c = &fit["measured"]["center"];
    assert!(
        (c[0].as_f64().unwrap() - 0.03).abs() < 1e-6
            && (c[1].as_f64().unwrap() + 0.04).abs() < 1e-6,
        "{fit}"
    );
    // 0.06 mm is outside the size tolerance: the feature fails although every point is within +-0.1.
    assert_eq!(fit["status"], "fail");
    assert_eq!(r.features[0].status, Verdict::Fail);
}

/// A gouge the active scan rides over without touching (trajectory error
/// just inside its tolerance, but no points over several millimetres) is
/// not measured: the scan is not taken as complete, the supervisor falls
/// back, and the gouge's depth shows in the deviations (or the feature is
/// incomplete), never a pass with the gouge unmeasured.
#[test]
fn a_scan_with_an_unmeasured_stretch_is_no_pass() {
    let am = json!({ "form": [ { "kind": "bump", "center_mm": [30.026, 9.501, 59.995],
                                 "radius_mm": 5, "height_mm": -2.3 } ] });
    let mut f = section("z60", 60.0, "auto");
    f["tolerance_mm"] = json!([-2.0, 0.1]);
    let r = run(&program(am, json!([f])), 1, true);
    let feat = &r.features[0];
    assert_ne!(feat.status, Verdict::Pass, "{:?}", outcomes(&r, 0));
    if feat.status == Verdict::Fail {
        assert!(feat.deviation_mm.min < -2.0, "{:?}", feat.deviation_mm);
    }
}
