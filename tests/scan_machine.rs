//! `cmm scan` on another machine: `--machine`, `--machine-profile`,
//! `--no-compensation` and the program's `machine` and `machine_profile`
//! keys. The reference is the truth the simulator reports for every point
//! (`true_deviation_mm`) and the URDF's own numbers.
mod common;

use std::path::Path;

use common::{arg as s, cmm, repo};
use serde_json::Value;

fn report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// Largest |deviation - true deviation| over every point, mm: the
/// measurement error.
fn worst_error(r: &Value) -> f64 {
    let features = r["features"].as_array().unwrap();
    let points = features
        .iter()
        .flat_map(|f| f["points"].as_array().unwrap().iter());
    let errors: Vec<f64> = points
        .map(|p| {
            (p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap()).abs()
        })
        .collect();
    assert!(errors.len() > 100, "{} points", errors.len());
    errors.into_iter().fold(0.0, f64::max)
}

/// The shipped error profile with large squareness and X scale errors
/// (tens of micrometres over the sphere's position) and no scale noise.
fn large_error_profile(dir: &Path) -> String {
    let text = std::fs::read_to_string(repo(
        "part-programs/machines/bridge-profile-with-errors.json",
    ))
    .unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["linear"]["scale_noise_mm"] = 0.0.into();
    p["linear"]["scale_resolution_mm"] = 0.0.into();
    p["geometric"]["squareness"] =
        serde_json::json!({ "xy_rad": 1e-4, "xz_rad": -8e-5, "yz_rad": 6e-5 });
    p["geometric"]["x"]["scale_mm"] = serde_json::json!([0, 1e-4]);
    let path = dir.join("large-errors.json");
    std::fs::write(&path, p.to_string()).unwrap();
    s(&path)
}

fn scan(out: &Path, extra: &[&str]) -> Value {
    let sphere = s(&repo("part-programs/sphere.json"));
    let mut args = vec!["scan", &sphere, "--quiet"];
    let out_s = s(out);
    args.extend(["--out", &out_s]);
    args.extend(extra);
    let o = cmm(&args);
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    report(out)
}

#[test]
fn the_host_compensates_the_profiles_geometric_errors() {
    let dir = tempfile::tempdir().unwrap();
    let profile = large_error_profile(dir.path());
    let plain = worst_error(&scan(&dir.path().join("plain"), &[]));
    let comp = worst_error(&scan(
        &dir.path().join("comp"),
        &["--machine-profile", &profile],
    ));
    let raw = worst_error(&scan(
        &dir.path().join("raw"),
        &["--machine-profile", &profile, "--no-compensation"],
    ));
    // Compensated: only the uncalibrated probe's own error is left, as on
    // the error-free machine.
    assert!(comp < plain + 2e-3, "compensated {comp} vs {plain} mm");
    // Without compensation the machine's errors (squareness 1e-4 rad over
    // the sphere's 500-700 mm position: tens of micrometres) show.
    assert!(raw > plain + 0.05, "uncompensated {raw} vs {plain} mm");
}

#[test]
fn a_machine_with_a_head_carries_the_stylus_by_its_offsets() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = s(&repo("part-programs/machines/bridge-ab-head.urdf"));
    let r = scan(&dir.path().join("o"), &["--machine", &urdf, "--ideal"]);
    // The URDF's head joints sit 0.05, 0.03 and 0.02 m below the spindle:
    // the 50 mm stylus hangs 150 mm below it.
    let pv: Vec<f64> = r["probe"]["probe_vector_mm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!((pv[0]).abs() < 1e-9 && (pv[1]).abs() < 1e-9, "{pv:?}");
    assert!((pv[2] + 150.0).abs() < 1e-9, "{pv:?}");
    assert_eq!(r["status"], "pass");
    assert!(worst_error(&r) < 5e-4, "{}", worst_error(&r));
}

/// The sphere program with `key` set to `value` (paths relative to the
/// copy in `dir`).
fn program_with(dir: &Path, name: &str, keys: &[(&str, &str)]) -> String {
    let text = std::fs::read_to_string(repo("part-programs/sphere.json")).unwrap();
    let mut p: Value = serde_json::from_str(&text).unwrap();
    p["workpiece"] = s(&repo("workpieces/sphere.json")).into();
    for (k, v) in keys {
        p[*k] = (*v).into();
    }
    let path = dir.join(name);
    std::fs::write(&path, p.to_string()).unwrap();
    s(&path)
}

#[test]
fn the_programs_machine_keys_are_read_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    large_error_profile(dir.path());
    let prog = program_with(
        dir.path(),
        "p.json",
        &[("machine_profile", "large-errors.json")],
    );
    let run = |name: &str, extra: &[&str]| {
        let out = s(&dir.path().join(name));
        let mut args = vec!["scan", &prog, "--quiet", "--out", &out];
        args.extend(extra);
        let o = cmm(&args);
        assert!(matches!(o.status.code(), Some(0 | 1)));
        worst_error(&report(&dir.path().join(name)))
    };
    assert!(run("raw", &["--no-compensation"]) > 0.05);
    assert!(run("comp", &[]) < 0.02);
}

#[test]
fn a_bad_machine_file_is_exit_2_naming_the_key_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    for (key, file) in [
        ("machine", "missing.urdf"),
        ("machine_profile", "missing.json"),
    ] {
        let prog = program_with(dir.path(), "p.json", &[(key, file)]);
        let out = dir.path().join("o");
        let o = cmm(&["scan", &prog, "--quiet", "--out", &s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains(&format!("$.{key}")) && err.contains(file),
            "{err}"
        );
        assert!(!out.exists());
    }
    let prog = program_with(dir.path(), "q.json", &[]);
    let o = cmm(&[
        "scan",
        &prog,
        "--machine",
        &s(&dir.path().join("none.urdf")),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("none.urdf"), "{err}");
}

#[test]
fn the_reach_is_checked_against_the_machines_own_travel() {
    let dir = tempfile::tempdir().unwrap();
    let bridge = std::fs::read_to_string(repo("part-programs/machines/bridge-ab-head.urdf"))
        .unwrap()
        .replace("upper=\"0.7\"", "upper=\"0.45\"");
    let urdf = dir.path().join("short-x.urdf");
    std::fs::write(&urdf, bridge).unwrap();
    // The sphere sits at x = 500 mm: beyond an X axis of 450 mm.
    let prog = program_with(dir.path(), "p.json", &[("machine", "short-x.urdf")]);
    let o = cmm(&["check", &prog]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("$.placement") && err.contains("450"), "{err}");
}
