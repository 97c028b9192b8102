//! The example programs on real CAD parts (NIST CTC 05, the ABC lamp),
//! run as a CMM programmer would: `cmm check`, then `cmm scan --ideal`
//! with a motion trace. References are independent of the measuring code:
//! the true surface (`true_deviation_mm`, the world's own distance), the
//! section lengths `cmm check` prints, and the part's geometry as drawn in
//! its STEP file (a tube of radius 152.4 mm whose bore of radius 127 mm is
//! a cavity open only at the bottom).
mod common;

use std::process::{Command, Output};

use common::repo;
use serde_json::Value;

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

fn scan_ideal(program: &str, dir: &std::path::Path) -> (Value, String) {
    scan_ideal_ending(&repo(program), dir, 0)
}

/// `cmm scan PROGRAM --ideal --trace` into `dir/out` (trace `dir/trace.csv`),
/// which must end with exit code `code`: the report and the trace.
fn scan_ideal_ending(
    program: &std::path::Path,
    dir: &std::path::Path,
    code: i32,
) -> (Value, String) {
    let (out, trace) = (dir.join("out"), dir.join("trace.csv"));
    let run = cmm(&[
        "scan",
        s(program),
        "--ideal",
        "--quiet",
        "--out",
        s(&out),
        "--trace",
        s(&trace),
    ]);
    assert_eq!(run.status.code(), Some(code), "{run:?}");
    let trace = std::fs::read_to_string(trace).unwrap();
    (read_report(&out), trace)
}

/// The `report.json` in `out`.
fn read_report(out: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap()
}

/// Every cycle of the trace in the phase `position` reads no deflection:
/// the probe touched nothing while positioning (over 1000 cycles of it).
fn positioning_touches_nothing(trace: &str) {
    positioning_touches_nothing_over(trace, 1000);
}

/// [`positioning_touches_nothing`] over more than `cycles` positioning
/// cycles.
fn positioning_touches_nothing_over(trace: &str, cycles: usize) {
    phase_touches_nothing(trace, "position", cycles);
}

/// Every cycle of the trace in `phase` (more than `cycles` of them) reads
/// no deflection.
fn phase_touches_nothing(trace: &str, wanted: &str, cycles: usize) {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (phase, dx, dy, dz) = (col("phase"), col("dx_mm"), col("dy_mm"), col("dz_mm"));
    let mut seen = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        if f[phase] != wanted {
            continue;
        }
        seen += 1;
        for k in [dx, dy, dz] {
            assert_eq!(f[k].parse::<f64>().unwrap(), 0.0, "{line}");
        }
    }
    assert!(seen > cycles, "{seen} {wanted} cycles");
}

/// The program's end move completed and left the probe touching nothing,
/// at rest (under 1 mm/s), no lower than where the program started it
/// (above the part): the last feature of the program is a scan, which
/// ends with the stylus pressed on the part.
fn ends_clear_and_at_rest_above_the_start(report: &Value, trace: &str) {
    assert_eq!(
        report["end_move"]["outcome"], "completed",
        "{}",
        report["end_move"]
    );
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let num = |row: &[&str], name: &str| row[col(name)].parse::<f64>().unwrap();
    let (first, last) = (rows.first().unwrap(), rows.last().unwrap());
    for k in ["dx_mm", "dy_mm", "dz_mm"] {
        assert_eq!(num(last, k), 0.0, "{last:?}");
    }
    let speed = ["vx", "vy", "vz"]
        .map(|k| num(last, k))
        .iter()
        .map(|v| v * v)
        .sum::<f64>();
    assert!(speed.sqrt() < 1.0, "{last:?}");
    assert!(
        num(last, "z_mm") >= num(first, "z_mm") - 0.05,
        "{first:?} {last:?}"
    );
    let scanned = rows
        .iter()
        .rev()
        .find(|r| r[col("phase")] == "scan")
        .unwrap();
    assert!(
        num(scanned, "z_mm") < num(last, "z_mm") - 10.0,
        "{scanned:?}"
    );
}

