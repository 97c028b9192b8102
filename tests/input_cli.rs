//! Bad input and faults through the command line: no panic, no hang, no
//! half-written output, and every error names the file, the place and the
//! reason, once, on stderr (exit 2).
mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use common::repo;

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

fn prog(name: &str) -> String {
    s(&repo(&format!("part-programs/{name}")))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2, no panic, stderr holds every one of `needles`, stdout is empty.
fn assert_bad_input(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "'{n}' missing in: {err}");
    }
    assert!(
        o.stdout.is_empty(),
        "stdout: {}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// The sphere program (radius 12.5 mm at (500, 700, 100)) rewritten by
/// `edit` and saved in `dir` beside a copy of its workpiece.
fn sphere_program(dir: &Path, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read_to_string(repo("part-programs/sphere.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    std::fs::copy(repo("workpieces/sphere.json"), dir.join("sphere.json")).unwrap();
    v["workpiece"] = "sphere.json".into();
    edit(&mut v);
    let path = dir.join("p.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

/// Runs `args` with stdout a pipe whose reading end is closed at once.
fn with_closed_stdout(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    child.wait_with_output().unwrap()
}

#[test]
fn a_closed_pipe_ends_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<Vec<String>> = vec![
        vec!["schema".into(), "program".into()],
        vec!["check".into(), prog("sphere.json")],
        vec![
            "calibrate-probe".into(),
            "--ideal".into(),
            "--out".into(),
            s(&dir.path().join("cal.json")),
        ],
    ];
    for args in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = with_closed_stdout(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        assert!(o.stderr.is_empty(), "{args:?}: {}", stderr(&o));
    }
    // A scan keeps its verdict (the reports are written) when nobody reads
    // the summary.
    let out = dir.path().join("scan");
    let o = with_closed_stdout(&["scan", &prog("sphere.json"), "--ideal", "--out", &s(&out)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(out.join("report.json").is_file());
}

#[test]
fn a_deeply_nested_urdf_is_refused_not_a_stack_overflow() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deep.urdf");
    let depth = 30_000;
    let text = format!(
        "<robot name=\"r\">\n{}{}</robot>\n",
        "<a>".repeat(depth),
        "</a>".repeat(depth)
    );
    std::fs::write(&path, text).unwrap();
    let o = cmm(&[
        "calibrate-probe",
        "--machine",
        &s(&path),
        "--out",
        &s(&dir.path().join("c.json")),
    ]);
    assert_bad_input(&o, &["deep.urdf", "line 2", "nested more than 32"]);
}

#[test]
fn urdf_errors_name_the_joint_and_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo("part-programs/machines/bridge-ab-head.urdf")).unwrap();
    // Joint 'a''s origin becomes unreadable for urdf-rs (two numbers).
    let bad = text.replace("<origin xyz=\"0 0 -0.03\"", "<origin xyz=\"0 zero -0.03\"");
    assert_ne!(bad, text);
    let at = text.find("<joint name=\"a\"").unwrap();
    let line = 1 + text[..at].matches('\n').count();
    let joint = "a";
    let path = dir.path().join("m.urdf");
    std::fs::write(&path, bad).unwrap();
    let out = s(&dir.path().join("c.json"));
    let o = cmm(&[
        "calibrate-probe",
        "--machine",
        &s(&path),
        "--head-angles",
        "0,0",
        "--out",
        &out,
    ]);
    assert_bad_input(
        &o,
        &[
            "m.urdf",
            &format!("line {line}"),
            &format!("joint '{joint}'"),
        ],
    );
}

#[test]
fn a_huge_tolerance_is_refused_with_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| {
        v["features"][0]["tolerance_mm"] = serde_json::json!([-1.797e308, 1.797e308]);
    });
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(
        &o,
        &["p.json", "$.features[0].tolerance_mm[0]", "tolerance"],
    );
}

#[test]
fn a_surface_named_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| {
        v["features"][0]["surfaces"] = serde_json::json!(["sphere", "sphere"]);
    });
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(&o, &["p.json", "$.features[0].surfaces[1]", "listed twice"]);
}

#[test]
fn too_many_form_terms_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| {
        let term = serde_json::json!({"kind": "offset", "mm": 0.0});
        v["as_machined"] = serde_json::json!({ "form": vec![term; 1001] });
    });
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(&o, &["p.json", "$.as_machined.form", "at most 1000"]);
}

#[test]
fn counts_beyond_their_bounds_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = s(&dir.path().join("out"));
    let sphere = prog("sphere.json");
    let o = cmm(&[
        "scan",
        &sphere,
        "--variants",
        "18446744073709551615",
        "--out",
        &out,
    ]);
    assert_bad_input(&o, &["--variants", "at most 100000 parts"]);
    let o = cmm(&["scan", &sphere, "--jobs", "100000", "--out", &out]);
    assert_bad_input(&o, &["--jobs 100000", "1 to 256"]);
    let o = cmm(&["scan", &sphere, "--jobs", "0", "--out", &out]);
    assert_bad_input(&o, &["--jobs 0"]);
    assert!(!dir.path().join("out").exists());
    let urdf = s(&repo("part-programs/machines/bridge-ab-head.urdf"));
    let o = cmm(&[
        "calibrate-probe",
        "--machine",
        &urdf,
        "--head-angles",
        "0,0;90,0",
        "--orientation-points",
        "1000000",
        "--out",
        &s(&dir.path().join("c.json")),
    ]);
    assert_bad_input(&o, &["--orientation-points 1000000", "1000"]);
}

