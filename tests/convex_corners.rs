//! A section round a box (four planes meeting at right-angled edges): the
//! ball centre goes round each convex edge on an arc of its offset radius,
//! so with `--ideal` the active scan keeps its deflection near the wanted
//! 0.3 mm all round (on a chord across the corner it would press 0.44 mm
//! deeper), and every point is on the true part.
mod common;

use std::process::Command;

use serde_json::{json, Value};

/// A plane patch with corner `o` and sides `du`, `dv` (outward `du x dv`).
fn face(name: &str, o: [f64; 3], du: [f64; 3], dv: [f64; 3]) -> Value {
    let add = |p: [f64; 3], q: [f64; 3]| [p[0] + q[0], p[1] + q[1], p[2] + q[2]];
    json!({ "name": name, "degree": [1, 1], "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
            "control_points": [[o, add(o, dv)], [add(o, du), add(add(o, du), dv)]] })
}

#[test]
fn a_box_outline_is_scanned_round_its_edges_at_the_wanted_deflection() {
    let (a, h) = (40.0, 30.0);
    let faces = vec![
        face("xp", [a, -a, 0.0], [0.0, 2.0 * a, 0.0], [0.0, 0.0, h]),
        face("xm", [-a, a, 0.0], [0.0, -2.0 * a, 0.0], [0.0, 0.0, h]),
        face("yp", [a, a, 0.0], [-2.0 * a, 0.0, 0.0], [0.0, 0.0, h]),
        face("ym", [-a, -a, 0.0], [2.0 * a, 0.0, 0.0], [0.0, 0.0, h]),
        face("top", [-a, -a, h], [2.0 * a, 0.0, 0.0], [0.0, 2.0 * a, 0.0]),
    ];
    let dir = tempfile::tempdir().unwrap();
    let wp =
        json!({ "format": "cmm-workpiece/1", "name": "box", "units": "mm", "surfaces": faces });
    std::fs::write(dir.path().join("box.json"), wp.to_string()).unwrap();
    let prog = json!({
        "format": "cmm-program/1", "name": "box", "workpiece": "box.json",
        "placement": { "translate_mm": [300, 300, 50], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.005 } ] },
        "features": [ { "name": "z15", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 15], "normal": [0, 0, 1] },
            "surfaces": ["xp", "xm", "yp", "ym"], "tolerance_mm": [-0.05, 0.05] } ] });
    let program = dir.path().join("box-prog.json");
    std::fs::write(&program, prog.to_string()).unwrap();
    let (out, trace) = (dir.path().join("out"), dir.path().join("t.csv"));
    let run = Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(["scan", program.to_str().unwrap(), "--ideal", "--quiet"])
        .args([
            "--out",
            out.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let f = &report["features"][0];
    assert_eq!(f["attempts"][0]["outcome"], "completed");
    let points = f["points"].as_array().unwrap();
    // 320 mm of outline at the pitch.
    assert!(points.len() >= 620, "{} points", points.len());
    for p in points {
        let e = p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap();
        assert!(e.abs() <= 5e-4, "{e}");
    }
    let text = std::fs::read_to_string(trace).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (phase, dx, dy, dz) = (col("phase"), col("dx_mm"), col("dy_mm"), col("dz_mm"));
    let mut scanned: Vec<f64> = Vec::new();
    for line in lines {
        let v: Vec<&str> = line.split(',').collect();
        if v[phase] != "scan" {
            continue;
        }
        let d = [dx, dy, dz].map(|k| v[k].parse::<f64>().unwrap());
        scanned.push((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
    }
    // The stylus's lift off the part after the scan belongs to the
    // measuring move (its phase): a tail over which the deflection falls
    // every cycle, down to free.
    let mut end = scanned.len();
    while end >= 2 && scanned[end - 1] < scanned[end - 2] {
        end -= 1;
    }
    assert!(
        scanned.len() - end < 100,
        "a lift-off of {} cycles",
        scanned.len() - end
    );
    // So does the press onto the part at its start: a head over which the
    // deflection rises every cycle, up from the first it reads.
    let mut start = 0;
    while start + 1 < end && scanned[start + 1] > scanned[start] {
        start += 1;
    }
    assert!(start < 100, "a press of {start} cycles");
    let kept = &scanned[start..end];
    let (lo, hi, cycles) = (
        kept.iter().copied().fold(f64::INFINITY, f64::min),
        kept.iter().copied().fold(0.0f64, f64::max),
        kept.len(),
    );
    assert!(cycles > 3000, "{cycles}");
    assert!(lo > 0.15 && hi < 0.4, "deflection {lo}..{hi} mm");
}
