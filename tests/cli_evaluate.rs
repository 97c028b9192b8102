//! `cmm evaluate` and `cmm schema` as a user runs them.
mod common;

use std::process::Command;

use common::repo;

fn cmm(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

#[test]
fn json_output_follows_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let pts = write(&dir, "p.csv", "id,x,y,z\n1,20,0,0\n2,0,0,-14\n3,0,3,4\n");
    let wp = repo("workpieces/sphere.json");
    let out = cmm(&[
        "evaluate",
        "--workpiece",
        wp.to_str().unwrap(),
        "--points",
        &pts,
        "--json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["format"], "cmm-evaluate/1");
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), 3);
    let want = [7.5, 1.5, -7.5];
    for (p, w) in points.iter().zip(want) {
        for key in [
            "input",
            "surface",
            "u",
            "v",
            "nominal",
            "normal",
            "deviation_mm",
        ] {
            assert!(p.get(key).is_some(), "missing {key}");
        }
        assert!((p["deviation_mm"].as_f64().unwrap() - w).abs() < 1e-9);
        let n: Vec<f64> = p["normal"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-12);
    }
    assert_eq!(points[1]["input"], serde_json::json!([0.0, 0.0, -14.0]));
}

#[test]
fn csv_output_and_out_file() {
    let dir = tempfile::tempdir().unwrap();
    let pts = write(&dir, "p.csv", "x,y,z\n25,0,5\n");
    let out_file = dir.path().join("dev.csv");
    let wp = repo("workpieces/bore.json");
    let out = cmm(&[
        "evaluate",
        "--workpiece",
        wp.to_str().unwrap(),
        "--points",
        &pts,
        "--out",
        out_file.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stdout.is_empty());
    let text = std::fs::read_to_string(out_file).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("x,y,z,surface,u,v"));
    assert!(lines.next().unwrap().starts_with("25,0,5,bore,"));
}

#[test]
fn bad_point_files_exit_2_with_file_line_and_reason() {
    let dir = tempfile::tempdir().unwrap();
    let wp = repo("workpieces/sphere.json");
    let cases = [
        ("", "p.csv:1"),
        ("a,b,c\n1,2,3\n", "no column 'x'"),
        ("x,y,z\n1,2,3\n4,five,6\n", "p.csv:3"),
        ("x,y,z\n1,2\n", "p.csv:2"),
        ("x,y,z\n", "no points"),
        ("x,y,z\n1,2,inf\n", "not finite"),
    ];
    for (text, want) in cases {
        let pts = write(&dir, "p.csv", text);
        let out_file = dir.path().join("never.json");
        let out = cmm(&[
            "evaluate",
            "--workpiece",
            wp.to_str().unwrap(),
            "--points",
            &pts,
            "--json",
            "--out",
            out_file.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{text:?}: {err}");
        assert!(err.contains(want), "{text:?}: expected '{want}' in '{err}'");
        assert!(!out_file.exists(), "no output on bad input");
    }
}

#[test]
fn bad_workpiece_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let wp = write(
        &dir,
        "w.json",
        r#"{"format":"cmm-workpiece/1","name":"x","surfaces":[]}"#,
    );
    let pts = write(&dir, "p.csv", "x,y,z\n1,2,3\n");
    let out = cmm(&["evaluate", "--workpiece", &wp, "--points", &pts]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("w.json") && err.contains("$.surfaces"),
        "{err}"
    );
}

#[test]
fn schema_describes_the_workpiece_format() {
    let out = cmm(&["schema", "workpiece"]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let props = &v["properties"];
    for key in ["format", "name", "units", "surfaces"] {
        assert!(props.get(key).is_some(), "schema lacks {key}");
    }
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(cmm(&["evaluate"]).status.code(), Some(2));
    assert_eq!(cmm(&["frobnicate"]).status.code(), Some(2));
}
