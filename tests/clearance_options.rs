//! The program's `clearance` margins as `cmm check` and `cmm scan` use
//! them, on the bore example (a 25 mm radius bore, a 2 mm ball on a 1 mm
//! shaft): thresholds that follow from its dimensions alone.
mod common;

use std::path::Path;

use common::{cmm, repo};
use serde_json::Value;

/// The bore program with `clearance` set to `margins`, written to `dir`.
fn bore_program(dir: &Path, margins: Value) -> String {
    let text = std::fs::read_to_string(repo("part-programs/bore-circles.json")).unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["workpiece"] = repo("workpieces/bore.json").to_string_lossy().into();
    p["clearance"] = margins;
    let path = dir.join("bore.json");
    std::fs::write(&path, p.to_string()).unwrap();
    path.to_string_lossy().into_owned()
}

fn check(margins: Value) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let o = cmm(&["check", &bore_program(dir.path(), margins)]);
    let text =
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    (o.status.code(), text)
}

#[test]
fn the_posture_margin_is_the_shafts_gap_to_the_wall() {
    // Ball centre 1 mm from the wall (its radius), shaft radius 0.5 mm:
    // the shaft runs 0.5 mm from the wall while the ball measures.
    let (code, text) = check(serde_json::json!({ "posture_margin_mm": 0.45 }));
    assert_eq!(code, Some(0), "{text}");
    let (code, text) = check(serde_json::json!({ "posture_margin_mm": 0.55 }));
    assert_eq!(code, Some(3), "{text}");
    assert!(text.contains("shaft would strike"), "{text}");
}

#[test]
fn margins_wider_than_the_bore_leave_it_unreachable() {
    // The ball centre has 24 mm of room from the bore's axis to its wall.
    let (code, text) = check(serde_json::json!({ "margin_mm": 30, "tight_margin_mm": 30 }));
    assert_eq!(code, Some(3), "{text}");
    assert!(
        text.contains("no route from the clearance height"),
        "{text}"
    );
    let dir = tempfile::tempdir().unwrap();
    let prog = bore_program(
        dir.path(),
        serde_json::json!({ "margin_mm": 30, "tight_margin_mm": 30 }),
    );
    let out = dir.path().join("o");
    let o = cmm(&[
        "scan",
        &prog,
        "--ideal",
        "--quiet",
        "--out",
        &out.to_string_lossy(),
    ]);
    assert_eq!(o.status.code(), Some(3));
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(r["status"], "incomplete");
    assert_eq!(
        r["machine_time_s"].as_f64(),
        Some(0.0),
        "nothing moved into the bore"
    );
}

#[test]
fn bad_margins_are_exit_2_naming_the_key() {
    for (margins, key) in [
        (
            serde_json::json!({ "margin_mm": -1 }),
            "$.clearance.margin_mm",
        ),
        (
            serde_json::json!({ "margin_mm": 3, "tight_margin_mm": 4 }),
            "$.clearance.tight_margin_mm",
        ),
        (
            serde_json::json!({ "posture_margin_mm": 1000 }),
            "$.clearance.posture_margin_mm",
        ),
        (serde_json::json!({ "margin": 1 }), "$.clearance.margin"),
    ] {
        let (code, text) = check(margins);
        assert_eq!(code, Some(2), "{text}");
        assert!(text.contains(key), "{key}: {text}");
    }
}
