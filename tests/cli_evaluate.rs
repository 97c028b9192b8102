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

/// A reference sphere of radius 12.5 mm whose poles point along
/// (sin 40 deg, 0, cos 40 deg) from the centre (10, -5, 3), as JSON.
fn tilted_sphere_json() -> String {
    let mut file = cmm::workpiece::examples::reference_sphere(25.0);
    let (s, c) = 40f64.to_radians().sin_cos();
    for cp in file.surfaces[0].control_points.iter_mut().flatten() {
        let [x, y, z] = *cp;
        *cp = [c * x + s * z + 10.0, y - 5.0, -s * x + c * z + 3.0];
    }
    cmm::workpiece::examples::to_json(&file)
}

#[test]
fn tilted_sphere_answers_every_point_with_status_ok() {
    let dir = tempfile::tempdir().unwrap();
    let wp = write(&dir, "tilted.json", &tilted_sphere_json());
    let (s, c) = 40f64.to_radians().sin_cos();
    let center = [10.0, -5.0, 3.0];
    // Directions from the centre (the poles and near them among them) and
    // radii; the analytic deviation is radius - 12.5.
    let dirs = [
        [s, 0.0, c],
        [-s, 0.0, -c],
        [s + 1e-7, 0.0, c],
        [1.0, 2.0, -0.5],
        [0.0, 1.0, 0.0],
        [-0.3, 0.2, 0.9],
    ];
    let radii = [0.4, 6.0, 12.5, 13.1, 30.0];
    let mut text = String::from("x,y,z\n");
    let mut want = vec![];
    for d in dirs {
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        for r in radii {
            let p: Vec<f64> = (0..3).map(|k| center[k] + d[k] / n * r).collect();
            text.push_str(&format!("{},{},{}\n", p[0], p[1], p[2]));
            want.push(r - 12.5);
        }
    }
    let pts = write(&dir, "p.csv", &text);
    let out = cmm(&["evaluate", "--workpiece", &wp, "--points", &pts, "--json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), want.len());
    for (k, (p, w)) in points.iter().zip(&want).enumerate() {
        assert_eq!(p["status"], "ok", "point {k}");
        let got = p["deviation_mm"].as_f64().unwrap();
        assert!((got - w).abs() < 1e-9, "point {k}: {got} vs {w}");
    }
    // CSV: the status is the last column.
    let out = cmm(&["evaluate", "--workpiece", &wp, "--points", &pts]);
    assert_eq!(out.status.code(), Some(0));
    let csv = String::from_utf8_lossy(&out.stdout);
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().ends_with(",deviation_mm,status"));
    assert_eq!(lines.filter(|l| l.ends_with(",ok")).count(), want.len());
}

#[test]
fn huge_finite_points_are_rejected_as_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let wp = repo("workpieces/sphere.json");
    let pts = write(&dir, "p.csv", "x,y,z\n1,2,3\n3.5e201,0,0\n");
    let out = cmm(&[
        "evaluate",
        "--workpiece",
        wp.to_str().unwrap(),
        "--points",
        &pts,
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("out of range") && err.contains("3.5e201"),
        "{err}"
    );
    assert!(!err.contains("not finite"), "{err}");
    assert!(out.stdout.is_empty());
    // Far but within range: answered.
    let pts = write(&dir, "q.csv", "x,y,z\n1e140,-2e139,5\n");
    let out = cmm(&[
        "evaluate",
        "--workpiece",
        wp.to_str().unwrap(),
        "--points",
        &pts,
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // So far out every point of the sphere is as close to rounding (the
    // sign is that of whichever foot came first).
    let got = v["points"][0]["deviation_mm"].as_f64().unwrap().abs();
    let want = (1e140f64).hypot(2e139) - 12.5;
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
}

#[test]
fn help_documents_the_exit_codes() {
    let out = cmm(&["evaluate", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("unconfirmed") && text.contains("3 "),
        "{text}"
    );
}
