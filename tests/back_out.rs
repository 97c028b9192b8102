//! A part that lies off its design by more than the ball's radius: the
//! io1 flange moved 4.5 mm across its 36 mm bore, measured with a 1 mm
//! ball. The bore's scan meets the moved wall 4.5 mm beyond the design's
//! and stops (trajectory error) with the ball where the design has
//! material; from there no route the design data allows starts. The probe
//! backs out along the way it came to where the scan left free air, so
//! the geometric correction's touch points are all taken (16 of 16, by
//! the supervisor's default), the next feature (the boss) is attempted,
//! and the program ends with the probe parked. References: the move, the
//! touch count the program asks for, and the trace's phases.
mod common;

use common::{arg, repo, scan_ideal_traced, write_program};
use serde_json::json;

#[test]
fn a_scan_stopped_inside_the_design_backs_out_the_way_it_came() {
    let program = json!({ "format": "cmm-program/1", "name": "moved-4.5",
        "workpiece": arg(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 40 },
        "defaults": { "speed_mm_s": 20, "deflection_mm": 0.2, "pitch_mm": 0.2 },
        "as_machined": { "transform": { "translate_mm": [0, 4.5, 0] } },
        "features": [
            { "name": "bore", "type": "section_scan",
              "plane": { "origin_mm": [15, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face3", "face18"], "tolerance_mm": [-0.1, 0.1] },
            { "name": "boss", "type": "section_scan",
              "plane": { "origin_mm": [25, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face5", "face27"], "tolerance_mm": [-0.1, 0.1] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), "p.json", &program);
    let (_, report, trace) = scan_ideal_traced(&path, dir.path());
    let attempts = |k: usize| {
        report["features"][k]["attempts"]
            .as_array()
            .unwrap()
            .clone()
    };
    let bore = attempts(0);
    assert_eq!(bore[0]["outcome"], "trajectory_error", "{report}");
    assert_eq!(bore[1]["mode"], "points", "{report}");
    assert_eq!(bore[1]["outcome"], "completed", "{report}");
    assert_eq!(bore[1]["points"], 16, "{report}");
    let boss = attempts(1);
    assert!(
        boss[0]["machine_time_s"].as_f64().unwrap() > 0.0,
        "{report}"
    );
    assert_eq!(report["end_move"]["outcome"], "completed", "{report}");
    for line in trace.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        if matches!(cols.last().copied(), Some("position" | "retract")) {
            let d: f64 = cols[10..13]
                .iter()
                .map(|c| c.parse::<f64>().unwrap_or(0.0).powi(2))
                .sum();
            assert!(d == 0.0, "{line}");
        }
    }
}
