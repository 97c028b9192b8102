//! A section that its geometric correction finds moved is scanned again
//! with the moves to the scan going round the part where it stands. CTC
//! 05 set up 1.9 mm off its nominal place (as-machined translation of
//! (1.6, 1.0, 0) mm), its 7.94 mm bore scanned with a 3 mm ball: the
//! first scan over-deflects on the near wall, the touch points find the
//! translation, and the scan of the corrected bore starts there. Planned
//! in the design's free space, the way down to that start struck the
//! true wall while positioning (deflections of 0.03-0.1 mm in position
//! and retract rows, the feature incomplete).
mod common;

use common::*;
use serde_json::json;

#[test]
fn a_bore_found_moved_is_rescanned_without_striking_its_wall() {
    let dir = tempfile::tempdir().unwrap();
    let program = json!({
        "format": "cmm-program/1", "name": "bore-moved",
        "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
        "placement": { "translate_mm": [400, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [1.6, 1.0, 0] } },
        "features": [ { "name": "bore-z20", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 20], "normal": [0, 0, 1] },
            "surfaces": ["face188", "face189"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle" } } ] });
    let file = write_program(dir.path(), "bore.json", &program);
    let (_, report, trace) = scan_ideal_traced(&file, dir.path());
    let f = &report["features"][0];
    let corrections = f["corrections"].as_array().unwrap();
    assert_eq!(corrections[0]["model"], "translation", "{f}");
    let last = f["attempts"].as_array().unwrap().last().unwrap();
    assert_eq!(last["outcome"], "completed", "{f}");
    assert!(f["points"].as_array().unwrap().len() > 45, "{f}");
    let pressed = (trace_deflections(&trace).into_iter())
        .filter(|(phase, _)| phase == "position" || phase == "retract")
        .map(|(_, d)| d)
        .fold(0.0, f64::max);
    assert!(pressed < 1e-3, "{pressed} mm off the scan");
    // The fitted bore stands where the setup put it.
    let (measured, nominal) = (
        &f["fit"]["measured"]["center"],
        &f["fit"]["nominal"]["center"],
    );
    for (k, shift) in [(0, 1.6), (1, 1.0)] {
        let moved = measured[k].as_f64().unwrap() - nominal[k].as_f64().unwrap();
        assert!((moved - shift).abs() < 2e-3, "axis {k}: {moved}");
    }
}
