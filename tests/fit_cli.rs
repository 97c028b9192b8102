//! `cmm fit` run as a program: JSON keys of the cmm-fit/1 format, text output,
//! probe compensation, --out, and exit 2 with a message for bad input.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn write_csv(dir: &Path, name: &str, pts: &[[f64; 3]]) -> PathBuf {
    let mut text = String::from("id,x,y,z\n");
    for (i, p) in pts.iter().enumerate() {
        text += &format!("{i},{:.17e},{:.17e},{:.17e}\n", p[0], p[1], p[2]);
    }
    let path = dir.join(name);
    if let Err(e) = std::fs::write(&path, text) {
        panic!("cannot write {}: {e}", path.display());
    }
    path
}

fn cmm(args: &[&str]) -> Output {
    match Command::new(env!("CARGO_BIN_EXE_cmm")).args(args).output() {
        Ok(o) => o,
        Err(e) => panic!("cannot run cmm: {e}"),
    }
}

fn json_of(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "cmm failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    match serde_json::from_slice(&out.stdout) {
        Ok(v) => v,
        Err(e) => panic!(
            "stdout is not JSON ({e}): {}",
            String::from_utf8_lossy(&out.stdout)
        ),
    }
}

fn tmp() -> tempfile::TempDir {
    match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => panic!("no temp dir: {e}"),
    }
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("key {key} missing or not a number in {v}"))
}

fn vec3(v: &Value, key: &str) -> [f64; 3] {
    let arr = v[key]
        .as_array()
        .unwrap_or_else(|| panic!("key {key} missing in {v}"));
    assert_eq!(arr.len(), 3, "{key} must have 3 components");
    [0, 1, 2].map(|i| arr[i].as_f64().unwrap_or(f64::NAN))
}

/// Points on a sphere of radius 5 about (1, 2, 3).
fn sphere_points() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for i in 0..6 {
        for k in 0..8 {
            let (pol, az) = (
                0.3 + 0.45 * i as f64,
                std::f64::consts::TAU * k as f64 / 8.0,
            );
            pts.push([
                1.0 + 5.0 * pol.sin() * az.cos(),
                2.0 + 5.0 * pol.sin() * az.sin(),
                3.0 + 5.0 * pol.cos(),
            ]);
        }
    }
    pts
}

fn cylinder_points() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for z in [0.0, 4.0, 9.0] {
        for k in 0..10 {
            let a = std::f64::consts::TAU * k as f64 / 10.0;
            pts.push([4.0 * a.cos(), 4.0 * a.sin() - 1.0, z]);
        }
    }
    pts
}

fn cone_points() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for z in [2.0, 5.0, 7.0] {
        for k in 0..9 {
            let a = std::f64::consts::TAU * k as f64 / 9.0;
            pts.push([z * a.cos(), z * a.sin(), -z]);
        }
    }
    pts
}

fn check_common(v: &Value, element: &str, method: &str) {
    assert_eq!(v["format"], "cmm-fit/1");
    assert_eq!(v["element"], element);
    assert_eq!(v["method"], method);
    for k in ["rms", "min", "max"] {
        assert!(v["residuals_mm"][k].is_number(), "residuals_mm.{k} in {v}");
    }
    assert!(v["form_mm"].is_number(), "form_mm in {v}");
}

#[test]
fn json_keys_per_element() {
    let dir = tmp();
    let sphere = write_csv(dir.path(), "s.csv", &sphere_points());
    let cyl = write_csv(dir.path(), "c.csv", &cylinder_points());
    let cone = write_csv(dir.path(), "k.csv", &cone_points());
    let cases: [(&str, &PathBuf, &[&str]); 6] = [
        ("sphere", &sphere, &["center", "radius", "diameter"]),
        ("plane", &cyl, &["point", "normal"]),
        ("line", &cyl, &["point", "direction"]),
        (
            "circle",
            &sphere,
            &["center", "normal", "radius", "diameter"],
        ),
        (
            "cylinder",
            &cyl,
            &["axis_point", "axis_direction", "radius", "diameter"],
        ),
        ("cone", &cone, &["apex", "axis_direction", "apex_angle_deg"]),
    ];
    for (element, file, keys) in cases {
        let path = file.to_string_lossy();
        let v = json_of(&cmm(&["fit", "--element", element, &path, "--json"]));
        check_common(&v, element, "lsq");
        for k in keys {
            assert!(!v[*k].is_null(), "{element}: key {k} missing in {v}");
        }
    }
}

