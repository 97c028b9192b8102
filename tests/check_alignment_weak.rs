//! `cmm check` notes an alignment that fixes the part only weakly where it
//! is measured: io1-flange aligned on its flange top (the plane x = 6) and
//! its outside (the cylinder of radius 44 about x). Three top points 2 mm
//! apart fix the tilts of the top only weakly: a common error of 5 um at
//! every point tilts it enough to move the flange's far edge, 44 mm out,
//! by over 0.1 mm. Three top points 80 mm apart fix them firmly, and
//! nothing is noted but the turn about the axis that plane and cylinder
//! leave free.
mod common;

use common::{arg, cmm, repo};
use serde_json::{json, Value};

/// `cmm check` output of io1-flange aligned on the top points `top` and
/// four points round the outside.
fn check_aligned(dir: &std::path::Path, top: Value) -> String {
    let text = std::fs::read_to_string(repo("part-programs/io1-flange.json")).unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["workpiece"] = arg(&repo("workpieces/io1-flange.stp")).into();
    let mut points = top.as_array().unwrap().clone();
    points.extend([
        json!([3, 44, 0]),
        json!([3, -44, 0]),
        json!([3, 0, 44]),
        json!([3, 0, -44]),
    ]);
    p["alignment"] = json!({ "points_mm": points });
    let prog = common::write_program(dir, "aligned.json", &p);
    let out = cmm(&["check", &arg(&prog)]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn a_narrow_alignment_is_noted_and_a_wide_one_not() {
    let dir = tempfile::tempdir().unwrap();
    let narrow = check_aligned(dir.path(), json!([[6, 40, 0], [6, 42, 0], [6, 40, 2]]));
    let weak: Vec<&str> = narrow.lines().filter(|l| l.contains("weakly")).collect();
    assert!(!weak.is_empty(), "{narrow}");
    assert!(weak.iter().any(|l| l.contains("a turn about")), "{narrow}");
    let wide = check_aligned(dir.path(), json!([[6, 40, 0], [6, -40, 0], [6, 20, 34.64]]));
    assert!(!wide.contains("weakly"), "{wide}");
    assert!(wide.contains("do not fix a turn about the axis"), "{wide}");
}