/// With `--ideal` every point's deviation is its true deviation (0.5 um),
/// and each scanned section is covered at its pitch: points 0.5 mm apart
/// on average (within 3 %), at least 97 % of its length over the pitch.
fn exact_and_covered(report: &Value, lengths_mm: &[(&str, f64)]) {
    for f in report["features"].as_array().unwrap() {
        assert_eq!(f["status"], "pass", "{}", f["name"]);
        for p in f["points"].as_array().unwrap() {
            let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
            assert!(e.abs() <= 5e-4, "{}: {e} mm", f["name"]);
        }
    }
    for &(name, length) in lengths_mm {
        let f = (report["features"].as_array().unwrap().iter())
            .find(|f| f["name"] == name)
            .unwrap();
        let points = f["points"].as_array().unwrap();
        let n = points.len() as f64;
        assert!(
            n >= 0.97 * length / 0.5,
            "{name}: {n} points over {length} mm"
        );
        let at = |p: &Value| -> Vec<f64> {
            (p["measured"].as_array().unwrap().iter())
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        let gaps: Vec<f64> = (points.windows(2))
            .map(|w| {
                let (a, b) = (at(&w[0]), at(&w[1]));
                (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
            })
            .filter(|g| *g < 2.0)
            .collect();
        let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
        assert!(
            (mean - 0.5).abs() <= 0.015,
            "{name}: mean spacing {mean} mm"
        );
    }
}

#[test]
fn nist_ctc05_program_measures_every_feature_exactly() {
    let check = cmm(&["check", s(&repo("part-programs/nist-ctc05.json"))]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let out = tempfile::tempdir().unwrap();
    let (report, trace) = scan_ideal("part-programs/nist-ctc05.json", out.path());
    // Section lengths: 2 pi 152.4 (the tube), 2 pi 31.75 (the column).
    let tube = std::f64::consts::TAU * 152.4;
    let column = std::f64::consts::TAU * 31.75;
    exact_and_covered(
        &report,
        &[
            ("tube-z100", tube),
            ("tube-z75", tube),
            ("column-z400", column),
        ],
    );
    positioning_touches_nothing(&trace);
    approaches_touch_nothing(&trace);
}

/// A turned flange (`workpieces/io1-flange.stp`, STEPcode's AP214 test
/// part) with its axis up: the outside, the bore, the boss, a bolt hole of
/// radius 3.5 mm (the approach starts inside it, not the standoff out in
/// its far wall, and the probe leaves it without blending the turn) and
/// the tops by touch points.
#[test]
fn io1_flange_program_measures_every_feature_exactly() {
    let check = cmm(&["check", s(&repo("part-programs/io1-flange.json"))]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let out = tempfile::tempdir().unwrap();
    let (report, trace) = scan_ideal("part-programs/io1-flange.json", out.path());
    let tau = std::f64::consts::TAU;
    exact_and_covered(
        &report,
        &[
            ("flange-od", tau * 44.0),
            ("bore", tau * 18.0),
            ("boss", tau * 31.0),
            ("bolt-hole-30", tau * 3.5),
        ],
    );
    positioning_touches_nothing(&trace);
    retracts_touch_nothing(&trace);
    approaches_touch_nothing(&trace);
}

/// Every cycle of the trace in the phase `approach` reads no deflection:
/// the cycles on the surface, while the stylus presses to the scan's
/// deflection, belong to the scan.
fn approaches_touch_nothing(trace: &str) {
    phase_touches_nothing(trace, "approach", 100);
}

/// Every cycle of the trace in the phase `retract` reads no deflection:
/// a touch's stop on the surface and its lift off it belong to the touch
/// (and a scan's to the scan), the retract is the move away in free air.
fn retracts_touch_nothing(trace: &str) {
    phase_touches_nothing(trace, "retract", 100);
}

/// The flange's groove (2 mm wide between two shoulders, the section
/// plane in its middle) is narrower than the 3 mm ball: `cmm check` says
/// so and `cmm scan` does not measure it (the walls are faces the section
/// plane does not cut), instead of scanning the shoulder beside it.
#[test]
fn a_groove_narrower_than_the_ball_is_not_measured() {
    let dir = tempfile::tempdir().unwrap();
    let mut prog: Value = serde_json::from_str(
        &std::fs::read_to_string(repo("part-programs/io1-flange.json")).unwrap(),
    )
    .unwrap();
    prog["workpiece"] = Value::from(s(&repo("workpieces/io1-flange.stp")));
    prog["features"] = serde_json::json!([
        { "name": "groove", "type": "section_scan",
          "plane": { "origin_mm": [20, 0, 0], "normal": [1, 0, 0] },
          "surfaces": ["face7", "face21"], "tolerance_mm": [-0.05, 0.05] },
        { "name": "boss", "type": "section_scan",
          "plane": { "origin_mm": [25, 0, 0], "normal": [1, 0, 0] },
          "surfaces": ["face5", "face27"], "tolerance_mm": [-0.05, 0.05] } ]);
    let file = dir.path().join("groove.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let check = cmm(&["check", s(&file)]);
    assert_eq!(check.status.code(), Some(3), "{check:?}");
    let said = String::from_utf8_lossy(&check.stdout).into_owned()
        + &String::from_utf8_lossy(&check.stderr);
    assert!(
        said.contains("groove [0]: not reachable: narrower than the ball"),
        "{said}"
    );
    assert!(!said.contains("boss [0]"), "{said}");
    let out = dir.path().join("out");
    let run = cmm(&["scan", s(&file), "--ideal", "--quiet", "--out", s(&out)]);
    assert_eq!(run.status.code(), Some(3), "{run:?}");
    let report = read_report(&out);
    let (groove, boss) = (&report["features"][0], &report["features"][1]);
    assert_eq!(groove["status"], "incomplete");
    assert_eq!(groove["points"].as_array().unwrap().len(), 0);
    assert_eq!(boss["status"], "pass");
}

/// A touch point on the flange's face beside the boss with a 5 mm ball:
/// the route comes out over the face and then straight down beside the
/// boss (4.5 mm clear of it). The positioning move follows that route, so
/// the ball touches nothing on the way and the point is measured (a move
/// that swung round its corner ran the ball into the boss at 27 mm/s).
#[test]
fn a_touch_point_beside_the_boss_is_reached_without_touching_it() {
    let dir = tempfile::tempdir().unwrap();
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "beside-boss",
        "workpiece": s(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 5.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "flange-top", "type": "touch_points", "points_mm": [[6, 38, 0]],
              "surfaces": ["face10"], "tolerance_mm": [-0.05, 0.05] } ] });
    let file = dir.path().join("beside.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let (report, trace) = scan_ideal_ending(&file, dir.path(), 0);
    let f = &report["features"][0];
    assert_eq!(f["status"], "pass", "{f}");
    assert_eq!(f["points"].as_array().unwrap().len(), 1);
    positioning_touches_nothing_over(&trace, 100);
}

/// The flange's shaft between its flange and its groove, lying on its
/// side, cut at 10 mm above its axis: two straight lines, each from the
/// groove's edge (convex) into the corner at the flange's face (concave,
/// where the ball ends 0.4 mm from the face). One line runs into the
/// corner and the other out of it: that one is scanned from its other end
/// (its start in the corner has no clear route), and from the corner where
/// the first line's scan ends the probe leaves by a short escape leg
/// before it goes on to the next line and to the touch points on the
/// boss's end face. Everything is measured, positioning touches nothing.
#[test]
fn lines_into_a_concave_corner_are_scanned_and_left_without_touching() {
    let dir = tempfile::tempdir().unwrap();
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "corner",
        "workpiece": s(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 4.0, "stylus_length_mm": 150 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "shaft-lines", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 10], "normal": [0, 0, 1] },
              "surfaces": ["face19"], "tolerance_mm": [-0.05, 0.05] },
            { "name": "boss-end", "type": "touch_points",
              "points_mm": [[31, 0, 20], [31, 15, -10], [31, -15, -10]],
              "surfaces": ["face4"], "tolerance_mm": [-0.05, 0.05] } ] });
    let file = dir.path().join("corner.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let check = cmm(&["check", s(&file)]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let (report, trace) = scan_ideal_ending(&file, dir.path(), 0);
    let (lines, touches) = (&report["features"][0], &report["features"][1]);
    assert_eq!(lines["status"], "pass", "{lines}");
    assert_eq!(touches["status"], "pass", "{touches}");
    assert_eq!(touches["points"].as_array().unwrap().len(), 3);
    // Each line is 13 mm long less the ball's radius in the corner: some
    // 22 points at the 0.5 mm pitch on each.
    assert!(lines["points"].as_array().unwrap().len() >= 40, "{lines}");
    positioning_touches_nothing(&trace);
}

