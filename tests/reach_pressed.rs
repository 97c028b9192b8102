//! The reach check stands the probe where it scans, pressed into the
//! surface by the scan's deflection, not where the ball just touches.
//! CTC 05's fillet at the foot of its tube (face74), cut by the plane
//! x = 0 with a 3 mm ball on a 100 mm stylus: scanning from the plate
//! side, the ball touching at z = 26.9 puts the probe body's flat end
//! 0.106 mm over the chamfer at the top of the tube's rim (z = 126.8 at
//! r = 146.25); pressed by the 0.3 mm deflection it stands 0.194 mm in it.
//! With a 0.01 mm deflection the body keeps its margin.
mod common;

use common::{arg, cmm, repo, write_program};
use serde_json::json;

fn fillet_section(deflection_mm: f64) -> serde_json::Value {
    json!({ "format": "cmm-program/1", "name": "fillet",
            "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
            "placement": { "translate_mm": [400, 400, 0], "rotate_deg": [0, 0, 0] },
            "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
            "defaults": { "speed_mm_s": 60, "deflection_mm": deflection_mm, "pitch_mm": 0.2 },
            "features": [ { "name": "t74", "type": "section_scan",
                "plane": { "origin_mm": [0, 0, 0], "normal": [1, 0, 0] },
                "surfaces": ["face74"], "tolerance_mm": [-0.5, 0.5] } ] })
}

#[test]
fn a_scan_pressed_into_a_fillet_puts_the_body_into_the_rim_above() {
    let dir = tempfile::tempdir().unwrap();
    let pressed = write_program(dir.path(), "pressed.json", &fillet_section(0.3));
    let out = cmm(&["check", &arg(&pressed)]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(3), "{text}");
    assert!(
        text.contains("t74 [0]: not reachable: the probe's body would strike"),
        "{text}"
    );
    let light = write_program(dir.path(), "light.json", &fillet_section(0.01));
    let out = cmm(&["check", &arg(&light)]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
}
