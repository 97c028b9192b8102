//! A collision on a move between measurements is reported, never
//! swallowed: io1's hub (the shipped STEP file) with a 0.6 mm gouge that
//! a 2 mm ball falls into, scanned in `auto` mode with a tight trajectory
//! tolerance. The active scan's trajectory error sends the supervisor to
//! a geometric correction, whose move to its first touch point lifts the
//! stylus off the gouge's wall with its shaft against the hub above: the
//! correction's attempt ends in `collision`, with the shaft, the place and
//! the phase of the move.
mod common;

use common::*;
use serde_json::{json, Value};

#[test]
fn a_collision_on_the_way_to_a_touch_point_is_reported() {
    let program = json!({
        "format": "cmm-program/1", "name": "gouge",
        "workpiece": arg(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [450, 300, 60], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 2.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 50, "deflection_mm": 0.25, "pitch_mm": 0.4,
                      "trajectory_tolerance_mm": 0.3 },
        "as_machined": { "form": [
            { "kind": "bump", "center_mm": [12, 31, 0], "radius_mm": 4, "height_mm": -0.6,
              "surfaces": ["face9", "face19"] } ] },
        "features": [
            { "name": "hub-gouge", "type": "section_scan",
              "plane": { "origin_mm": [12, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face9", "face19"], "tolerance_mm": [-0.7, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let file = write_program(dir.path(), "gouge.json", &program);
    let (code, report) = scan_ideal(&file, &dir.path().join("out"));
    assert_eq!(code, Some(3), "{report}");
    let attempts = report["features"][0]["attempts"].as_array().unwrap();
    let touches: Vec<&Value> = attempts.iter().filter(|a| a["mode"] == "points").collect();
    assert!(!touches.is_empty(), "{attempts:?}");
    let struck = touches[0];
    assert_eq!(struck["outcome"], "collision", "{struck}");
    assert_eq!(struck["collision"]["probe_part"], "shaft", "{struck}");
    assert!(struck["collision"]["at_mm"].is_array(), "{struck}");
}
