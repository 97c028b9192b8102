//! A scan that loses its surface and runs on, with the ball nearer the
//! design's surface than its radius, backs out along its own path lifted
//! off the surface it followed: the retract reads no deflection (heading
//! back the way it came, unlifted, it would press into the rib it has
//! just lost).
//!
//! The part: the bearing housing of the shared CAD files, whose IGES file
//! is 0.16 mm across (its units are wrong by a factor of 1000), scaled to
//! millimetres here; its ribs and hub are drafted by 7 degrees. The true
//! part lies 1.2 mm and 1 degree off its design, so the active scan of
//! the hub-and-rib section at z = 20 loses its surface on one of the ribs.
mod common;

use common::arg;
use serde_json::json;

#[test]
fn a_scan_that_lost_its_surface_backs_out_without_touching_it() {
    let dir = tempfile::tempdir().unwrap();
    let Some(workpiece) = common::bearing_in_mm(dir.path()) else {
        return;
    };
    let faces = [
        "face158", "face160", "face161", "face166", "face173", "face175", "face188", "face183",
        "face184", "face163", "face164", "face176", "face185", "face199", "face172", "face187",
    ];
    let program = json!({
        "format": "cmm-program/1", "name": "bearing-ribs",
        "workpiece": arg(&workpiece),
        "placement": { "translate_mm": [400, 500, 80], "rotate_deg": [0, 0, 90] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 40, "deflection_mm": 0.3, "pitch_mm": 0.25,
                      "trajectory_tolerance_mm": 0.2 },
        "as_machined": {
            "form": [ { "kind": "offset", "mm": 0.01 } ],
            "transform": { "translate_mm": [1.2, -0.8, 0], "rotate_deg": [0, 0, 1.0],
                           "about_mm": [2.127, -1.05, 0] } },
        "features": [ { "name": "hub-ribs-z20", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 20], "normal": [0, 0, 1] },
            "surfaces": faces, "tolerance_mm": [-0.5, 0.5] } ]
    });
    let prog = common::write_program(dir.path(), "ribs.json", &program);
    let (code, report, trace) = common::scan_ideal_traced(&prog, dir.path());
    assert!(matches!(code, Some(0 | 1)), "{report}");
    // The scan did lose its surface on the way (else this shows nothing).
    let attempts = report["features"][0]["attempts"].as_array().unwrap();
    assert!(
        attempts.iter().any(|a| a["outcome"] == "trajectory_error"),
        "{attempts:?}"
    );
    for (phase, d) in common::trace_deflections(&trace) {
        if phase == "retract" || phase == "position" {
            assert!(d == 0.0, "{phase} reads {:.2} um", d * 1000.0);
        }
    }
}
