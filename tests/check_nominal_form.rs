//! `cmm check` notes a fit that fails on a perfect part: io1-flange's
//! 36 mm bore cut by a plane tilted by atan(0.1) from square to its axis
//! is an ellipse with semi-axes 18 / cos and 18 mm, and a least-squares
//! circle leaves residuals over their difference (18 (1 / cos - 1) =
//! 0.0898 mm), over the program's 0.02 mm form tolerance. Square to the
//! axis the section is a circle and nothing is noted.
mod common;

use common::{arg, cmm, repo};
use serde_json::Value;

/// `cmm check` of the shipped io1-flange program with the bore's section
/// plane normal `normal`: its exit code and output.
fn check_with_bore_plane(dir: &std::path::Path, normal: [f64; 3]) -> (Option<i32>, String) {
    let text = std::fs::read_to_string(repo("part-programs/io1-flange.json")).unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["workpiece"] = arg(&repo("workpieces/io1-flange.stp")).into();
    let bore = (p["features"].as_array_mut().unwrap().iter_mut())
        .find(|f| f["name"] == "bore")
        .unwrap();
    bore["plane"]["normal"] = serde_json::json!(normal);
    let prog = common::write_program(dir, "flange.json", &p);
    let out = cmm(&["check", &arg(&prog)]);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn a_circle_fitted_to_an_ellipse_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let (code, text) = check_with_bore_plane(dir.path(), [1.0, 0.0, 0.1]);
    assert_eq!(code, Some(0), "{text}");
    let prefix = "bore: note: the design's own circle has a form error of ";
    let line = text.lines().find(|l| l.contains(prefix)).expect(&text);
    let form: f64 = line
        .split(prefix)
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .expect(line);
    let cos = 1.0 / 1.01f64.sqrt();
    let expected = 18.0 * (1.0 / cos - 1.0);
    assert!(
        (form - expected).abs() < 0.05 * expected,
        "{form} vs {expected}"
    );
    assert!(line.contains("over the form tolerance 0.02 mm"), "{line}");

    let (code, text) = check_with_bore_plane(dir.path(), [1.0, 0.0, 0.0]);
    assert_eq!(code, Some(0), "{text}");
    assert!(!text.contains("note: the design's own"), "{text}");
}