#[test]
fn a_report_set_is_written_whole_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("junit.xml")).unwrap();
    let o = cmm(&["scan", &prog("sphere.json"), "--ideal", "--out", &s(&out)]);
    assert_bad_input(&o, &["junit.xml", "is a folder"]);
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["junit.xml"]);
}

#[test]
fn every_output_path_is_checked_before_measuring() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (option, file) in [
        ("--corrections", "nodir/c.json"),
        ("--trace", "nodir/t.csv"),
    ] {
        let target = s(&dir.path().join(file));
        let o = cmm(&[
            "scan",
            &prog("sphere.json"),
            "--ideal",
            "--out",
            &s(&out),
            option,
            &target,
        ]);
        assert_bad_input(&o, &[file, "does not exist"]);
        assert!(!out.exists(), "{option}: the reports were written");
    }
    let o = cmm(&[
        "calibrate-probe",
        "--ideal",
        "--out",
        &s(&dir.path().join("nodir/c.json")),
    ]);
    assert_bad_input(&o, &["nodir/c.json", "does not exist"]);
}

#[test]
fn out_dot_writes_into_the_current_folder() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(["scan", &prog("sphere.json"), "--ideal", "--out", "."])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(dir.path().join("report.json").is_file());
}

#[test]
fn invalid_utf8_names_file_line_and_column_once() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("p.json");
    std::fs::write(
        &p,
        b"{\n  \"format\": \"cmm-program/1\",\n  \"name\": \"a\xFFb\"\n}\n",
    )
    .unwrap();
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(&o, &["p.json", "line 3, column 13", "invalid UTF-8"]);
    assert_eq!(stderr(&o).matches("UTF-8").count(), 2, "{}", stderr(&o));
    let csv = dir.path().join("pts.csv");
    std::fs::write(&csv, b"x,y,z\n1,2,3\n\xC3(,1,1\n").unwrap();
    let o = cmm(&["fit", "--element", "plane", &s(&csv)]);
    assert_bad_input(&o, &["pts.csv", "line 3, column 1", "invalid UTF-8"]);
}

#[test]
fn os_errors_are_printed_once() {
    let o = cmm(&["check", "no-such-program.json"]);
    assert_bad_input(&o, &["no-such-program.json"]);
    let err = stderr(&o);
    assert_eq!(err.matches("os error").count(), 1, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn a_workpiece_that_is_a_folder_or_a_fifo_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| v["workpiece"] = "wp".into());
    std::fs::create_dir(dir.path().join("wp")).unwrap();
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(&o, &["p.json", "$.workpiece", "is a folder"]);
    std::fs::remove_dir(dir.path().join("wp")).unwrap();
    let made = Command::new("mkfifo").arg(dir.path().join("wp")).status();
    if made.is_ok_and(|s| s.success()) {
        let o = cmm(&["check", &s(&p)]);
        assert_bad_input(&o, &["p.json", "$.workpiece", "is a FIFO"]);
    }
}

#[test]
fn fit_errors_name_the_point_file() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("three.csv");
    std::fs::write(&csv, "x,y,z\n0,0,0\n1,0,0\n0,1,0\n").unwrap();
    let o = cmm(&["fit", "--element", "sphere", &s(&csv)]);
    assert_bad_input(&o, &["three.csv: "]);
    let o = cmm(&[
        "fit",
        "--element",
        "plane",
        &s(&csv),
        "--probe-radius=-1",
        "--side",
        "inside",
    ]);
    assert_bad_input(&o, &["--probe-radius -1"]);
}

#[test]
fn point_csvs_as_cmms_write_them() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("cmm.csv");
    // BOM, comments, quoted upper-case names, `;` and decimal commas.
    let text = "\u{feff}# exported by a CMM\n\"Id\";\"X\";\"Y\";\"Z\"\n\"p1\";0;0;0\n# a comment\n\"p2\";10,5;0;0\n\n\"p3\";0;10;0\n\"p4\";10;10;0\n";
    std::fs::write(&csv, text).unwrap();
    let o = cmm(&["fit", "--element", "plane", &s(&csv), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["point_count"], 4);
    assert!(v["form_mm"].as_f64().unwrap().abs() < 1e-9);
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "X,Y,Z\n1,2,3\n\"4\",five,6\n").unwrap();
    let o = cmm(&["fit", "--element", "plane", &s(&bad)]);
    assert_bad_input(&o, &["bad.csv:3:", "column 'y' is not a number: 'five'"]);
}

