//! A route the design data clears with the tight margin only keeps to its
//! legs: on the fixture assembly (three placed brackets, STEP), a curve of
//! the hub section of the first bracket at z = 20 starts close beside the
//! boss, and its route (down from the clearance height to an entry point,
//! then in) is clear with the tight margin only. A blended fast move turned
//! before that corner and the servo lag carried the ball 2.3 mm below it,
//! into the part at 114 mm/s; the positioning moves now stop at each corner
//! of such a route, so no move that does not measure touches the part
//! (`--ideal`: nothing but the method moves the probe).
mod common;

use common::*;

/// The program: the hub section and the boss end of bracket #1.
fn program(dir: &std::path::Path) -> std::path::PathBuf {
    let wp = repo("workpieces/fixture-assembly.step");
    let p = serde_json::json!({
        "format": "cmm-program/1",
        "name": "fixture-b1-hub",
        "workpiece": arg(&wp),
        "placement": { "translate_mm": [300, 420, 60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 80 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "b1-hub-z20", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 20], "normal": [0, 0, 1] },
              "surfaces": ["bracket#1/face19", "bracket#1/face27",
                           "bracket#1/face4", "bracket#1/face10"],
              "tolerance_mm": [-0.05, 0.05] },
            { "name": "b1-boss-end", "type": "touch_points",
              "points_mm": [[31, 24, 0], [31, -12, 20.785], [31, -12, -20.785]],
              "surfaces": ["bracket#1/face4"], "tolerance_mm": [-0.05, 0.05],
              "fit": { "element": "plane", "form_mm": 0.02 } }
        ]
    });
    write_program(dir, "fixture-b1-hub.json", &p)
}

#[test]
fn positioning_into_a_narrow_gap_does_not_touch_the_part() {
    let dir = tempfile::tempdir().unwrap();
    let prog = program(dir.path());
    let out = dir.path().join("out");
    let (code, report) = scan_ideal(&prog, &out);
    assert!(code.is_some_and(|c| c != 2), "exit {code:?}");
    let features = report["features"].as_array().unwrap();
    let hub = &features[0];
    assert!(
        hub["points"].as_array().unwrap().len() > 150,
        "the hub section is measured where it can be reached"
    );
    for f in features {
        for a in f["attempts"].as_array().unwrap() {
            let c = &a["collision"];
            assert!(c.is_null(), "{}: collision {c}", f["name"]);
        }
    }
    assert_eq!(features[1]["status"], "pass");
}
