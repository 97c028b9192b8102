//! After the stylus shaft strikes the part in a scan, the probe backs out
//! the way it came, not off the surface the ball is pressed on (which
//! drives the shaft on into the part). Linkrods with a 0.3 mm ball on a
//! 10 mm stylus: the section y = 3.25 through ring B runs down its bore
//! until the shaft strikes the ring's rim (a true strike, which the reach
//! check foresees); the touch points on ring A's top and ring A's bore,
//! each measurable on its own, must then be measured and the probe
//! parked. Before, every later move started with the shaft in the part.
mod common;

use common::{arg, repo, scan_ideal, write_program};
use serde_json::json;

#[test]
fn after_a_shaft_strike_the_later_features_are_measured() {
    let program = json!({ "format": "cmm-program/1", "name": "strike-then-on",
        "workpiece": arg(&repo("workpieces/linkrods.step")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 0.3, "stylus_length_mm": 10 },
        "defaults": { "speed_mm_s": 5, "deflection_mm": 0.05, "pitch_mm": 0.02 },
        "clearance": { "tight_margin_mm": 0.03 },
        "features": [
            { "name": "ringB", "type": "section_scan",
              "plane": { "origin_mm": [0, 3.25, 0], "normal": [0, 1, 0] },
              "surfaces": ["face1", "face2", "face3", "face4", "face5", "face12"],
              "tolerance_mm": [-0.05, 0.05] },
            { "name": "ringA-top", "type": "touch_points",
              "points_mm": [[3.2, 3.25, 2.0], [3.875, 3.95, 2.0], [4.55, 3.25, 2.0]],
              "tolerance_mm": [-0.05, 0.05] },
            { "name": "ringA-bore", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 1.0], "normal": [0, 0, 1] },
              "surfaces": ["face11"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), "p.json", &program);
    let (code, report) = scan_ideal(&path, &dir.path().join("out"));
    assert_eq!(code, Some(3), "{report}");
    let f = &report["features"];
    assert_eq!(
        f[0]["attempts"][0]["collision"]["probe_part"], "shaft",
        "{report}"
    );
    assert_eq!(f[1]["status"], "pass", "{report}");
    assert_eq!(f[1]["points"].as_array().unwrap().len(), 3, "{report}");
    assert_eq!(f[2]["status"], "pass", "{report}");
    assert_eq!(report["end_move"]["outcome"], "completed", "{report}");
}
