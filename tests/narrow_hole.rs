//! A hole narrower than the ball is reported as such, in `cmm check` and
//! in the scan, not as a hole without a route: io1-flange's 7 mm bolt
//! hole (its section 22.0 mm round, its points close enough together that
//! no two neighbours turn by a corner's angle) with an 8 mm ball, and the
//! same hole measured with the shipped 3 mm ball.
mod common;

use common::{arg, cmm, repo};
use serde_json::Value;

/// The shipped io1-flange program with a ball of `tip_mm`, its workpiece
/// named by its full path, written into `dir`.
fn flange_program(dir: &std::path::Path, tip_mm: f64) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo("part-programs/io1-flange.json")).unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["workpiece"] = arg(&repo("workpieces/io1-flange.stp")).into();
    p["probe"]["tip_diameter_mm"] = tip_mm.into();
    common::write_program(dir, &format!("flange-{tip_mm}.json"), &p)
}

/// The notes of the feature `name` in `report`.
fn notes(report: &Value, name: &str) -> String {
    let features = report["features"].as_array().unwrap();
    let f = features.iter().find(|f| f["name"] == name).unwrap();
    f["notes"].to_string()
}

#[test]
fn a_hole_narrower_than_the_ball_is_named_so() {
    let dir = tempfile::tempdir().unwrap();
    let big = flange_program(dir.path(), 8.0);
    let check = cmm(&["check", &arg(&big)]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{text}");
    assert!(
        text.contains("bolt-hole-30 [0]: not reachable: narrower than the ball"),
        "{text}"
    );
    let (code, report) = common::scan_ideal(&big, &dir.path().join("big"));
    assert_eq!(code, Some(3), "{report}");
    let n = notes(&report, "bolt-hole-30");
    assert!(
        n.contains("narrower than the ball") && !n.contains("no route"),
        "{n}"
    );

    let small = flange_program(dir.path(), 3.0);
    let (code, report) = common::scan_ideal(&small, &dir.path().join("small"));
    assert_eq!(code, Some(0), "{report}");
    assert_eq!(notes(&report, "bolt-hole-30"), "[]");
}
