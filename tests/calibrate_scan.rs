//! `cmm calibrate-probe` and `cmm scan --probe-cal`: the calibration file,
//! the measurement error of a blade scan with and without it, a calibration
//! used under other conditions, and bad calibration files.
mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::repo;
use serde_json::Value;

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

fn json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// RMS of `deviation_mm - true_deviation_mm` over all points, mm.
fn rms_error(report: &Value) -> f64 {
    let e: Vec<f64> = report["features"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|f| f["points"].as_array().unwrap().iter())
        .map(|p| p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap())
        .collect();
    (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt()
}

/// Scans `program` (optionally with a calibration) and returns the report.
fn scan(program: &Path, cal: Option<&Path>, out: &Path) -> Value {
    let mut args = vec![
        "scan".to_string(),
        s(program),
        "--quiet".into(),
        "--out".into(),
        s(out),
    ];
    if let Some(c) = cal {
        args.extend(["--probe-cal".into(), s(c)]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = cmm(&args);
    assert!(o.status.code().is_some_and(|c| c <= 1), "{o:?}");
    json(&out.join("report.json"))
}

fn calibrate(out: &Path, extra: &[&str]) {
    let mut args = vec!["calibrate-probe", "--out"];
    let o = s(out);
    args.push(&o);
    args.extend_from_slice(extra);
    let res = cmm(&args);
    assert_eq!(res.status.code(), Some(0), "{res:?}");
}

#[test]
fn calibration_file_and_blade_scan_error_drops() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("probe-cal.json");
    calibrate(&cal, &["--seed", "3", "--stylus-length", "100"]);
    let file = json(&cal);
    assert_eq!(file["format"], "cmm-probe-cal/1");
    for key in ["probe_vector_mm", "sphere_center_mm"] {
        assert_eq!(file[key].as_array().unwrap().len(), 3);
    }
    assert!(file["tip_radius_mm"].as_f64().unwrap() > 1.49);
    assert!(file["probing_error_mm"].as_f64().unwrap() < 1e-3);
    assert!(file["simulation_truth"]["tip_radius_mm"].is_f64());

    let blade = repo("part-programs/blade-z60.json");
    let nominal = scan(&blade, None, &dir.path().join("nominal"));
    let calibrated = scan(&blade, Some(&cal), &dir.path().join("cal"));
    assert_eq!(nominal["probe"]["source"], "nominal");
    assert_eq!(calibrated["probe"]["source"], s(&cal));
    let (before, after) = (rms_error(&nominal), rms_error(&calibrated));
    assert!(after <= 1e-3, "calibrated RMS error {after} mm");
    assert!(after * 5.0 <= before, "RMS error {before} -> {after} mm");
}

#[test]
fn calibration_under_other_conditions_still_helps() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("blade-05.json");
    let text = std::fs::read_to_string(repo("part-programs/blade-z60.json")).unwrap();
    let wp = s(&repo("workpieces/blade.json"));
    let text = text
        .replace("\"deflection_mm\": 0.3", "\"deflection_mm\": 0.5")
        .replace("../workpieces/blade.json", &wp);
    std::fs::write(&program, text).unwrap();
    let nominal = rms_error(&scan(&program, None, &dir.path().join("n")));
    // One direction at 0.2 mm each; the blade is scanned at 0.5 mm, so one of
    // the two is also the other direction.
    for dirn in ["cw", "ccw"] {
        let cal = dir.path().join(format!("{dirn}.json"));
        calibrate(
            &cal,
            &[
                "--deflections",
                "0.2",
                "--directions",
                dirn,
                "--stylus-length",
                "100",
            ],
        );
        let err = rms_error(&scan(&program, Some(&cal), &dir.path().join(dirn)));
        assert!(err < 0.7 * nominal, "{dirn}: {nominal} -> {err} mm");
    }
}

#[test]
fn bad_calibration_files_exit_2_naming_file_and_path() {
    let dir = tempfile::tempdir().unwrap();
    let blade = s(&repo("part-programs/blade-z60.json"));
    let cases = [
        ("notjson.json", "{ nope".to_string(), "$"),
        (
            "unknown.json",
            r#"{"format":"cmm-probe-cal/1","probe_vector_mm":[0,0,-50],"tip_radius_mm":1.5,"sphere_center_mm":[0,0,0],"probing_error_mm":0,"bogus":1}"#.into(),
            "bogus",
        ),
        (
            "radius.json",
            r#"{"format":"cmm-probe-cal/1","probe_vector_mm":[0,0,-50],"tip_radius_mm":-1,"sphere_center_mm":[0,0,0],"probing_error_mm":0}"#.into(),
            "$.tip_radius_mm",
        ),
        (
            "format.json",
            r#"{"format":"other/1","probe_vector_mm":[0,0,-50],"tip_radius_mm":1.5,"sphere_center_mm":[0,0,0],"probing_error_mm":0}"#.into(),
            "$.format",
        ),
        (
            "type.json",
            r#"{"format":"cmm-probe-cal/1","probe_vector_mm":[0,"x",-50],"tip_radius_mm":1.5,"sphere_center_mm":[0,0,0],"probing_error_mm":0}"#.into(),
            "$.probe_vector_mm[1]",
        ),
    ];
    for (name, text, path) in cases {
        let file = dir.path().join(name);
        std::fs::write(&file, text).unwrap();
        let out = dir.path().join(format!("out-{name}"));
        let o = cmm(&[
            "scan",
            &blade,
            "--quiet",
            "--out",
            &s(&out),
            "--probe-cal",
            &s(&file),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(name) && err.contains(path), "{name}: {err}");
        assert!(!out.join("report.json").exists());
    }
}

#[test]
fn simulation_truth_is_accepted_and_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cal.json");
    let text = r#"{"format":"cmm-probe-cal/1","probe_vector_mm":[0,0,-50],"tip_radius_mm":1.5,
        "sphere_center_mm":[0,0,0],"probing_error_mm":0,
        "simulation_truth":{"anything":[1,2,3],"probe_vector_mm":"not read"}}"#;
    std::fs::write(&file, text).unwrap();
    let cal = cmm::host::calibrate::file::ProbeCalibration::read(&file).unwrap();
    assert_eq!(cal.probe.tip_radius_mm, 1.5);
}

#[test]
fn program_probe_calibration_is_used_and_checked() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    calibrate(&cal, &["--ideal", "--stylus-length", "100"]);
    let text = std::fs::read_to_string(repo("part-programs/blade-z60.json")).unwrap();
    let wp = s(&repo("workpieces/blade.json"));
    let with_cal = |name: &str| {
        text.replace("../workpieces/blade.json", &wp).replace(
            "\"stylus_length_mm\": 100 }",
            &format!("\"stylus_length_mm\": 100, \"calibration\": \"{name}\" }}"),
        )
    };
    let program = dir.path().join("p.json");
    std::fs::write(&program, with_cal("cal.json")).unwrap();
    let report = scan(&program, None, &dir.path().join("ok"));
    assert!(report["probe"]["source"]
        .as_str()
        .unwrap()
        .ends_with("cal.json"));
    std::fs::write(dir.path().join("bad.json"), "{}").unwrap();
    std::fs::write(&program, with_cal("bad.json")).unwrap();
    let o = cmm(&[
        "scan",
        &s(&program),
        "--quiet",
        "--out",
        &s(&dir.path().join("bad")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("bad.json"));
}