/// The flange lying on its side, its whole outside diameter (88 mm) as
/// one section: a vertical stylus reaches its upper half (and a little
/// below the axis, until the shaft meets the flange's rim). `cmm check`
/// says the shaft would strike; the scan starts at one end of the reachable
/// arc, measures all of it, and the machine's collision stop ends it where
/// the shaft meets the rim: the attempt reports the `collision`, the
/// feature stays incomplete and keeps the arc it measured (at least half
/// the circumference at the pitch), every point on the true surface.
#[test]
fn a_circle_half_out_of_reach_keeps_its_reachable_arc_and_reports_the_strike() {
    let dir = tempfile::tempdir().unwrap();
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "side-od",
        "workpiece": s(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 30] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "flange-od", "type": "section_scan",
              "plane": { "origin_mm": [3, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face1", "face20"], "tolerance_mm": [-0.05, 0.05] } ] });
    let file = dir.path().join("side.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let check = cmm(&["check", s(&file)]);
    assert_eq!(check.status.code(), Some(3), "{check:?}");
    assert!(String::from_utf8_lossy(&check.stdout).contains("shaft would strike"));
    let (report, _) = scan_ideal_ending(&file, dir.path(), 3);
    let f = &report["features"][0];
    assert_eq!(f["status"], "incomplete");
    let attempt = &f["attempts"][0];
    assert_eq!(attempt["outcome"], "collision", "{attempt}");
    assert_eq!(attempt["collision"]["probe_part"], "shaft");
    assert_eq!(attempt["collision"]["phase"], "scan");
    let points = f["points"].as_array().unwrap();
    let half_mm = std::f64::consts::PI * 88.0 / 2.0;
    assert!(points.len() as f64 * 0.5 >= half_mm, "{}", points.len());
    for p in points {
        let err = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
        assert!(err.abs() < 5e-4, "{p}");
    }
}

#[test]
fn abc_lamp_program_measures_every_feature_exactly() {
    let out = tempfile::tempdir().unwrap();
    let (report, trace) = scan_ideal("part-programs/abc-lamp.json", out.path());
    exact_and_covered(&report, &[]);
    positioning_touches_nothing(&trace);
    approaches_touch_nothing(&trace);
}

#[test]
fn a_bore_open_only_below_is_not_reachable_from_above() {
    // The CTC 05 section at z = 100 of every face: the tube's outside and
    // its bore, a cavity closed above (the tube's top at z = 127).
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("bore.json");
    let text = serde_json::json!({
        "format": "cmm-program/1", "name": "bore",
        "workpiece": s(&repo("workpieces/nist-ctc05.stp")),
        "placement": { "translate_mm": [400, 400, -60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "features": [ { "name": "z100", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 100], "normal": [0, 0, 1] },
            "tolerance_mm": [-0.1, 0.1] } ]
    });
    std::fs::write(&prog, text.to_string()).unwrap();
    let check = cmm(&["check", s(&prog)]);
    let stdout = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{stdout}");
    let unreachable: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains("not reachable"))
        .collect();
    assert_eq!(unreachable.len(), 1, "{stdout}");
    assert!(unreachable[0].contains("no route"), "{stdout}");
    // The scan measures the outside and leaves the bore unmeasured,
    // without touching the part while positioning.
    let (report, trace) = scan_ideal_ending(&prog, dir.path(), 3);
    let f = &report["features"][0];
    assert_eq!(f["status"], "incomplete");
    let notes = f["notes"].to_string();
    assert!(notes.contains("not measured: no route"), "{notes}");
    for p in f["points"].as_array().unwrap() {
        let m = &p["measured"];
        let r = m[0].as_f64().unwrap().hypot(m[1].as_f64().unwrap());
        assert!((r - 152.4).abs() < 0.01, "a point at r = {r}");
    }
    positioning_touches_nothing(&trace);
}

fn report_without_wall(dir: &std::path::Path) -> Value {
    let text = std::fs::read_to_string(dir.join("report.json")).unwrap();
    let mut r: Value = serde_json::from_str(&text).unwrap();
    r.as_object_mut().unwrap().remove("wall_time_s");
    r
}

/// A batch's later variants reuse what the earlier ones computed from the
/// design (free-space answers, the contact search's split of the faces);
/// their reports equal those of a process that runs them alone.
#[test]
fn batch_variants_equal_the_same_variants_run_alone() {
    let out = tempfile::tempdir().unwrap();
    let run = |dir: &str, extra: &[&str]| {
        let d = out.path().join(dir);
        let prog = repo("part-programs/abc-lamp.json");
        let mut args = vec!["scan", s(&prog), "--variants", "3", "--quiet"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", s(&d)]);
        let o = cmm(&args);
        assert_eq!(o.status.code(), Some(0), "{o:?}");
        d
    };
    let (batch, alone) = (
        run("batch", &["--jobs", "1"]),
        run("alone", &["--shard", "3/3"]),
    );
    let part = "00-abc-lamp-v002";
    let r = report_without_wall(&batch.join(part));
    // One part alone: its reports are written at the top of `--out`.
    assert_eq!(r, report_without_wall(&alone));
    assert_eq!(r["status"], "pass");
    // A traced part is the same part too (its variant, not the program's
    // own as-machined part).
    let trace = out.path().join("second.csv");
    let traced = run("traced", &["--shard", "2/3", "--trace", s(&trace)]);
    assert_eq!(
        report_without_wall(&batch.join("00-abc-lamp-v001")),
        report_without_wall(&traced)
    );
}

/// The fixture assembly (three placed brackets, 87 faces,
/// `workpieces/fixture-assembly.step`), as a programmer would try it: a section of one
/// bracket's boss steps at z = 25 (one stretch starts in the concave
/// corner beside the flange, too narrow to come down into) and touch points
/// on the boss and the flange. With `--ideal` every measured point is on
/// the true part, and no positioning cycle reads a deflection: each retract
/// off the surface ends with the stylus free.
#[test]
fn fixture_assembly_program_positions_clear_of_the_part() {
    let cad = repo("workpieces/fixture-assembly.step");
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("fixture.json");
    let faces =
        ["face5", "face9", "face7", "face27", "face19", "face21"].map(|f| format!("bracket#1/{f}"));
    let text = serde_json::json!({
        "format": "cmm-program/1", "name": "fixture",
        "workpiece": s(&cad),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.005 } ] },
        "features": [
            { "name": "b1-z25", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 25], "normal": [0, 0, 1] },
              "surfaces": faces, "tolerance_mm": [-0.05, 0.05] },
            { "name": "b1-boss-top", "type": "touch_points",
              "points_mm": [[25, 0, 31], [25, 8, 29.95], [25, -8, 29.95], [23, 0, 31]],
              "tolerance_mm": [-0.05, 0.05] },
            { "name": "flange-top", "type": "touch_points",
              "points_mm": [[3, 0, 44], [3, 6, 43.59]], "tolerance_mm": [-0.05, 0.05] } ]
    });
    std::fs::write(&prog, text.to_string()).unwrap();
    // The stretch in the corner is not measured: the section is incomplete.
    let (report, trace) = scan_ideal_ending(&prog, dir.path(), 3);
    let mut points = 0;
    for f in report["features"].as_array().unwrap() {
        for p in f["points"].as_array().unwrap() {
            let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
            assert!(e.abs() <= 5e-4, "{}: {e} mm", f["name"]);
            points += 1;
        }
    }
    assert!(points > 50, "{points} points");
    positioning_touches_nothing(&trace);
}

