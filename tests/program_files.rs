//! Part programs: the shipped examples validate; broken programs are
//! rejected before anything runs, naming the file, the JSON path and the reason.
mod common;

use std::process::Command;

use common::repo;
use serde_json::{json, Value};

fn base() -> Value {
    let text = std::fs::read_to_string(repo("part-programs/blade-z60.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v["workpiece"] = json!(repo("workpieces/blade.json").to_string_lossy());
    v
}

fn check(v: &Value) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("prog.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .arg("check")
        .arg(&p)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn shipped_programs_check_clean() {
    for entry in std::fs::read_dir(repo("part-programs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let out = Command::new(env!("CARGO_BIN_EXE_cmm"))
                .arg("check")
                .arg(&path)
                .output()
                .unwrap();
            assert_eq!(
                out.status.code(),
                Some(0),
                "{}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
    assert_eq!(check(&base()).0, Some(0));
}

#[test]
fn broken_programs_exit_2_naming_the_place() {
    type Edit = Box<dyn Fn(&mut Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["format"] = json!("cmm-program/9")),
            "$.format",
        ),
        (Box::new(|v| v["extra"] = json!(true)), "extra"),
        (Box::new(|v| v["features"] = json!([])), "$.features"),
        (
            Box::new(|v| v["workpiece"] = json!("missing.json")),
            "$.workpiece",
        ),
        (
            Box::new(|v| v["features"][1]["name"] = json!("z60")),
            "$.features[1].name",
        ),
        (
            Box::new(|v| v["features"][0]["plane"]["origin_mm"] = json!([0, 0, 500])),
            "$.features[0].plane",
        ),
        (
            Box::new(|v| v["features"][0]["plane"]["normal"] = json!([0, 0, 0])),
            "$.features[0].plane.normal",
        ),
        (
            Box::new(|v| v["features"][1]["surfaces"] = json!(["hub"])),
            "$.features[1].surfaces[0]",
        ),
        (
            Box::new(|v| v["features"][0]["tolerance_mm"] = json!([0.1, -0.1])),
            "$.features[0].tolerance_mm",
        ),
        (
            Box::new(|v| v["features"][0]["tolerance_mm"] = json!("tight")),
            "$.features[0]",
        ),
        (
            Box::new(|v| v["features"][0]["type"] = json!("laser_scan")),
            "$.features[0]",
        ),
        (
            Box::new(|v| v["features"][0]["mode"] = json!("turbo")),
            "$.features[0]",
        ),
        (
            Box::new(|v| v["defaults"]["speed_mm_s"] = json!(-5)),
            "$.defaults.speed_mm_s",
        ),
        (
            Box::new(|v| v["defaults"]["deflection_mm"] = json!(5)),
            "$.defaults.deflection_mm",
        ),
        (
            Box::new(|v| v["features"][0]["pitch_mm"] = json!(0)),
            "$.features[0].pitch_mm",
        ),
        (
            Box::new(|v| v["probe"]["tip_diameter_mm"] = json!(0)),
            "$.probe.tip_diameter_mm",
        ),
        (
            Box::new(|v| v["probe"]["calibration"] = json!("nope.json")),
            "$.probe.calibration",
        ),
        (
            Box::new(|v| v["placement"]["translate_mm"] = json!([2000, 0, 0])),
            "$.placement",
        ),
        (
            Box::new(|v| v["placement"]["rotate_deg"] = json!([0, 0, 400])),
            "$.placement.rotate_deg",
        ),
        (
            Box::new(|v| v["as_machined"]["transform"] = json!({"rotate_deg": [0, 0, 1e300]})),
            "$.as_machined.transform.rotate_deg",
        ),
        (
            Box::new(|v| v["as_machined"]["form"][1]["radius_mm"] = json!(0)),
            "$.as_machined.form[1].radius_mm",
        ),
        (
            Box::new(|v| v["as_machined"]["form"][0]["surfaces"] = json!(["tip"])),
            "$.as_machined.form[0].surfaces[0]",
        ),
        (
            Box::new(
                |v| v["features"][0] = json!({"name": "t", "type": "touch_points", "points_mm": [[0, 0, 300]], "tolerance_mm": [-1, 1]}),
            ),
            "$.features[0].points_mm[0]",
        ),
        (
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("workpiece");
            }),
            "workpiece",
        ),
    ];
    for (k, (edit, want)) in cases.iter().enumerate() {
        let mut v = base();
        edit(&mut v);
        let (code, err) = check(&v);
        assert_eq!(code, Some(2), "case {k}: {err}");
        assert!(
            err.contains("prog.json"),
            "case {k}: no file named in '{err}'"
        );
        assert!(err.contains(want), "case {k}: expected '{want}' in '{err}'");
    }
}

#[test]
fn syntax_errors_have_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("prog.json");
    std::fs::write(&p, "{\n  \"format\": \"cmm-program/1\",\n  \"name\": ,\n}").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .arg("check")
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("prog.json:3:"));
}
