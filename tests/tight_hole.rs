//! A ball that all but fills the hole it measures: NIST CTC 05's
//! 7.9375 mm drilled hole at (-203.2, 0), cut at z = 25 and scanned with a
//! 7.9 mm ball (18.75 um of play each side) on an ideal machine. The
//! section is measured; the move that ends the program, starting 18 um
//! off the hole's axis, strikes its wall within a few hundredths.
mod common;

use common::*;

/// The program: the scan, then the end move.
fn program() -> serde_json::Value {
    serde_json::json!({
        "format": "cmm-program/1", "name": "tight-hole",
        "workpiece": repo("workpieces/nist-ctc05.stp").to_str().unwrap(),
        "placement": { "translate_mm": [350, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 7.9, "stylus_length_mm": 60 },
        "defaults": { "speed_mm_s": 40, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "clearance": { "tight_margin_mm": 0.001, "margin_mm": 4 },
        "features": [ { "name": "drill-z25", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 25], "normal": [0, 0, 1] },
            "surfaces": ["face188", "face189"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle" } } ] })
}

/// The strike in the end move is a crash the run must not hide: the
/// program is `incomplete` (exit 3) though its feature passed. Backing off
/// the strike, the ball meets the far wall at once: it turns off each wall
/// it presses 0.1 mm harder, and stops where it touches again once free,
/// in the hole, resting on its wall by a few hundredths: not pressed on to
/// the stylus's 1 mm range for seconds, and not driven on through the
/// part (read as free once the wall lay beyond the contact search's reach,
/// it ran 29 mm sideways through the rail).
#[test]
fn a_strike_leaving_a_tight_hole_stops_the_probe_in_it() {
    let dir = tempfile::tempdir().unwrap();
    let prog = write_program(dir.path(), "tight-hole.json", &program());
    let (code, report, trace) = scan_ideal_traced(&prog, dir.path());
    let f = &report["features"][0];
    assert_eq!(f["status"], "pass", "{f}");
    let d = f["fit"]["measured"]["diameter_mm"].as_f64().unwrap();
    assert!((d - 7.9375).abs() < 1e-4, "{d}");
    assert_eq!(report["end_move"]["outcome"], "collision", "{report}");
    assert_eq!(report["status"], "incomplete");
    assert_eq!(code, Some(3));
    let rows: Vec<Vec<String>> = (trace.lines().skip(1))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let num = |r: &[String], k: usize| r[k].parse::<f64>().unwrap();
    let deflection = |r: &[String]| (10..13).map(|k| num(r, k).powi(2)).sum::<f64>().sqrt();
    let retract = rows.iter().filter(|r| r[14] == "retract");
    let widest = retract.map(|r| deflection(r)).fold(0.0, f64::max);
    assert!(widest < 0.5, "pressed {widest} mm backing off");
    let last = rows.last().unwrap();
    let off_axis = (num(last, 1) - 350.0 + 203.2).hypot(num(last, 2) - 500.0);
    assert!(off_axis < 0.15, "ended {off_axis} mm off the axis");
    assert!(deflection(last) < 0.1, "{}", deflection(last));
}
