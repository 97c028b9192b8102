//! A touch point is taken where the program puts it: the approach runs on
//! the line through the programmed point along its normal, whatever the
//! move before it left of the servo's following error sideways. Four touch
//! points 3 mm apart on the end face of a bracket's boss (the fixture
//! assembly, STEP; the face is the plane x = 31 of the first bracket):
//! each move between them is sideways to the approach, and arriving at
//! the approach speed the following error and braking used to carry the
//! ball 0.06-0.14 mm sideways past the start (off a small face, or over
//! its edge, on a small part). With `--ideal` and no machining errors the
//! measured point lies on the plane at the programmed y and z.
mod common;

use common::*;

const POINTS: [[f64; 3]; 4] = [
    [31.0, 24.0, 0.0],
    [31.0, 21.0, 2.0],
    [31.0, 21.0, -2.0],
    [31.0, 18.0, 0.0],
];

fn program(dir: &std::path::Path) -> std::path::PathBuf {
    let wp = repo("workpieces/fixture-assembly.step");
    let p = serde_json::json!({
        "format": "cmm-program/1",
        "name": "boss-touch",
        "workpiece": arg(&wp),
        "placement": { "translate_mm": [300, 420, 60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 80 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "b1-boss-end", "type": "touch_points", "points_mm": POINTS,
              "surfaces": ["bracket#1/face4"], "tolerance_mm": [-0.05, 0.05] }
        ]
    });
    write_program(dir, "boss-touch.json", &p)
}

#[test]
fn touch_points_are_taken_on_their_programmed_lines() {
    let dir = tempfile::tempdir().unwrap();
    let prog = program(dir.path());
    let out = dir.path().join("out");
    let (code, report) = scan_ideal(&prog, &out);
    assert_eq!(code, Some(0), "exit {code:?}");
    let points = report["features"][0]["points"].as_array().unwrap();
    assert_eq!(points.len(), POINTS.len());
    for (p, want) in points.iter().zip(POINTS) {
        let m: Vec<f64> = (0..3).map(|k| p["measured"][k].as_f64().unwrap()).collect();
        let sideways = (m[1] - want[1]).hypot(m[2] - want[2]);
        assert!(
            sideways < 1e-3,
            "{want:?}: measured {m:?}, {sideways} mm beside"
        );
        assert!(
            (m[0] - want[0]).abs() < 5e-4,
            "{want:?}: measured {m:?} off the plane"
        );
    }
}

/// Four touch points round a 7 mm bolt hole of the io1 flange with a
/// 3 mm ball, the part on its side: each move to the next start goes by
/// way of a point of the planning grid that can lie behind the start,
/// against the way in. The last leg must still be driven (the velocity
/// left of the leg before, turned away from the start, is no sign of
/// having passed it): every touch lands on its programmed point, and the
/// circle through them is the hole's, 7 mm across, round the hole's
/// axis at y = 0, z = 37.5.
#[test]
fn touches_round_a_small_hole_land_where_programmed() {
    let points = [
        [3.0, 3.5, 37.5],
        [3.0, 0.0, 41.0],
        [3.0, -3.5, 37.5],
        [3.0, 0.0, 34.0],
    ];
    let p = serde_json::json!({
        "format": "cmm-program/1", "name": "bolt-touch",
        "workpiece": arg(&repo("workpieces/io1-flange.stp")),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [ { "name": "bolt90", "type": "touch_points", "points_mm": points,
            "surfaces": ["face16", "face23"], "tolerance_mm": [-0.05, 0.05],
            "fit": { "element": "circle", "size_mm": [-0.05, 0.05] } } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), "p.json", &p);
    let (code, report) = scan_ideal(&path, &dir.path().join("out"));
    assert_eq!(code, Some(0), "{report}");
    let feature = &report["features"][0];
    for (got, want) in feature["points"].as_array().unwrap().iter().zip(points) {
        for k in 0..3 {
            let x = got["measured"][k].as_f64().unwrap();
            assert!((x - want[k]).abs() < 1e-6, "{got} vs {want:?}");
        }
    }
    let nominal = &feature["fit"]["nominal"];
    assert!(
        (nominal["diameter_mm"].as_f64().unwrap() - 7.0).abs() < 1e-9,
        "{nominal}"
    );
}
