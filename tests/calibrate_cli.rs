//! `cmm calibrate-probe --probe FILE`: the nominal probe from a file.
use std::path::Path;
use std::process::{Command, Output};

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

/// `cmm calibrate-probe --probe PROBE --out OUT`.
fn calibrate(probe: &Path, out: &Path) -> Output {
    cmm(&[
        "calibrate-probe",
        "--probe",
        probe.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

/// A 4 mm ball on a 40 mm stylus given by a probe block: the calibration
/// finds the ball 40 mm below the mount and a 2 mm radius (simulated probe
/// errors are micrometres), and a whole part program's block works too.
#[test]
fn probe_file_sets_the_nominal_probe() {
    let dir = tempfile::tempdir().unwrap();
    let block = dir.path().join("probe.json");
    std::fs::write(
        &block,
        r#"{"tip_diameter_mm": 4.0, "stylus_length_mm": 40}"#,
    )
    .unwrap();
    let program = dir.path().join("program.json");
    std::fs::write(
        &program,
        r#"{"format": "cmm-program/1", "name": "p", "workpiece": "w.json",
            "probe": {"tip_diameter_mm": 4.0, "stylus_length_mm": 40}, "features": []}"#,
    )
    .unwrap();
    for file in [&block, &program] {
        let out = dir.path().join("cal.json");
        let run = cmm(&[
            "calibrate-probe",
            "--probe",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let cal: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let pv = cal["probe_vector_mm"].as_array().unwrap();
        let z = pv[2].as_f64().unwrap();
        let r = cal["tip_radius_mm"].as_f64().unwrap();
        assert!((z + 40.0).abs() < 0.05, "probe vector z {z}");
        assert!((r - 2.0).abs() < 0.01, "tip radius {r}");
        let truth = cal["simulation_truth"]["tip_radius_mm"].as_f64().unwrap();
        assert!((r - truth).abs() < 0.2e-3, "{r} vs truth {truth}");
    }
}

#[test]
fn bad_probe_files_exit_2_naming_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            r#"{"tip_diameter_mm": -3, "stylus_length_mm": 50}"#,
            "$.tip_diameter_mm",
        ),
        (r#"{"tip_diameter_mm": 3, "stylus": 50}"#, "stylus"),
        (
            r#"{"probe": {"tip_diameter_mm": 3, "stylus_length_mm": 0}}"#,
            "$.probe.stylus_length_mm",
        ),
        (r#"{"tip_diameter_mm": 3,"#, "probe.json"),
    ];
    for (text, expected) in cases {
        let file = dir.path().join("probe.json");
        std::fs::write(&file, text).unwrap();
        let out = dir.path().join("cal.json");
        let run = calibrate(&file, &out);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{text}: {err}");
        assert!(
            err.contains(expected) && err.contains("probe.json"),
            "{text}: {err}"
        );
        assert!(!out.exists(), "nothing written for {text}");
    }
    let missing = cmm(&["calibrate-probe", "--probe", "/nonexistent/probe.json"]);
    assert_eq!(missing.status.code(), Some(2));
    let both = cmm(&[
        "calibrate-probe",
        "--probe",
        "p.json",
        "--stylus-length",
        "40",
    ]);
    assert_eq!(both.status.code(), Some(2), "--probe with --stylus-length");
}

/// A 1 mm ball takes at most 0.45 mm of deflection: without
/// `--deflections` it is calibrated at those of 0.1, 0.2, 0.3 and 0.5 mm
/// it allows, and asked for 0.5 mm it is refused (exit 2).
#[test]
fn default_deflections_follow_the_tip() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.json");
    let args = [
        "calibrate-probe",
        "--probe-tip-diameter",
        "1",
        "--ideal",
        "--out",
    ];
    let run = cmm(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert!(run.status.success(), "{run:?}");
    let cal: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(
        cal["conditions"]["deflections_mm"],
        serde_json::json!([0.1, 0.2, 0.3])
    );
    assert!((cal["tip_radius_mm"].as_f64().unwrap() - 0.5).abs() < 1e-6);
    let refused = dir.path().join("refused.json");
    let run = cmm(&[
        &args[..],
        &[refused.to_str().unwrap(), "--deflections", "0.5"],
    ]
    .concat());
    assert_eq!(run.status.code(), Some(2), "{run:?}");
    assert!(!refused.exists());
}

/// A 0.6 mm ball on the default shaft (0.3 mm thick): below the equator
/// its vertical shaft meets the 25 mm sphere 3.9 degrees down at 0.1 mm of
/// deflection, so its arcs stop there, and it is calibrated to its true
/// radius within a micrometre.
#[test]
fn a_small_ball_is_calibrated_without_its_shaft_touching_the_sphere() {
    let dir = tempfile::tempdir().unwrap();
    calibrated_to_the_truth(dir.path(), &["--probe-tip-diameter", "0.6"]);
}

/// `cmm calibrate-probe ARGS` into `dir/cal.json`, which must succeed and
/// find the simulated tip radius within a micrometre: the calibration.
fn calibrated_to_the_truth(dir: &std::path::Path, args: &[&str]) -> serde_json::Value {
    let out = dir.join("cal.json");
    let mut all = vec!["calibrate-probe"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", out.to_str().unwrap()]);
    let run = cmm(&all);
    assert!(run.status.success(), "{run:?}");
    let cal: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let found = cal["tip_radius_mm"].as_f64().unwrap();
    let truth = cal["simulation_truth"]["tip_radius_mm"].as_f64().unwrap();
    assert!((found - truth).abs() < 1e-3, "{found} vs {truth}");
    cal
}

/// A probe file's shaft diameter is the shaft calibrated with: a 0.9 mm
/// shaft on a 1 mm ball meets the 25 mm sphere below its equator at any
/// deflection, so the XZ and YZ arcs stop at the equator (fewer points
/// than on the default 0.5 mm shaft, whose arcs reach 8 degrees below at
/// 0.1 mm deflection), and the thick shaft never touches the sphere.
#[test]
fn a_probe_files_shaft_diameter_limits_the_arcs() {
    let dir = tempfile::tempdir().unwrap();
    let xz_points = |probe: &str| {
        let file = dir.path().join("probe.json");
        std::fs::write(&file, probe).unwrap();
        let args = ["--probe", file.to_str().unwrap(), "--deflections", "0.1"];
        let cal = calibrated_to_the_truth(dir.path(), &args);
        let scans = cal["scans"].as_array().unwrap().clone();
        let xz = scans.iter().find(|s| s["plane"] == "xz").unwrap();
        xz["points"].as_u64().unwrap()
    };
    let plain = xz_points(r#"{"tip_diameter_mm": 1.0, "stylus_length_mm": 30}"#);
    let thick =
        xz_points(r#"{"tip_diameter_mm": 1.0, "stylus_length_mm": 30, "shaft_diameter_mm": 0.9}"#);
    assert!(
        thick < plain,
        "{thick} points on the thick shaft, {plain} on the default"
    );
}