#[test]
fn json_values_sphere_cylinder_cone() {
    let dir = tmp();
    let s = write_csv(dir.path(), "s.csv", &sphere_points());
    let v = json_of(&cmm(&[
        "fit",
        "--element",
        "sphere",
        &s.to_string_lossy(),
        "--json",
    ]));
    let c = vec3(&v, "center");
    assert!(
        (c[0] - 1.0).abs() < 1e-9 && (c[1] - 2.0).abs() < 1e-9 && (c[2] - 3.0).abs() < 1e-9,
        "{v}"
    );
    assert!((num(&v, "diameter") - 10.0).abs() < 1e-9, "{v}");
    let k = write_csv(dir.path(), "k.csv", &cone_points());
    let v = json_of(&cmm(&[
        "fit",
        "--element",
        "cone",
        &k.to_string_lossy(),
        "--json",
    ]));
    assert!((num(&v, "apex_angle_deg") - 90.0).abs() < 1e-9, "{v}");
    let axis = vec3(&v, "axis_direction");
    assert!(
        (axis[2] + 1.0).abs() < 1e-12,
        "axis must point to growing radius (-z): {v}"
    );
    let apex = vec3(&v, "apex");
    assert!(apex.iter().all(|x| x.abs() < 1e-9), "{v}");
}

#[test]
fn probe_compensation_inside_and_outside() {
    let dir = tmp();
    let s = write_csv(dir.path(), "s.csv", &sphere_points());
    let path = s.to_string_lossy();
    let run = |side: &str| {
        let v = json_of(&cmm(&[
            "fit",
            "--element",
            "sphere",
            &path,
            "--json",
            "--probe-radius",
            "1.5",
            "--side",
            side,
        ]));
        num(&v, "radius")
    };
    assert!((run("outside") - 3.5).abs() < 1e-9);
    assert!((run("inside") - 6.5).abs() < 1e-9);
}

#[test]
fn text_output_and_out_file() {
    let dir = tmp();
    let c = write_csv(dir.path(), "c.csv", &cylinder_points());
    let out = cmm(&["fit", "--element", "cylinder", &c.to_string_lossy()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("radius") && text.contains("form"),
        "{text}"
    );
    let target = dir.path().join("fit.json");
    let target_s = target.to_string_lossy();
    let out = cmm(&[
        "fit",
        "--element",
        "cylinder",
        &c.to_string_lossy(),
        "--method",
        "minimum-zone",
        "--json",
        "--out",
        &target_s,
    ]);
    assert!(out.status.success() && out.stdout.is_empty());
    let written = std::fs::read_to_string(&target).unwrap_or_default();
    let v: Value = serde_json::from_str(&written).unwrap_or(Value::Null);
    check_common(&v, "cylinder", "minimum-zone");
}

fn expect_exit_2(args: &[&str], needle: &str) {
    let out = cmm(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert!(
        err.contains(needle),
        "stderr should mention '{needle}': {err}"
    );
    assert!(out.stdout.is_empty(), "nothing on stdout for a failure");
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let dir = tmp();
    let few = write_csv(
        dir.path(),
        "few.csv",
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    );
    expect_exit_2(
        &["fit", "--element", "sphere", &few.to_string_lossy()],
        "at least 4 points, got 3",
    );
    let line: Vec<[f64; 3]> = (0..5).map(|i| [i as f64, 0.0, 1.0]).collect();
    let col = write_csv(dir.path(), "col.csv", &line);
    expect_exit_2(
        &[
            "fit",
            "--element",
            "plane",
            &col.to_string_lossy(),
            "--json",
        ],
        "collinear",
    );
    let nan = dir.path().join("nan.csv");
    let _ = std::fs::write(&nan, "x,y,z\n1,2,3\nNaN,0,0\n4,5,6\n");
    expect_exit_2(
        &["fit", "--element", "circle", &nan.to_string_lossy()],
        "not finite",
    );
    expect_exit_2(
        &["fit", "--element", "circle", "/nonexistent/p.csv"],
        "cannot read",
    );
    expect_exit_2(
        &["fit", "--element", "ellipse", &few.to_string_lossy()],
        "ellipse",
    );
    expect_exit_2(
        &[
            "fit",
            "--element",
            "plane",
            &col.to_string_lossy(),
            "--probe-radius",
            "1",
        ],
        "--side",
    );
    let target = dir.path().join("never.json");
    let out = cmm(&[
        "fit",
        "--element",
        "plane",
        &col.to_string_lossy(),
        "--out",
        &target.to_string_lossy(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!target.exists(), "no output file after a failure");
}
