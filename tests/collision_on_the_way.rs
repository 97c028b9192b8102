//! A collision is reported, never swallowed: io1's hub (the shipped STEP
//! file) with a 0.6 mm gouge that a 2 mm ball falls into, scanned in
//! `auto` mode with a tight trajectory tolerance. The active scan's
//! trajectory error stops it with the ball where the design has material
//! (in the gouge), so it backs out along its own path to where it left
//! free air, and the geometric correction's touches, which start from
//! there, all complete (from inside the gouge, the move to the first lifted
//! the stylus off its wall with the shaft against the hub above). The
//! autonomous scan that follows runs its shaft into the hub: that attempt
//! ends in `collision`, with the shaft, the place and the phase.
mod common;

use common::*;
use serde_json::{json, Value};

#[test]
fn a_collision_after_a_gouge_is_reported_with_the_probe_part() {
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
    assert_eq!(touches[0]["outcome"], "completed", "{attempts:?}");
    assert_eq!(touches[0]["points"], 16, "{attempts:?}");
    let struck = attempts.iter().find(|a| a["outcome"] == "collision");
    let struck = struck.unwrap_or_else(|| panic!("{attempts:?}"));
    assert_eq!(struck["collision"]["probe_part"], "shaft", "{struck}");
    assert!(struck["collision"]["at_mm"].is_array(), "{struck}");
    assert!(struck["collision"]["phase"].is_string(), "{struck}");
}

/// Runs of consecutive trace rows of a move that does not measure
/// (position, retract) with the stylus deflected.
fn deflected_runs(trace: &str) -> usize {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (phase, d) = (col("phase"), [col("dx_mm"), col("dy_mm"), col("dz_mm")]);
    let mut runs = 0;
    let mut inside = false;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let deflected = d.iter().any(|&k| f[k].parse::<f64>().unwrap() != 0.0);
        let moving = f[phase] == "position" || f[phase] == "retract";
        runs += usize::from(moving && deflected && !inside);
        inside = moving && deflected;
    }
    runs
}

/// io1 made 1.3 mm off its place (no alignment), a 7 mm bolt hole
/// scanned with a 3 mm ball: the active scan's trajectory error sends the
/// supervisor to a geometric correction whose touch points lie in the
/// misplaced hole's wall. The first strike ends the correction's attempt
/// (a machine stops there): no touch after it runs into the wall again,
/// so every deflection outside a measuring move is a collision reported
/// (an attempt's, or the end move's out of the misplaced hole).
#[test]
fn the_first_strike_ends_a_geometric_correction() {
    let program = json!({
        "format": "cmm-program/1", "name": "io1-misplaced",
        "workpiece": arg(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [0.3, -0.8, 0.6],
                                        "rotate_deg": [1.5, 0.05, 0] } },
        "features": [
            { "name": "bolt-hole-30", "type": "section_scan",
              "plane": { "origin_mm": [3, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face11", "face25"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let file = write_program(dir.path(), "misplaced.json", &program);
    let (code, report, trace) = scan_ideal_traced(&file, dir.path());
    assert!(matches!(code, Some(1 | 3)), "{report}");
    let attempts = report["features"][0]["attempts"].as_array().unwrap();
    let ended_struck = usize::from(report["end_move"]["outcome"] == "collision");
    let struck = ended_struck
        + attempts
            .iter()
            .filter(|a| a["outcome"] == "collision")
            .count();
    let touches = attempts.iter().find(|a| a["mode"] == "points").unwrap();
    assert_eq!(touches["outcome"], "collision", "{attempts:?}");
    assert_eq!(deflected_runs(&trace), struck, "{attempts:?}");
    // The speed reported is the axes' at the strike (the trace's measured
    // velocity where the ball guard caught it), not the one commanded.
    let c = &touches["collision"];
    assert_eq!(c["probe_part"], "ball", "{c}");
    let axes = strike_speed(&trace).unwrap();
    let reported = c["speed_mm_s"].as_f64().unwrap();
    assert!((reported - axes).abs() < 1e-6, "{reported} vs {axes}");
}

/// The measured speed (mm/s) of the first trace row of a positioning move
/// whose deflection reaches the ball guard's strike threshold (0.002 mm,
/// `ModeOptions::strike_mm`).
fn strike_speed(trace: &str) -> Option<f64> {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (phase, d, v) = (
        col("phase"),
        [col("dx_mm"), col("dy_mm"), col("dz_mm")],
        [col("vx"), col("vy"), col("vz")],
    );
    let norm = |f: &[&str], k: [usize; 3]| {
        k.iter()
            .map(|&i| f[i].parse::<f64>().unwrap().powi(2))
            .sum::<f64>()
            .sqrt()
    };
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find_map(|f| (f[phase] == "position" && norm(&f, d) >= 0.002).then(|| norm(&f, v)))
}

/// Four touch points on CTC 05's 19.05 mm counterbore wall at z = 6 with a
/// 12 mm stylus: the probe body (25 mm across) strikes the counterbore's
/// top at the first. A machine stops at a crash, so the feature ends
/// there: one attempt, a collision of the body, and a note that the three
/// points after it were not measured (each was driven into the part in
/// turn before).
#[test]
fn a_touch_that_strikes_ends_the_features_touches() {
    let program = json!({
        "format": "cmm-program/1", "name": "cbore-short",
        "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
        "placement": { "translate_mm": [400, 400, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 12 },
        "features": [ { "name": "hole-z6", "type": "touch_points",
            "points_mm": [[9.525, 222.25, 6], [0, 231.775, 6], [-9.525, 222.25, 6],
                          [0, 212.725, 6]],
            "surfaces": ["face25", "face26"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let file = write_program(dir.path(), "cbore.json", &program);
    let (code, report) = scan_ideal(&file, &dir.path().join("out"));
    assert_eq!(code, Some(3), "{report}");
    let f = &report["features"][0];
    let attempts = f["attempts"].as_array().unwrap();
    assert_eq!(attempts.len(), 1, "{attempts:?}");
    assert_eq!(attempts[0]["outcome"], "collision");
    assert_eq!(attempts[0]["collision"]["probe_part"], "body");
    let notes = f["notes"].to_string();
    assert!(
        notes.contains("3 touch points after the collision not measured"),
        "{notes}"
    );
}
