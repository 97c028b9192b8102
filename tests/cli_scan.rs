//! `cmm scan` as users and CI scripts run it: files, exit codes, batches,
//! determinism and learned corrections.
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

fn prog(name: &str) -> String {
    repo(&format!("part-programs/{name}"))
        .to_string_lossy()
        .into_owned()
}

fn report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

fn strip_wall(mut v: Value) -> Value {
    v["wall_time_s"] = Value::Null;
    v
}

#[test]
fn exit_codes_follow_the_contract() {
    let out = tempfile::tempdir().unwrap();
    let d = |s: &str| out.path().join(s).to_string_lossy().into_owned();
    assert_eq!(
        cmm(&[
            "scan",
            &prog("blade-gouge.json"),
            "--out",
            &d("a"),
            "--ideal"
        ])
        .status
        .code(),
        Some(0)
    );
    assert_eq!(
        cmm(&[
            "scan",
            &prog("blade-overcut.json"),
            "--out",
            &d("b"),
            "--ideal"
        ])
        .status
        .code(),
        Some(1)
    );
    // Active-only scan of a 2.5 mm overcut cannot complete: exit 3.
    let text = std::fs::read_to_string(prog("blade-overcut.json"))
        .unwrap()
        .replace("\"auto\"", "\"active\"")
        .replace("../workpieces", &repo("workpieces").to_string_lossy());
    let p = out.path().join("active.json");
    std::fs::write(&p, text).unwrap();
    let o = cmm(&["scan", p.to_str().unwrap(), "--out", &d("c"), "--ideal"]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(report(&out.path().join("c"))["status"], "incomplete");
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let out = tempfile::tempdir().unwrap();
    let bad = out.path().join("bad.json");
    std::fs::write(&bad, "{\"format\": \"cmm-program/1\"}").unwrap();
    let target = out.path().join("never");
    let o = cmm(&[
        "scan",
        &prog("blade-z60.json"),
        bad.to_str().unwrap(),
        "--out",
        target.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("bad.json"));
    assert!(!target.exists(), "nothing written when any input is bad");
}

#[test]
fn report_json_has_every_contract_key() {
    let out = tempfile::tempdir().unwrap();
    assert_eq!(
        cmm(&[
            "scan",
            &prog("blade-gouge.json"),
            "--out",
            out.path().to_str().unwrap()
        ])
        .status
        .code(),
        Some(0)
    );
    let r = report(out.path());
    for key in [
        "format",
        "program",
        "seed",
        "status",
        "machine_time_s",
        "wall_time_s",
        "part_to_machine",
        "features",
    ] {
        assert!(r.get(key).is_some(), "missing {key}");
    }
    assert_eq!(r["format"], "cmm-report/1");
    assert_eq!(
        r["part_to_machine"]["translation_mm"],
        serde_json::json!([350.0, 500.0, 150.0])
    );
    let f = &r["features"][0];
    for key in [
        "name",
        "status",
        "attempts",
        "corrections",
        "deviation_mm",
        "tolerance_mm",
        "points",
    ] {
        assert!(f.get(key).is_some(), "missing features[].{key}");
    }
    for key in ["mode", "outcome", "machine_time_s"] {
        assert!(
            f["attempts"][0].get(key).is_some(),
            "missing attempts[].{key}"
        );
    }
    for key in [
        "measured",
        "nominal",
        "normal",
        "deviation_mm",
        "true_deviation_mm",
    ] {
        assert!(f["points"][0].get(key).is_some(), "missing points[].{key}");
    }
    let kinds: Vec<&str> = f["corrections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["kind"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"autonomous"), "{kinds:?}");
    // Machine time is far more than wall time (the simulator runs faster than real time).
    assert!(r["machine_time_s"].as_f64().unwrap() > 10.0 * r["wall_time_s"].as_f64().unwrap());
}

#[test]
fn same_seed_same_reports_and_jobs_do_not_change_them() {
    let out = tempfile::tempdir().unwrap();
    let run = |dir: &str, jobs: &str, seed: &str| {
        let d = out.path().join(dir);
        let o = cmm(&[
            "scan",
            &prog("blade-z60.json"),
            &prog("bore-circles.json"),
            "--variants",
            "2",
            "--jobs",
            jobs,
            "--seed",
            seed,
            "--out",
            d.to_str().unwrap(),
        ]);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        d
    };
    let (a, b, c) = (run("a", "1", "5"), run("b", "2", "5"), run("c", "1", "6"));
    let parts = [
        "00-blade-z60-v000",
        "00-blade-z60-v001",
        "01-bore-circles-v000",
        "01-bore-circles-v001",
    ];
    for p in parts {
        assert_eq!(
            strip_wall(report(&a.join(p))),
            strip_wall(report(&b.join(p))),
            "{p}"
        );
        assert_ne!(
            strip_wall(report(&a.join(p))),
            strip_wall(report(&c.join(p))),
            "{p}"
        );
    }
    let batch: Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("batch.json")).unwrap()).unwrap();
    assert_eq!(batch["parts"].as_array().unwrap().len(), 4);
}

#[test]
fn a_second_part_uses_the_learned_correction() {
    let out = tempfile::tempdir().unwrap();
    let corr = out.path().join("corrections.json");
    let run = |dir: &str| {
        let d = out.path().join(dir);
        cmm(&[
            "scan",
            &prog("blade-overcut.json"),
            "--ideal",
            "--corrections",
            corr.to_str().unwrap(),
            "--out",
            d.to_str().unwrap(),
        ]);
        report(&d)
    };
    let first = run("first");
    assert_eq!(
        first["features"][0]["attempts"][0]["outcome"],
        "trajectory_error"
    );
    assert!(corr.exists());
    let second = run("second");
    let attempts = second["features"][0]["attempts"].as_array().unwrap();
    assert_eq!(attempts.len(), 1, "{attempts:?}");
    assert_eq!(attempts[0]["outcome"], "completed");
    assert_eq!(second["features"][0]["corrections"][0]["source"], "learned");
}

#[test]
fn as_machined_override_and_quiet_stderr() {
    let out = tempfile::tempdir().unwrap();
    let am = out.path().join("am.json");
    std::fs::write(&am, r#"{"form":[{"kind":"offset","mm":2.5}]}"#).unwrap();
    let d = out.path().join("r");
    let o = cmm(&[
        "scan",
        &prog("blade-z60.json"),
        "--ideal",
        "--as-machined",
        am.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "2.5 mm overcut is out of tolerance"
    );
    assert!(
        o.stderr.is_empty(),
        "no progress output when stderr is not a terminal"
    );
    assert_eq!(
        report(&d)["features"][0]["attempts"][0]["outcome"],
        "trajectory_error"
    );
    std::fs::write(
        &am,
        r#"{"form":[{"kind":"offset","mm":1,"surfaces":["hub"]}]}"#,
    )
    .unwrap();
    let d2 = out.path().join("r2");
    let o = cmm(&[
        "scan",
        &prog("blade-z60.json"),
        "--as-machined",
        am.to_str().unwrap(),
        "--out",
        d2.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("am.json") && err.contains("$.form[0].surfaces[0]"),
        "{err}"
    );
    assert!(!d2.exists());
}

/// Columns of a trace CSV as numbers (empty cells as NaN).
fn trace_rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("t_s,x_mm,y_mm,z_mm,vx_cmd"));
    lines
        .map(|l| {
            l.split(',')
                .map(|c| c.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

#[test]
fn trace_shows_scanning_speeds_and_no_axis_beyond_its_limits() {
    let out = tempfile::tempdir().unwrap();
    let (csv, d) = (out.path().join("trace.csv"), out.path().join("r"));
    let o = cmm(&[
        "scan",
        &prog("blade-gouge.json"),
        "--ideal",
        "--trace",
        csv.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0));
    let rows = trace_rows(&csv);
    let speed = |r: &Vec<f64>| (r[7] * r[7] + r[8] * r[8] + r[9] * r[9]).sqrt();
    // Bridge CMM defaults: 500 mm/s per axis (rapids run at 400), 2000 mm/s^2.
    for w in rows.windows(2) {
        let dt = w[1][0] - w[0][0];
        for k in 7..10 {
            assert!(w[1][k].abs() <= 500.0 + 1e-6);
            assert!(
                ((w[1][k] - w[0][k]) / dt).abs() <= 2000.0 * (1.0 + 1e-6),
                "acceleration at t = {}",
                w[1][0]
            );
        }
    }
    // Active scanning (dL recorded) cruises at the programmed 80 mm/s.
    let mut active: Vec<f64> = rows
        .iter()
        .filter(|r| r[13].is_finite())
        .map(speed)
        .collect();
    active.sort_by(f64::total_cmp);
    let median = active[active.len() / 2];
    assert!(
        (50.0..=100.0).contains(&median),
        "design-value scanning at {median} mm/s"
    );
    // The autonomous attempt: its time window from the report.
    let r = report(&d);
    let attempts = r["features"][0]["attempts"].as_array().unwrap();
    let t_before: f64 = attempts
        .iter()
        .take_while(|a| a["mode"] != "autonomous")
        .map(|a| a["machine_time_s"].as_f64().unwrap())
        .sum();
    let t_auto = attempts.iter().find(|a| a["mode"] == "autonomous").unwrap()["machine_time_s"]
        .as_f64()
        .unwrap();
    let mut auto: Vec<f64> = rows
        .iter()
        .filter(|x| {
            x[0] > t_before
                && x[0] < t_before + t_auto
                && (x[10] * x[10] + x[11] * x[11] + x[12] * x[12]).sqrt() > 0.1
        })
        .map(speed)
        .collect();
    auto.sort_by(f64::total_cmp);
    let median = auto[auto.len() / 2];
    assert!(
        (10.0..=15.0).contains(&median),
        "autonomous scanning at {median} mm/s"
    );
}

/// A batch's parts share the loading of their program: only the first part
/// counts it in its `wall_time_s`, so the parts' times add up to no more
/// than the whole run, timed around the command (the STEP part loads in
/// about as long as a part runs).
#[test]
fn a_batchs_wall_times_add_up_to_its_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let started = std::time::Instant::now();
    let o = cmm(&[
        "scan",
        &prog("io1-flange.json"),
        "--variants",
        "4",
        "--jobs",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let run = started.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let batch: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("batch.json")).unwrap()).unwrap();
    let parts = batch["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 4);
    let sum: f64 = parts
        .iter()
        .map(|p| p["wall_time_s"].as_f64().unwrap())
        .sum();
    assert!(sum <= run, "parts {sum} s, run {run} s");
}
