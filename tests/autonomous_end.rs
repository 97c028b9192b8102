//! An autonomous scan of an open section that ends where a floor curves
//! up into a wall runs to the section's end: the measured normal on the
//! floor leans towards the end tangent (straight up the wall) but lies
//! across the path it is on, unlike a ball rolled over the part's end.
//! CTC 05's plate at y = 0 (face8, z = 54.61 from x = -184.15 to -158.75)
//! and the 6.35 mm fillet up to x = -152.4 (face10): 25.4 mm plus a
//! quarter circle, 35.37 mm, at a 0.2 mm pitch.
mod common;

use common::{arg, repo, scan_ideal, write_program};
use serde_json::json;

#[test]
fn an_autonomous_scan_into_a_concave_end_runs_to_the_end() {
    let program = json!({ "format": "cmm-program/1", "name": "floor-to-wall",
        "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
        "placement": { "translate_mm": [400, 400, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.2 },
        "features": [ { "name": "plate-y0", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 0], "normal": [0, 1, 0] },
            "surfaces": ["face8", "face10"], "mode": "autonomous",
            "tolerance_mm": [-0.5, 0.5] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), "p.json", &program);
    let (code, report) = scan_ideal(&path, &dir.path().join("out"));
    assert_eq!(code, Some(0), "{report}");
    let points = report["features"][0]["points"].as_array().unwrap();
    let length = 25.4 + std::f64::consts::FRAC_PI_2 * 6.35;
    assert!(
        points.len() as f64 * 0.2 >= 0.95 * length,
        "{} points",
        points.len()
    );
    // The last point is on the fillet's top, where it meets the wall.
    let last = &points[points.len() - 1]["nominal"];
    let x = last[0].as_f64().unwrap();
    assert!((x + 152.4).abs() < 0.3, "{last}");
}

/// The autonomous scan holds the measured point in the section plane,
/// not the ball centre: on the blade's twisted surface, inclined to the
/// plane z = 60, the ball centre held in it puts the contact points off
/// it by the radius times the normal's lean, and the rescan along the
/// autonomous scan's points inherits that (0.078 mm). The reference is
/// the plane itself.
#[test]
fn autonomous_points_and_the_rescan_on_them_stay_in_the_section_plane() {
    let dir = tempfile::tempdir().unwrap();
    let (code, report) = scan_ideal(&repo("part-programs/blade-gouge.json"), dir.path());
    assert_eq!(code, Some(0), "{report}");
    let feature = &report["features"][0];
    let modes: Vec<&str> = (feature["attempts"].as_array().unwrap().iter())
        .map(|a| a["mode"].as_str().unwrap())
        .collect();
    assert!(modes.contains(&"autonomous"), "{modes:?}");
    for p in feature["points"].as_array().unwrap() {
        let z = p["measured"][2].as_f64().unwrap();
        assert!((z - 60.0).abs() < 0.02, "{p}");
    }
}
