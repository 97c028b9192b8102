//! Backing out of a strike of the stylus shaft or the probe body during a
//! scan: away from where it struck, across the stylus (and off the
//! surface the ball is pressed on), and never on through the part.
mod common;

use std::path::Path;
use std::process::Command;

use common::repo;
use serde_json::Value;

/// Runs `program` (written to `dir`) with a trace; the report and the
/// trace's rows (phase, deflection in mm, machine z).
fn run(dir: &Path, program: &Value) -> (Value, Vec<(String, f64, f64)>) {
    let prog = common::write_program(dir, "p.json", program);
    let (out, trace) = (dir.join("out"), dir.join("trace.csv"));
    let run = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(["scan", prog.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .arg("--trace")
        .arg(&trace)
        .output()
        .unwrap();
    assert!(matches!(run.status.code(), Some(0..=3)), "{run:?}");
    let text = std::fs::read_to_string(out.join("report.json")).unwrap();
    let mut reader = csv::Reader::from_path(&trace).unwrap();
    let head = reader.headers().unwrap().clone();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let (phase, z, d) = (
        col("phase"),
        col("z_mm"),
        [col("dx_mm"), col("dy_mm"), col("dz_mm")],
    );
    let rows = (reader.records())
        .map(|r| {
            let r = r.unwrap();
            let num = |k: usize| r[k].parse::<f64>().unwrap_or(0.0);
            let defl = d.iter().map(|&k| num(k).powi(2)).sum::<f64>().sqrt();
            (r[phase].to_string(), defl, num(z))
        })
        .collect();
    (serde_json::from_str(&text).unwrap(), rows)
}

fn statuses(report: &Value) -> Vec<String> {
    let features = report["features"].as_array().unwrap();
    features
        .iter()
        .map(|f| f["status"].as_str().unwrap().to_string())
        .collect()
}

/// CTC 05's floor scanned along x = 40 beside its column (radius 31.75
/// mm) with a 50 mm stylus: the probe body (radius 12.5 mm) strikes the
/// column. Backing off the floor alone (up) dragged the body 24 mm up
/// the column, and every later feature struck at once; away from the
/// strike as well, the later features (the floor at x = -80, the column
/// above the body) complete and the end move is clear.
#[test]
fn a_body_that_strikes_a_column_backs_away_from_it() {
    let dir = tempfile::tempdir().unwrap();
    let section = |name: &str, origin: [f64; 3], normal: [f64; 3], faces: &[&str]| {
        serde_json::json!({ "name": name, "type": "section_scan",
            "plane": { "origin_mm": origin, "normal": normal },
            "surfaces": faces, "tolerance_mm": [-0.05, 0.05] })
    };
    let program = serde_json::json!({
        "format": "cmm-program/1", "name": "floor-by-column",
        "workpiece": repo("workpieces/nist-ctc05.stp").to_str().unwrap(),
        "placement": { "translate_mm": [400, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.005 } ], "roughness_um": 0.2 },
        "features": [
            section("floor-x40", [40.0, 0.0, 0.0], [1.0, 0.0, 0.0], &["face97"]),
            section("floor-x-80", [-80.0, 0.0, 0.0], [1.0, 0.0, 0.0], &["face97"]),
            section("column-z470", [0.0, 0.0, 470.0], [0.0, 0.0, 1.0], &["face129", "face130"]) ] });
    let (report, rows) = run(dir.path(), &program);
    let first = &report["features"][0]["attempts"][0];
    assert_eq!(first["outcome"], "collision", "{first}");
    assert_eq!(first["collision"]["probe_part"], "body", "{first}");
    assert_eq!(statuses(&report)[1..], ["pass", "pass"], "{report}");
    assert_eq!(report["end_move"]["outcome"], "completed");
    // The move out rises no more than the standoff above the floor's
    // approach height (it went 24 mm up the column).
    let retract_top = (rows.iter())
        .skip_while(|r| r.0 != "retract")
        .take_while(|r| r.0 == "retract")
        .map(|r| r.2)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(retract_top < 340.0, "{retract_top}");
}

/// The flange tilted 20 degrees from upright and moved 0.9 mm, its 7 mm
/// bolt hole scanned with a 2 mm ball: the shaft strikes the hole's rim
/// with the ball over it, unpressed. Backing against the scan's last
/// motion drove the ball 20 mm through the flange (deflections to 2.8
/// mm in retract rows); away from the strike it comes free, and no
/// retract row is deflected.
#[test]
fn a_shaft_that_strikes_a_holes_rim_backs_away_across_the_stylus() {
    let dir = tempfile::tempdir().unwrap();
    let circle = |name: &str, x: f64, faces: &[&str]| {
        serde_json::json!({ "name": name, "type": "section_scan",
            "plane": { "origin_mm": [x, 0, 0], "normal": [1, 0, 0] },
            "surfaces": faces, "tolerance_mm": [-0.05, 0.05], "fit": { "element": "circle" } })
    };
    let program = serde_json::json!({
        "format": "cmm-program/1", "name": "flange-tilted",
        "workpiece": repo("workpieces/io1-flange.stp").to_str().unwrap(),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -70, 15] },
        "probe": { "tip_diameter_mm": 2.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.005 } ],
            "transform": { "translate_mm": [0, 0.9, 0.9] }, "roughness_um": 0.2 },
        "features": [ circle("bolt-hole", 3.0, &["face11", "face25"]),
                      circle("bore-x15", 15.0, &["face3", "face18"]) ] });
    let (report, rows) = run(dir.path(), &program);
    let first = &report["features"][0]["attempts"][0];
    assert_eq!(first["collision"]["probe_part"], "shaft", "{first}");
    let pressed = (rows.iter())
        .filter(|r| r.0 == "retract" || r.0 == "position")
        .map(|r| r.1)
        .fold(0.0, f64::max);
    assert!(pressed < 1e-3, "{pressed} mm");
    assert_eq!(report["end_move"]["outcome"], "completed");
}
