//! An open section sampled coarsely (a nearly straight curve on a web of
//! the shared bearing housing, its 10 design points 1.25-1.6 mm apart) is
//! measured up to where the ball meets the next face, not only to the
//! last design point the ball can touch: the web's section at x = -15
//! runs 11.3 mm from y = -19.18 to -30.44, and a 3 mm ball touching it
//! meets the blend beside it from about y = -19.6 on (within 1.5 um of
//! the ball's radius at -19.70, 7.6 um inside it at -19.50), so the points
//! span at least 10.5 mm of it; ending at the sample before the blend
//! they spanned 9.5.
mod common;

use common::arg;
use serde_json::{json, Value};

/// The distance between two report points' nominal positions, mm.
fn apart(a: &Value, b: &Value) -> f64 {
    (0..3)
        .map(|k| (a["nominal"][k].as_f64().unwrap() - b["nominal"][k].as_f64().unwrap()).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn a_coarse_open_section_is_measured_up_to_the_wall() {
    let dir = tempfile::tempdir().unwrap();
    let Some(workpiece) = common::bearing_in_mm(dir.path()) else {
        return;
    };
    let program = json!({
        "format": "cmm-program/1", "name": "bearing-web",
        "workpiece": arg(&workpiece),
        "placement": { "translate_mm": [350, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 40, "deflection_mm": 0.3, "pitch_mm": 0.25 },
        "features": [ { "name": "web-x-15", "type": "section_scan",
            "plane": { "origin_mm": [-15, 0, 0], "normal": [1, 0, 0] },
            "surfaces": ["face169"], "tolerance_mm": [-0.05, 0.05] } ]
    });
    let prog = common::write_program(dir.path(), "web.json", &program);
    let (code, report) = common::scan_ideal(&prog, &dir.path().join("out"));
    assert_eq!(code, Some(0), "{report}");
    let points = report["features"][0]["points"].as_array().unwrap();
    let (first, last) = (points.first().unwrap(), points.last().unwrap());
    let span = apart(first, last);
    assert!(span >= 10.5, "the points span {span:.3} mm");
    for p in points {
        let (d, t) = (
            p["deviation_mm"].as_f64().unwrap(),
            p["true_deviation_mm"].as_f64().unwrap(),
        );
        assert!((d - t).abs() < 5e-4, "{p}");
    }
}