#[test]
fn calibration_numbers_are_checked_for_meaning() {
    let dir = tempfile::tempdir().unwrap();
    let out = s(&dir.path().join("c.json"));
    for (option, value) in [
        ("--probe-tip-diameter", "0"),
        ("--sphere-diameter", "1e-9"),
        ("--stylus-length", "-5"),
        ("--deflections", "0,0.2"),
    ] {
        let o = cmm(&[
            "calibrate-probe",
            &format!("{option}={value}"),
            "--out",
            &out,
        ]);
        assert_bad_input(&o, &[&format!("{option} ")]);
    }
    assert!(!dir.path().join("c.json").exists());
}

#[test]
fn a_profile_with_a_meaningless_control_cycle_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for cycle in ["10", "1e-320"] {
        let path = dir.path().join("profile.json");
        let text =
            format!("{{\"format\": \"cmm-machine-profile/1\", \"control_cycle_s\": {cycle}}}");
        std::fs::write(&path, text).unwrap();
        let o = cmm(&[
            "calibrate-probe",
            "--machine-profile",
            &s(&path),
            "--out",
            &s(&dir.path().join("c.json")),
        ]);
        assert_bad_input(&o, &["profile.json", "$.control_cycle_s", "within"]);
    }
}

#[test]
fn a_feature_that_measures_no_point_is_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| {
        v["features"] = serde_json::json!([{
            "name": "top", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 12.4999999], "normal": [0, 0, 1] },
            "tolerance_mm": [-0.01, 0.01]
        }]);
    });
    let out = dir.path().join("out");
    let o = cmm(&["scan", &s(&p), "--ideal", "--out", &s(&out)]);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let feature = &report["features"][0];
    if feature["points"].as_array().is_some_and(|p| p.is_empty()) {
        assert_eq!(feature["status"], "incomplete");
        assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    } else {
        assert_ne!(feature["status"], "pass", "no point measured yet passed");
    }
}

#[test]
fn a_start_beyond_the_travel_is_bad_input_for_check_and_scan() {
    let dir = tempfile::tempdir().unwrap();
    let p = sphere_program(dir.path(), |v| {
        v["probe"]["stylus_length_mm"] = 480.into();
    });
    let o = cmm(&["check", &s(&p)]);
    assert_bad_input(&o, &["p.json", "$.placement", "stylus"]);
    let out = dir.path().join("out");
    let o = cmm(&["scan", &s(&p), "--out", &s(&out)]);
    assert_bad_input(&o, &["p.json", "$.placement"]);
    assert!(!out.exists());
}

#[test]
fn a_failed_calibration_names_its_machine_and_probe() {
    let dir = tempfile::tempdir().unwrap();
    let out = s(&dir.path().join("c.json"));
    let head = s(&repo("part-programs/machines/bridge-ab-head.urdf"));
    let o = cmm(&["calibrate-probe", "--machine", &head, "--out", &out]);
    assert_bad_input(
        &o,
        &["bridge-ab-head.urdf", "probe-head joints", "--head-angles"],
    );
    let o = cmm(&["calibrate-probe", "--stylus-length", "500", "--out", &out]);
    assert_bad_input(&o, &["built-in bridge CMM", "stylus 500 mm", "travel"]);
    assert!(!dir.path().join("c.json").exists());
}

#[test]
fn an_interrupt_leaves_no_output_behind() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args([
            "scan",
            &prog("sphere.json"),
            "--variants",
            "500",
            "--out",
            &s(&out),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    if !sent.is_ok_and(|s| s.success()) {
        let _ = child.kill();
        let _ = child.wait();
        return;
    }
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(stderr(&o).contains("interrupted"));
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// A file holds one JSON value: a second object after the program (two
/// files run together) or a stray brace is bad input, with its place,
/// and nothing is measured or written.
#[test]
fn text_after_the_program_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo("part-programs/sphere.json")).unwrap();
    let workpiece = s(&repo("workpieces/sphere.json"));
    let text = text.replace("../workpieces/sphere.json", &workpiece);
    for (k, tail) in ["\n{}\n", "}", " 42"].iter().enumerate() {
        let path = dir.path().join(format!("p{k}.json"));
        std::fs::write(&path, format!("{text}{tail}")).unwrap();
        let out = dir.path().join(format!("out{k}"));
        let o = cmm(&["scan", &s(&path), "--quiet", "--out", &s(&out)]);
        assert_bad_input(&o, &[&s(&path), "trailing characters"]);
        assert!(!out.exists(), "{tail:?}");
    }
}

/// A program's scan defaults are checked whatever features it holds: a
/// 5 mm default deflection (the range is (0, 1] mm) is bad input in a
/// program of touch points too.
#[test]
fn bad_scan_defaults_are_bad_input_in_a_touch_only_program() {
    let dir = tempfile::tempdir().unwrap();
    let path = sphere_program(dir.path(), |v| {
        v["defaults"]["deflection_mm"] = 5.0.into();
        v["features"] = serde_json::json!([ { "name": "pole", "type": "touch_points",
            "points_mm": [[0.0, 0.0, 12.5]], "tolerance_mm": [-0.05, 0.05] } ]);
    });
    let out = dir.path().join("out");
    let o = cmm(&["scan", &s(&path), "--quiet", "--out", &s(&out)]);
    assert_bad_input(&o, &[&s(&path), "$.defaults.deflection_mm", "(0, 1]"]);
    assert!(!out.exists());
}
