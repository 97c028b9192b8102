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

/// io1's 7 mm bolt hole scanned with a 4 mm ball: the ball's path round
/// it (radius 1.5) is 2.3 times shorter than the contact's (3.5), and the
/// points are a pitch apart along the contact's. The loop's last point
/// lies between half a pitch and a pitch and a half before its first
/// (it lay 7 um from it, all but repeating it), and the points cover
/// the hole's circumference 2 pi 3.5 at the 0.5 mm pitch.
#[test]
fn a_closed_loop_ends_short_of_its_first_point() {
    let program = serde_json::json!({
        "format": "cmm-program/1", "name": "bolt",
        "workpiece": arg(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 4.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 40, "deflection_mm": 0.2, "pitch_mm": 0.5 },
        "features": [ { "name": "bolt-hole-30", "type": "section_scan",
            "plane": { "origin_mm": [3, 0, 0], "normal": [1, 0, 0] },
            "surfaces": ["face11", "face25"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle" } } ] });
    let dir = tempfile::tempdir().unwrap();
    let file = write_program(dir.path(), "bolt.json", &program);
    let (code, report) = scan_ideal(&file, &dir.path().join("out"));
    assert_eq!(code, Some(0), "{report}");
    let points = report["features"][0]["points"].as_array().unwrap();
    let at = |k: usize| {
        let p = &points[k]["measured"];
        [0, 1, 2].map(|i| p[i].as_f64().unwrap())
    };
    let (first, last) = (at(0), at(points.len() - 1));
    let gap = (0..3)
        .map(|i| (first[i] - last[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((0.25..0.75).contains(&gap), "{gap}");
    let around = 2.0 * std::f64::consts::PI * 3.5;
    let covered = 0.5 * (points.len() - 1) as f64 + gap;
    assert!((covered - around).abs() < 0.3, "{covered} vs {around}");
}