/// OpenCASCADE's link rods (`workpieces/linkrods.step`) with a 0.6 mm ball
/// on every face at z = 1: three closed curves. The ring's 1.03 mm bore
/// leaves the ball centre 0.22 mm of room, too little for the default
/// 1 mm tight margin: the bore is reported not reachable (not measured by
/// an approach from beyond the ring, through its wall), every attempt
/// ends in seconds, and no positioning move touches the part. With a
/// 0.1 mm tight margin the bore is measured, its scan completing.
#[test]
fn a_bore_too_small_for_the_margins_is_reported_not_driven_through() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("linkrods.json");
    let mut program = serde_json::json!({
        "format": "cmm-program/1", "name": "linkrods",
        "workpiece": s(&repo("workpieces/linkrods.step")),
        "placement": { "translate_mm": [300, 300, 50], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 0.6, "stylus_length_mm": 20 },
        "defaults": { "speed_mm_s": 20, "deflection_mm": 0.1, "pitch_mm": 0.1 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.002 } ] },
        "features": [ { "name": "z1", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 1.0], "normal": [0, 0, 1] },
            "tolerance_mm": [-0.02, 0.02] } ] });
    std::fs::write(&prog, program.to_string()).unwrap();
    let (report, trace) = scan_ideal_ending(&prog, dir.path(), 3);
    let f = &report["features"][0];
    let notes = f["notes"].to_string();
    assert!(notes.contains("not measured: no route"), "{notes}");
    assert!(notes.contains("narrower than the ball"), "{notes}");
    for a in f["attempts"].as_array().unwrap() {
        assert!(a["machine_time_s"].as_f64().unwrap() < 30.0, "{a}");
    }
    positioning_touches_nothing_over(&trace, 100);
    program["clearance"] = serde_json::json!({ "tight_margin_mm": 0.1 });
    std::fs::write(&prog, program.to_string()).unwrap();
    let other = tempfile::tempdir().unwrap();
    let (report, _) = scan_ideal_ending(&prog, other.path(), 3);
    let f = &report["features"][0];
    let notes = f["notes"].to_string();
    assert!(!notes.contains("no route"), "{notes}");
    let attempts = f["attempts"].as_array().unwrap();
    assert_eq!(attempts.len(), 2, "{attempts:?}");
    assert!(
        attempts.iter().all(|a| a["outcome"] == "completed"),
        "{attempts:?}"
    );
}

