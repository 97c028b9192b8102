//! A closed section whose first point lies under an overhang is scanned
//! from a point of it the probe can reach. The ABC lamp (the shipped STEP
//! file): its base cone cut at z = 10 is a circle of radius 95.40 (the
//! cone r = 101.6 - z tan 0.5555 of the file); the half shell of glass
//! above it (y >= 0 only, up to radius 75.15 from z 104.6 on, and out to
//! the rim beyond) stands over the circle's start at (-100.9, 0), so no
//! route comes down there, while nothing stands over the half at y < 0.
mod common;

use common::*;

fn program() -> serde_json::Value {
    serde_json::json!({
        "format": "cmm-program/1", "name": "lamp-base",
        "workpiece": arg(&repo("workpieces/abc-lamp.step")),
        "placement": { "translate_mm": [350, 500, -10], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.003 } ] },
        "features": [ { "name": "base-z10", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 10], "normal": [0, 0, 1] },
            "surfaces": ["face17"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle" } } ] })
}

/// `cmm check` accepts the feature, and the scan measures the whole
/// circle (its 599.4 mm at the 0.5 mm pitch) on the cone.
#[test]
fn a_closed_section_starts_where_a_route_reaches_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_program(dir.path(), "lamp-base.json", &program());
    let check = cmm(&["check", &arg(&file)]);
    assert!(check.status.success(), "{check:?}");
    let (code, report) = scan_ideal(&file, &dir.path().join("out"));
    assert_eq!(code, Some(0), "{report}");
    let f = &report["features"][0];
    let points = f["points"].as_array().unwrap();
    assert!(points.len() >= 1190, "{}", points.len());
    let radius = 101.6 - 10.0 * 0.5555_f64.tan();
    for p in points {
        let m = |k: usize| p["measured"][k].as_f64().unwrap();
        assert!((m(0).hypot(m(1)) - radius).abs() < 0.02, "{p}");
    }
    assert!(points
        .iter()
        .any(|p| p["measured"][1].as_f64().unwrap() > 50.0));
}
