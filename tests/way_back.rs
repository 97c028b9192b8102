//! After a collision under an overhang the probe goes back the way it
//! came in: the ABC part's base cone lies under its lamp cap, so a probe
//! that came down beside the cap and in under it has no way straight up.
//! The section of the cone at x = 0 drives the probe body into the cap
//! (a true strike, which the reach check foresees); the next section,
//! reachable on its own, must then be measured, not refused for want of
//! a route. References: the strike's part (the body) and the reachability
//! of the next feature when it runs first.
mod common;

use common::{arg, repo, scan_ideal_traced, write_program};
use serde_json::{json, Value};

fn program(features: &[&str]) -> Value {
    let section = |name: &str| match name {
        "cone-x0" => json!({ "name": name, "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 0], "normal": [1, 0, 0] },
            "surfaces": ["face17"], "tolerance_mm": [-0.05, 0.05] }),
        _ => json!({ "name": name, "type": "section_scan",
            "plane": { "origin_mm": [0, -80, 0], "normal": [0, 1, 0] },
            "surfaces": ["face17"], "tolerance_mm": [-0.05, 0.05] }),
    };
    json!({ "format": "cmm-program/1", "name": "way-back",
            "workpiece": arg(&repo("workpieces/abc-lamp.step")),
            "placement": { "translate_mm": [350, 450, 3], "rotate_deg": [0, 0, 0] },
            "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 30 },
            "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
            "features": features.iter().map(|f| section(f)).collect::<Vec<_>>() })
}

/// The features' statuses and first attempts' outcomes.
fn outcomes(report: &Value) -> Vec<(String, String)> {
    let features = report["features"].as_array().unwrap();
    (features.iter())
        .map(|f| {
            let first = &f["attempts"][0];
            (f["status"].to_string(), first["outcome"].to_string())
        })
        .collect()
}

#[test]
fn after_a_strike_under_an_overhang_the_probe_goes_back_the_way_it_came() {
    let dir = tempfile::tempdir().unwrap();
    // The second section on its own: reachable, measured.
    let alone = write_program(dir.path(), "alone", &program(&["cone-y-80"]));
    let (code, report, _) = scan_ideal_traced(&alone, dir.path());
    assert_eq!(code, Some(0), "{report}");
    let (code, report, trace) = scan_ideal_traced(
        &write_program(dir.path(), "both", &program(&["cone-x0", "cone-y-80"])),
        dir.path(),
    );
    let got = outcomes(&report);
    let strike = &report["features"][0]["attempts"][0]["collision"];
    assert_eq!(strike["probe_part"], "body", "{report}");
    assert_eq!(got[0].0, "\"incomplete\"", "{got:?}");
    assert_eq!(
        got[1],
        ("\"pass\"".into(), "\"completed\"".into()),
        "{got:?}"
    );
    assert_eq!(report["end_move"]["outcome"], "completed", "{report}");
    assert_eq!(code, Some(3));
    // No deflection while positioning or retracting, going back included.
    for line in trace.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        let phase = cols.last().copied().unwrap_or("");
        if phase == "position" || phase == "retract" {
            let d: f64 = (cols[10..13].iter())
                .map(|c| c.parse::<f64>().unwrap_or(0.0).powi(2))
                .sum();
            assert!(d == 0.0, "{line}");
        }
    }
}
