//! The probe body's flat end beside a part edge, on a real CAD part: NIST
//! CTC 05's column (31.75 mm across to z = 476.25, a 45 degree chamfer up
//! to its top face at z = 482.6, 25.4 mm across) scanned with a 100 mm
//! stylus and the default body (12.5 mm radius). Scanning at z = 380 the
//! body's flat end stands at z = 480, the ball centre 33.25 mm from the
//! column's axis: the chamfer (28 mm from the axis at z = 480) comes up
//! through the flat end's outer ring, which a capsule over the flat end
//! leaves out. Scanning at z = 385 the flat end stands 2.4 mm above the
//! top face. References are this geometry, not the measuring code.
mod common;

use std::path::Path;

use cmm::app::reach::{part_clearance, program_margins};
use cmm::host::inspect::clearance::ClearanceOptions;
use cmm::host::modes::{FreeSpace, HostProbe};
use cmm::math::Point3;
use cmm::seam::ProbePart;
use common::{arg, cmm, repo};
use serde_json::{json, Value};

/// The section of the column at height `z` (part coordinates, mm).
fn column_program(z: f64) -> Value {
    json!({ "format": "cmm-program/1", "name": "column",
            "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
            "placement": { "translate_mm": [350, 500, -60], "rotate_deg": [0, 0, 0] },
            "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
            "defaults": { "speed_mm_s": 80, "deflection_mm": 0.3, "pitch_mm": 0.5,
                          "trajectory_tolerance_mm": 1.5 },
            "features": [ { "name": "column", "type": "section_scan",
                "plane": { "origin_mm": [0, 0, z], "normal": [0, 0, 1] },
                "surfaces": ["face129", "face130"], "tolerance_mm": [-0.05, 0.05] } ] })
}

fn write_program(dir: &Path, program: &Value) -> String {
    let path = dir.join("column.json");
    std::fs::write(&path, program.to_string()).unwrap();
    arg(&path)
}

fn read_report(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap()
}

/// The attempts of the report's only feature.
fn attempts(report: &Value) -> Vec<Value> {
    report["features"][0]["attempts"]
        .as_array()
        .unwrap()
        .clone()
}

#[test]
fn the_probe_standing_with_the_chamfer_in_its_flat_end_is_a_body_strike() {
    let dir = tempfile::tempdir().unwrap();
    let program = cmm::program::load(Path::new(&write_program(
        dir.path(),
        &column_program(380.0),
    )))
    .unwrap_or_else(|e| panic!("{e}"));
    let probe = HostProbe::nominal(program.probe_vector(), program.probe.tip_radius_mm);
    let margins = program_margins(&program, ClearanceOptions::default());
    let free = part_clearance(&program, probe, margins);
    let ball = program.placement.to_machine(Point3::new(33.25, 0.0, 380.0));
    assert_eq!(free.posture(ball), Some(ProbePart::Body));
    // 2.4 mm higher above the top face the body is clear.
    let ball = program.placement.to_machine(Point3::new(33.25, 0.0, 385.0));
    assert_eq!(free.posture(ball), None);
}

#[test]
fn check_refuses_the_column_under_the_flat_end_and_the_scan_does_not_strike() {
    let dir = tempfile::tempdir().unwrap();
    let program = write_program(dir.path(), &column_program(380.0));
    let check = cmm(&["check", &program]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{text}");
    assert!(text.contains("column [0]: not reachable"), "{text}");
    let out = dir.path().join("out");
    let run = cmm(&["scan", &program, "--quiet", "--out", &arg(&out)]);
    assert_eq!(run.status.code(), Some(3), "{run:?}");
    let report = read_report(&out);
    assert_eq!(report["features"][0]["status"], "incomplete");
    let struck: Vec<Value> = (attempts(&report).into_iter())
        .filter(|a| a["outcome"] == "collision")
        .collect();
    assert!(struck.is_empty(), "{struck:?}");
}

#[test]
fn the_column_with_the_flat_end_above_its_top_is_measured() {
    let dir = tempfile::tempdir().unwrap();
    let program = write_program(dir.path(), &column_program(385.0));
    let check = cmm(&["check", &program]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(0), "{text}");
    let out = dir.path().join("out");
    let run = cmm(&["scan", &program, "--ideal", "--quiet", "--out", &arg(&out)]);
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let report = read_report(&out);
    assert_eq!(report["features"][0]["status"], "pass");
    assert!(attempts(&report)
        .iter()
        .all(|a| a["outcome"] == "completed"));
}
