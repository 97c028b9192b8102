//! After a scan runs in under an overhang until the probe body strikes it,
//! the software backs the probe out and takes it back along the scan's
//! path to where the scan left free air, so the features after it start
//! from a point their routes lead from. The ABC lamp (the shipped STEP
//! file), turned 60 degrees on the table: a vertical section of the base
//! at y = -40 runs in under the lamp's body, which the probe body strikes
//! (`cmm check` says it would); the glass and the cap above are reachable
//! from the clearance height and are measured afterwards; the stylus
//! comes free within the scan's own phase and the move back touches
//! nothing.
mod common;

use common::*;
use serde_json::{json, Value};

fn program(features: Value) -> Value {
    json!({
        "format": "cmm-program/1",
        "name": "lamp-retrace",
        "workpiece": arg(&repo("workpieces/abc-lamp.step")),
        "placement": { "translate_mm": [380, 420, 0], "rotate_deg": [0, 0, 60] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": features
    })
}

fn section(name: &str, origin: [f64; 3], normal: [f64; 3], face: &str) -> Value {
    json!({ "name": name, "type": "section_scan",
            "plane": { "origin_mm": origin, "normal": normal },
            "surfaces": [face], "tolerance_mm": [-0.1, 0.1] })
}

#[test]
fn features_after_a_collision_under_an_overhang_are_measured() {
    let dir = tempfile::tempdir().unwrap();
    let features = json!([
        section("under-body", [0.0, -40.0, 0.0], [0.0, 1.0, 0.0], "face17"),
        section("glass", [0.0, 0.0, 395.0], [0.1, 0.0, 1.0], "face15"),
        section("cap", [0.0, 0.0, 505.0], [0.0, 0.1, 1.0], "face18"),
    ]);
    let file = write_program(dir.path(), "lamp.json", &program(features));
    let (code, report, trace) = scan_ideal_traced(&file, dir.path());
    assert_eq!(code, Some(3), "{report}");
    let f = report["features"].as_array().unwrap();
    assert_eq!(f[0]["status"], "incomplete");
    let struck = &f[0]["attempts"][0];
    assert_eq!(struck["outcome"], "collision", "{struck}");
    assert_eq!(struck["collision"]["probe_part"], "body", "{struck}");
    assert!(f[0]["points"].as_array().unwrap().len() > 100);
    for later in &f[1..] {
        assert_eq!(
            later["status"], "pass",
            "{}: {}",
            later["name"], later["notes"]
        );
        assert!(
            later["points"].as_array().unwrap().len() > 500,
            "{}",
            later["name"]
        );
    }
    // No cycle of a move that does not measure has the stylus deflected:
    // coming free off the surface belongs to the scan the strike stopped,
    // and the way back follows the scan off the surface.
    let rows = trace_deflections(&trace);
    for (k, (p, d)) in rows.iter().enumerate() {
        if p == "retract" || p == "position" {
            assert!(*d == 0.0, "row {k}: {p} deflected {d}");
        }
    }
}