/// OpenCASCADE's linked rods (`workpieces/linkrods.step`, two rings about
/// 1.5 and 0.8 mm across joined by a rod, 2 mm high) with a 0.3 mm ball on
/// a 10 mm stylus and a 0.1 mm tight margin: the outside of both rings
/// and the 1.03 mm bore of one (2 pi 0.5172 mm at the 0.02 mm pitch)
/// measure exactly, and `cmm check` agrees (the shaft beside a
/// wall the ball touches keeps the ball radius less its own from it). With
/// the default 1 mm tight margin the bore has no room: `cmm check` and
/// `cmm scan` say so, and the probe is not driven through the ring to an
/// approach start beyond it.
#[test]
fn linkrods_program_measures_a_one_millimetre_bore_with_a_small_ball() {
    let program = repo("part-programs/linkrods.json");
    let check = cmm(&["check", s(&program)]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let dir = tempfile::tempdir().unwrap();
    let (report, trace) = scan_ideal_ending(&program, dir.path(), 0);
    for f in report["features"].as_array().unwrap() {
        assert_eq!(f["status"], "pass", "{}", f["name"]);
        for p in f["points"].as_array().unwrap() {
            let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
            assert!(e.abs() <= 5e-4, "{}: {e} mm", f["name"]);
        }
    }
    let bore = (report["features"].as_array().unwrap().iter())
        .find(|f| f["name"] == "ringA-bore")
        .unwrap();
    let n = bore["points"].as_array().unwrap().len() as f64;
    assert!(
        n >= 0.97 * std::f64::consts::TAU * 0.5172 / 0.02,
        "{n} points"
    );
    positioning_touches_nothing_over(&trace, 300);
    ends_clear_and_at_rest_above_the_start(&report, &trace);

    let mut p: Value = serde_json::from_str(&std::fs::read_to_string(&program).unwrap()).unwrap();
    p["workpiece"] = repo("workpieces/linkrods.step").to_string_lossy().into();
    p.as_object_mut().unwrap().remove("clearance");
    let roomless = common::write_program(dir.path(), "default-margins.json", &p);
    let check = cmm(&["check", s(&roomless)]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{check:?}");
    assert!(
        text.lines()
            .any(|l| l.contains("ringA-bore [0]: not reachable: no route")),
        "{text}"
    );
    let other = tempfile::tempdir().unwrap();
    let (report, trace) = scan_ideal_ending(&roomless, other.path(), 3);
    let statuses: Vec<_> = (report["features"].as_array().unwrap().iter())
        .map(|f| (f["name"].as_str().unwrap().to_string(), f["status"].clone()))
        .collect();
    for (name, status) in statuses {
        let expected = if name == "ringA-bore" {
            "incomplete"
        } else {
            "pass"
        };
        assert_eq!(status, expected, "{name}");
    }
    positioning_touches_nothing_over(&trace, 300);
}

/// The outside of the link rods' larger eye (radius 0.75 mm; an open arc
/// of 3.7 mm where the rod joins it) with a 1 mm ball at 60 mm/s and a
/// 0.05 mm pitch: the ball path's 1.25 mm radius turns faster than the
/// deflection loop follows, and the ball leaves the surface a third of
/// the way round. That is lost contact, not a completed scan with a third
/// of the points: the supervisor corrects, the autonomous scan measures
/// the arc, and the feature keeps its points (at least 90 % of the arc at
/// the pitch, every one on the true surface).
#[test]
fn a_scan_that_leaves_a_tight_arc_is_lost_contact_and_the_arc_is_measured() {
    let dir = tempfile::tempdir().unwrap();
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "eye",
        "workpiece": s(&repo("workpieces/linkrods.step")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 20 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.1, "pitch_mm": 0.05 },
        "features": [
            { "name": "eye-od", "type": "section_scan",
              "plane": { "origin_mm": [3.875, 3.25, 1], "normal": [0, 0, 1] },
              "surfaces": ["face7"], "tolerance_mm": [-0.05, 0.05] } ] });
    let file = dir.path().join("eye.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let check = cmm(&["check", s(&file)]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(text.contains("1 curve(s) (0 closed), 3.7 mm"), "{text}");
    let (report, _) = scan_ideal_ending(&file, dir.path(), 0);
    let f = &report["features"][0];
    assert_eq!(f["status"], "pass", "{f}");
    assert_eq!(f["attempts"][0]["outcome"], "lost_contact", "{f}");
    let points = f["points"].as_array().unwrap();
    assert!(points.len() as f64 >= 0.9 * 3.7 / 0.05, "{}", points.len());
    for p in points {
        let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
        assert!(e.abs() <= 5e-4, "{p}");
    }
}

/// The flange upright, the bottom of its groove (radius 29 mm, between
/// the flange and the 31 mm shoulder above it) cut at its middle, with a
/// 1 mm ball on a vertical 30 mm stylus: the ball centre would stand 1.5
/// mm inside the shoulder's radius, so the shaft would run down through
/// the shoulder. `cmm check` says so (a shaft check sampled every 2 mm,
/// each sample keeping its 0.35 mm, called it clear), and the scan ends
/// at the shaft's collision.
#[test]
fn a_groove_under_a_shoulder_is_a_shaft_strike_for_check_and_scan() {
    let dir = tempfile::tempdir().unwrap();
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "under",
        "workpiece": s(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 30 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 1.0 },
        "features": [
            { "name": "groove", "type": "section_scan",
              "plane": { "origin_mm": [20, 0, 0], "normal": [1, 0, 0] },
              "surfaces": ["face7", "face21"], "tolerance_mm": [-0.05, 0.05] } ] });
    let file = dir.path().join("under.json");
    std::fs::write(&file, prog.to_string()).unwrap();
    let check = cmm(&["check", s(&file)]);
    assert_eq!(check.status.code(), Some(3), "{check:?}");
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(
        text.contains("groove [0]: not reachable: the probe's shaft would strike"),
        "{text}"
    );
    let (report, _) = scan_ideal_ending(&file, dir.path(), 3);
    let f = &report["features"][0];
    assert_eq!(f["status"], "incomplete");
    assert_eq!(f["attempts"][0]["outcome"], "collision", "{f}");
    assert_eq!(f["attempts"][0]["collision"]["probe_part"], "shaft", "{f}");
}

/// The link rods' smaller bore (0.44 mm across, axis at (7.75, 3.125))
/// with a 0.3 mm ball and a 0.03 mm tight margin: the ball centre has
/// 0.07 mm of room round the axis, less than a sixteenth of the 5 mm
/// standoff, so the approach starts at a shorter one inside the bore (not
/// at a sixteenth, beyond the far wall, from where `cmm check` found no
/// route). The bore is measured: every point on the true surface, no
/// positioning move touching the part.
#[test]
fn a_bore_barely_wider_than_the_ball_is_approached_from_inside_it() {
    let dir = tempfile::tempdir().unwrap();
    let program = serde_json::json!({
        "format": "cmm-program/1", "name": "linkrods-small-bore",
        "workpiece": s(&repo("workpieces/linkrods.step")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 0.3, "stylus_length_mm": 10 },
        "defaults": { "speed_mm_s": 5, "deflection_mm": 0.05, "pitch_mm": 0.02 },
        "clearance": { "tight_margin_mm": 0.03, "margin_mm": 0.1 },
        "features": [ { "name": "small-bore", "type": "section_scan",
            "plane": { "origin_mm": [7.75, 3.125, 0.5], "normal": [0, 0, 1] },
            "surfaces": ["face12"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle" } } ] });
    let prog = common::write_program(dir.path(), "small-bore.json", &program);
    let check = cmm(&["check", s(&prog)]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let (report, trace) = scan_ideal_ending(&prog, dir.path(), 0);
    let f = &report["features"][0];
    let points = f["points"].as_array().unwrap();
    assert!(points.len() > 30, "{} points", points.len());
    for p in points {
        let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
        assert!(e.abs() <= 5e-4, "{e} mm");
    }
    let d = f["fit"]["measured"]["diameter_mm"].as_f64().unwrap();
    assert!((d - 0.44).abs() < 0.01, "diameter {d}");
    // The loop is closed all round at the pitch: the arc the scan goes
    // before its point settles in the plane is measured at the end.
    let covered = angular_coverage(points, (7.75, 3.125), 0.02 / 0.22);
    assert!(covered >= 0.9, "coverage {covered}");
    positioning_touches_nothing_over(&trace, 100);
}

/// The share of the full turn round the axis through `centre` (part x, y;
/// the axis along z) that the points cover, each gap between neighbours
/// wider than 1.5 pitches (`pitch_rad`, the pitch's angle) counting as
/// uncovered beyond that.
fn angular_coverage(points: &[serde_json::Value], centre: (f64, f64), pitch_rad: f64) -> f64 {
    let mut angles: Vec<f64> = points
        .iter()
        .map(|p| {
            let m = &p["measured"];
            let (x, y) = (m[0].as_f64().unwrap(), m[1].as_f64().unwrap());
            (y - centre.1).atan2(x - centre.0)
        })
        .collect();
    angles.sort_by(f64::total_cmp);
    let turn = std::f64::consts::TAU;
    let wrap = angles.first().unwrap() + turn - angles.last().unwrap();
    let gaps = angles.windows(2).map(|w| w[1] - w[0]).chain([wrap]);
    let missing: f64 = gaps.map(|g| (g - 1.5 * pitch_rad).max(0.0)).sum();
    1.0 - missing / turn
}

/// A blind hole of CTC 05 (radius 4.4 mm, 25 mm below the top of its
/// boss) with a 10 mm stylus: the probe body would stand in the part with
/// the ball at the scan's start, so `cmm check` and `cmm scan` say there
/// is no route to it and name the body, and nothing is driven into the
/// part.
#[test]
fn a_hole_deeper_than_the_stylus_names_the_body_in_the_way() {
    let dir = tempfile::tempdir().unwrap();
    let program = serde_json::json!({
        "format": "cmm-program/1", "name": "short-stylus",
        "workpiece": s(&repo("workpieces/nist-ctc05.stp")),
        "placement": { "translate_mm": [400, 400, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 10 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [ { "name": "deep-hole", "type": "section_scan",
            "plane": { "origin_mm": [203.2, 0, 25], "normal": [0, 0, 1] },
            "surfaces": ["face196", "face197"], "tolerance_mm": [-0.05, 0.05] } ] });
    let prog = common::write_program(dir.path(), "short-stylus.json", &program);
    let check = cmm(&["check", s(&prog)]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{check:?}");
    assert!(
        text.contains("no route") && text.contains("the probe's body would strike the part there"),
        "{text}"
    );
    let (report, _) = scan_ideal_ending(&prog, dir.path(), 3);
    let f = &report["features"][0];
    let notes = f["notes"].to_string();
    assert!(notes.contains("body would strike"), "{notes}");
    let attempts = f["attempts"].as_array().unwrap();
    assert!(
        attempts.iter().all(|a| a["outcome"] != "collision"),
        "{attempts:?}"
    );
}
