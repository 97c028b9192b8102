//! Programs on real CAD parts that a CMM programmer writes without
//! thinking of the numbers' coincidences: round-numbered bolt holes whose
//! far wall meets the approach standoff at exactly the tight clearance
//! margin, a clearance height just under the top of the machine's travel,
//! a section through a steep drill-point cone. References are independent
//! of the measuring code: the holes' geometry (through holes, open from
//! above, 7 mm across for a 1 mm ball), the travel of the embedded machine
//! (Z up to 600 mm) and the section plane itself.
mod common;

use std::path::Path;

use common::{arg, cmm, repo, scan_ideal_traced};
use serde_json::{json, Value};

/// Writes `program` (its workpiece a file of `workpieces/`) to `dir`.
fn write_program(dir: &Path, program: &Value) -> String {
    let path = dir.join("p.json");
    std::fs::write(&path, program.to_string()).unwrap();
    arg(&path)
}

fn workpiece(name: &str) -> String {
    arg(&repo(&format!("workpieces/{name}")))
}

/// The six 7 mm bolt holes of the io1 flange, each a section at mid-depth
/// with a 1 mm ball, the part on its face turned `rz` degrees.
fn bolt_holes(rz: f64) -> Value {
    let holes = [
        ["face11", "face25"],
        ["face12", "face24"],
        ["face13", "face26"],
        ["face14", "face28"],
        ["face15", "face22"],
        ["face16", "face23"],
    ];
    let features: Vec<Value> = (holes.iter())
        .map(|[a, b]| {
            json!({ "name": format!("{a}-{b}"), "type": "section_scan",
                    "plane": { "origin_mm": [3, 0, 0], "normal": [1, 0, 0] },
                    "surfaces": [a, b], "tolerance_mm": [-0.05, 0.05] })
        })
        .collect();
    json!({ "format": "cmm-program/1", "name": "holes",
            "workpiece": workpiece("io1-flange.stp"),
            "placement": { "translate_mm": [350, 500, 80], "rotate_deg": [0, -90, rz] },
            "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 50 },
            "defaults": { "speed_mm_s": 30, "deflection_mm": 0.2, "pitch_mm": 0.2 },
            "features": features })
}

#[test]
fn small_ball_bolt_holes_are_reachable_however_the_part_is_turned() {
    let dir = tempfile::tempdir().unwrap();
    for rz in [0.0, 15.0, 30.0, 45.0, 60.0, 90.0] {
        let program = write_program(dir.path(), &bolt_holes(rz));
        let check = cmm(&["check", &program]);
        let text = String::from_utf8_lossy(&check.stdout);
        assert_eq!(check.status.code(), Some(0), "rz {rz}: {text}");
    }
}

#[test]
fn every_bolt_hole_is_measured_one_after_the_other() {
    let dir = tempfile::tempdir().unwrap();
    let program = write_program(dir.path(), &bolt_holes(0.0));
    let out = dir.path().join("out");
    let run = cmm(&["scan", &program, "--ideal", "--quiet", "--out", &arg(&out)]);
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let report = read_report(&out);
    for f in report["features"].as_array().unwrap() {
        assert_eq!(f["status"], "pass", "{}", f["name"]);
        // 2 pi 3.5 mm at a 0.2 mm pitch.
        assert!(
            f["points"].as_array().unwrap().len() >= 105,
            "{}",
            f["name"]
        );
    }
}

fn read_report(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap()
}

/// The largest machine z of the trace's axes.
fn highest_z(trace: &str) -> f64 {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let z = header.iter().position(|h| *h == "z_mm").unwrap();
    (lines.map(|l| l.split(',').nth(z).unwrap().parse::<f64>().unwrap())).fold(f64::MIN, f64::max)
}

#[test]
fn positioning_under_the_top_of_the_travel_stays_inside_it() {
    // A 120 mm stylus over NIST CTC 05 put 15 mm low: the clearance height
    // leaves the Z axis 0.8 mm under its 600 mm limit, and routes to the
    // block's top and back come from above.
    let program = json!({ "format": "cmm-program/1", "name": "high",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, -15], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 120 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [
            { "name": "block-back-z190", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 190], "normal": [0, 0, 1] },
              "surfaces": ["face88"], "tolerance_mm": [-0.05, 0.05] },
            { "name": "block-top", "type": "touch_points",
              "points_mm": [[80, -40, 279.4], [-80, -40, 279.4], [0, 50, 279.4]],
              "surfaces": ["face97"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), &program);
    let check = cmm(&["check", &path]);
    assert_eq!(check.status.code(), Some(0), "{check:?}");
    let (code, report, trace) = scan_ideal_traced(Path::new(&path), dir.path());
    assert_eq!(code, Some(0), "{report}");
    for f in report["features"].as_array().unwrap() {
        assert_eq!(f["status"], "pass", "{f}");
    }
    let top = highest_z(&trace);
    assert!(top < 600.0, "the Z axis reached {top} mm");
}

#[test]
fn a_scan_on_a_steep_cone_starts_on_its_section_plane() {
    // CTC 05's 118 degree drill points: at z = 14 the cone's normal leans
    // 59 degrees out of the section plane. The drill hole above it is
    // scanned first, so the probe comes down from its wall with the
    // servo's following error sideways: an approach that keeps it starts
    // the scan off the plane (its first point 0.07 mm below it).
    let program = json!({ "format": "cmm-program/1", "name": "cone",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 30, "deflection_mm": 0.15, "pitch_mm": 0.2,
                      "trajectory_tolerance_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [0.005, -0.004, 0] } },
        "features": [
            { "name": "drill-z20", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 20], "normal": [0, 0, 1] },
              "surfaces": ["face196", "face197"], "tolerance_mm": [-0.05, 0.05] },
            { "name": "drill-cone-z14", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 14], "normal": [0, 0, 1] },
              "surfaces": ["face198", "face199"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), &program);
    let out = dir.path().join("out");
    let run = cmm(&["scan", &path, "--ideal", "--quiet", "--out", &arg(&out)]);
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let report = read_report(&out);
    let points = report["features"][1]["points"].as_array().unwrap();
    // The scan starts on the plane; the plane hold then keeps every point
    // within 0.025 mm of it (the ball's 5 ms servo lag on a 2 mm circle
    // pulls the deflection up by about 0.035 mm, which held the ball on
    // its path moved the points 0.03 mm above the plane).
    let z = |p: &Value| p["measured"][2].as_f64().unwrap();
    let first = z(&points[0]);
    assert!(
        (first - 14.0).abs() < 0.01,
        "the first point at z = {first}"
    );
    for p in points {
        assert!((z(p) - 14.0).abs() < 0.025, "a point at z = {}", z(p));
    }
}

#[test]
fn an_alignment_that_cannot_be_measured_leaves_the_run_incomplete() {
    // Alignment touches on CTC 05's plate, its 45 degree faces and the
    // block's underside (face113, open only from below): the last cannot
    // be reached from above. `cmm check` says so, and `cmm scan` does not
    // go on to measure the part as if it were where the placement says.
    let program = json!({ "format": "cmm-program/1", "name": "align",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, -60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "defaults": { "speed_mm_s": 80, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [0.2, -0.15, 0.02] } },
        "alignment": { "points_mm": [[0, 180, 25.4], [200, -150, 25.4], [-200, -150, 25.4],
                                     [88.9, -60, 200], [88.9, -35, 160], [-88.9, -60, 200],
                                     [40, -68.395, 200], [-40, -68.395, 200]],
                       "surfaces": ["face20", "face21", "face99", "face113", "face112"] },
        "features": [
            { "name": "col-z460", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 460], "normal": [0, 0, 1] },
              "surfaces": ["face129", "face130"], "tolerance_mm": [-0.05, 0.05] } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), &program);
    let check = cmm(&["check", &path]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{text}");
    assert!(text.contains("alignment [4]: not reachable"), "{text}");
    let out = dir.path().join("out");
    let run = cmm(&["scan", &path, "--ideal", "--quiet", "--out", &arg(&out)]);
    assert_eq!(run.status.code(), Some(3), "{run:?}");
    let report = read_report(&out);
    assert_eq!(report["status"], "incomplete");
    let alignment = &report["alignment"];
    assert!(alignment["failed"].is_string(), "{alignment}");
    // It says which point could not be measured, how many were before it,
    // and the time they took.
    assert_eq!(alignment["failed_point"], 4, "{alignment}");
    assert_eq!(alignment["points"], 4, "{alignment}");
    assert!(
        alignment["machine_time_s"].as_f64().unwrap() > 1.0,
        "{alignment}"
    );
}

/// `cmm scan` of `program` (`--ideal` if `ideal`): its exit code and
/// report.
fn run_default(program: &Value, ideal: bool) -> (Option<i32>, Value) {
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), program);
    let out = dir.path().join("out");
    let mut args = vec!["scan", path.as_str(), "--quiet", "--out"];
    let out_arg = arg(&out);
    args.push(&out_arg);
    if ideal {
        args.push("--ideal");
    }
    let run = cmm(&args);
    (run.status.code(), read_report(&out))
}

#[test]
fn a_corner_the_ball_rolls_over_stays_out_of_the_deviations() {
    // CTC 05's block outline at z = 190: two convex 90 degree corners,
    // measured with the default (uncalibrated) probe errors. A point taken
    // while the ball rolls over a corner carries the error of a deflection
    // that is not the face's normal (35 um); the others the probe's few.
    let program = json!({ "format": "cmm-program/1", "name": "corners",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, -15], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [-0.01, 0.012, 0.005],
                                        "rotate_deg": [0, 0, -0.002] },
                         "form": [{ "kind": "offset", "mm": 0.006 },
                                  { "kind": "bump", "center_mm": [88.9, -40, 190],
                                    "radius_mm": 8, "height_mm": 0.02 },
                                  { "kind": "waviness", "amplitude_mm": 0.002,
                                    "wavelength_mm": 40, "direction": [1, 0, 0] }],
                         "roughness_um": 0.2 },
        "features": [
            { "name": "block-front-z190", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 190], "normal": [0, 0, 1] },
              "surfaces": ["face112", "face99", "face113"], "tolerance_mm": [-0.05, 0.05] } ] });
    let (code, report) = run_default(&program, false);
    assert_eq!(code, Some(0), "{report}");
    let points = report["features"][0]["points"].as_array().unwrap();
    let worst = (points.iter())
        .filter(|p| p["edge"] != true)
        .map(|p| {
            (p["deviation_mm"].as_f64().unwrap() - p["true_deviation_mm"].as_f64().unwrap()).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 0.015, "a measurement error of {worst} mm");
}

#[test]
fn a_profile_with_concave_corners_is_not_called_lost_contact() {
    // The fixture assembly's second bracket cut at z = 40: concave corners
    // with fillets smaller than the 1.5 mm ball, which bridges them, so
    // the measured points jump up to about 2 mm (four pitches) there.
    let program = json!({ "format": "cmm-program/1", "name": "profile",
        "workpiece": workpiece("fixture-assembly.step"),
        "placement": { "translate_mm": [250, 300, 60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 50, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [0.01, 0, -0.005],
                                        "rotate_deg": [0, 0, 0.003] },
                         "form": [{ "kind": "offset", "mm": 0.005 }] },
        "features": [
            { "name": "b2-profile-z40", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 40], "normal": [0, 0, 1] },
              "surfaces": (1..=29).map(|k| format!("bracket#2/face{k}")).collect::<Vec<_>>(),
              "tolerance_mm": [-0.05, 0.05] } ] });
    let (code, report) = run_default(&program, true);
    assert_eq!(code, Some(0), "{}", report["features"][0]["notes"]);
    for a in report["features"][0]["attempts"].as_array().unwrap() {
        assert_eq!(a["outcome"], "completed");
    }
}

#[test]
fn a_fit_its_nominal_points_cannot_make_is_bad_input() {
    // A sphere asked of four touch points on CTC 05's flat shoulder: no
    // sphere goes through four coplanar points, so nothing is measured.
    let program = json!({ "format": "cmm-program/1", "name": "fit",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [400, 400, -60], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "features": [
            { "name": "shoulder", "type": "touch_points",
              "points_mm": [[120, 0, 127], [0, 120, 127], [-120, 0, 127], [0, -120, 127]],
              "surfaces": ["face84"], "tolerance_mm": [-0.05, 0.05],
              "fit": { "element": "sphere" } } ] });
    let dir = tempfile::tempdir().unwrap();
    let path = write_program(dir.path(), &program);
    for args in [
        vec!["check", path.as_str()],
        vec!["scan", path.as_str(), "--quiet"],
    ] {
        let out = dir.path().join("out");
        let mut args = args;
        let out_arg = arg(&out);
        if args[0] == "scan" {
            args.extend(["--out", out_arg.as_str()]);
        }
        let run = cmm(&args);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{err}");
        assert!(
            err.contains("$.features[0].fit") && err.contains("coplanar"),
            "{err}"
        );
        assert!(!out.exists());
    }
}

#[test]
fn a_section_of_an_inclined_surface_stays_in_its_plane_on_a_shifted_part() {
    // The ABC lamp's cap sphere (centre z 457.164, radius 79.065) cut at
    // z = 505, where its normal leans 0.6 out of the plane, on a part
    // shifted 0.2 mm along x: the points lie where the plane cuts the
    // shifted sphere, a circle centred at x = 0.2.
    let program = json!({ "format": "cmm-program/1", "name": "cap",
        "workpiece": workpiece("abc-lamp.step"),
        "placement": { "translate_mm": [400, 300, -10], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 2.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 60, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [0.2, 0, 0] } },
        "features": [
            { "name": "cap-z505", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 505], "normal": [0, 0, 1] },
              "surfaces": ["face18"], "tolerance_mm": [-0.3, 0.3],
              "fit": { "element": "circle" } } ] });
    let (code, report) = run_default(&program, true);
    let f = &report["features"][0];
    assert_eq!(code, Some(0), "{}", f["notes"]);
    for p in f["points"].as_array().unwrap() {
        let z = p["measured"][2].as_f64().unwrap();
        assert!((z - 505.0).abs() < 0.01, "a point at z = {z}");
    }
    let centre = &f["fit"]["measured"]["center"];
    let (x, y) = (centre[0].as_f64().unwrap(), centre[1].as_f64().unwrap());
    assert!(
        (x - 0.2).abs() < 0.002 && y.abs() < 0.002,
        "centre {centre}"
    );
}

/// The io1 flange aligned by twelve points on its faces round about its
/// axis (the x axis: flange and boss faces, bore, boss and outside
/// cylinders).
fn flange_alignment() -> Value {
    let points = vec![
        [6.0, 40.0, 0.0],
        [6.0, -20.0, 34.64],
        [6.0, -20.0, -34.64],
        [31.0, 24.0, 0.0],
        [31.0, -12.0, 20.78],
        [31.0, -12.0, -20.78],
        [25.0, 31.0, 0.0],
        [25.0, -15.5, 26.8468],
        [25.0, -15.5, -26.8468],
        [12.0, 15.5, 26.8468],
        [12.0, -31.0, 0.0],
        [12.0, 15.5, -26.8468],
    ];
    let faces = vec!["face10", "face4", "face5", "face27", "face9", "face19"];
    json!({ "format": "cmm-program/1", "name": "aligned",
        "workpiece": workpiece("io1-flange.stp"),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [0, -90, 0] },
        "probe": { "tip_diameter_mm": 1.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 30, "deflection_mm": 0.15, "pitch_mm": 0.25 },
        "alignment": { "points_mm": points, "surfaces": faces },
        "features": [
            { "name": "flange-top", "type": "touch_points",
              "points_mm": [[6, 40, 0], [6, -40, 0], [6, 20, 34.64]],
              "tolerance_mm": [-0.05, 0.05] } ] })
}

#[test]
fn an_alignment_that_leaves_a_turn_free_says_so() {
    // Every point's surface is round about the flange's axis: no point
    // resists a turn about it.
    let dir = tempfile::tempdir().unwrap();
    let check = cmm(&["check", &write_program(dir.path(), &flange_alignment())]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(
        text.contains("alignment: note: the alignment points do not fix a turn"),
        "{text}"
    );
    let (code, report) = run_default(&flange_alignment(), true);
    assert_eq!(code, Some(0), "{}", report["alignment"]);
    let notes = report["alignment"]["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{notes:?}");
    let note = notes[0].as_str().unwrap();
    assert!(
        note.contains("turn about the axis (1.000, 0.000, 0.000)"),
        "{note}"
    );
    // With the probe's and machine's errors the fit keeps the placement's
    // turn about the axis (it was fitted to the noise: 0.97 rad).
    let (_, report) = run_default(&flange_alignment(), false);
    let r = &report["part_to_machine"]["rotation"];
    let at = |i: usize, j: usize| r[i][j].as_f64().unwrap();
    // The placement turns by -90 degrees about y: R0 = [[0,0,-1],[0,1,0],[1,0,0]];
    // the fitted turn about the part's x axis is that of R0^T R.
    let q21 = -at(0, 1);
    let q12 = at(1, 2);
    let turn = 0.5 * (q21 - q12);
    assert!(turn.abs() < 1e-9, "turn about the axis {turn} rad");
    // CTC 05's plate top, its block's 45 degree faces and front: every
    // motion is resisted, and no note is made.
    let program = json!({ "format": "cmm-program/1", "name": "aligned",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "as_machined": { "transform": { "translate_mm": [0.2, -0.15, 0.05],
                                        "rotate_deg": [0.01, -0.01, 0.05] } },
        "alignment": { "points_mm": [[0, 180, 25.4], [200, -150, 25.4], [-200, -150, 25.4],
                                     [88.9, -60, 200], [88.9, -45, 250], [-88.9, -60, 200],
                                     [40, -68.395, 200], [-40, -68.395, 200]],
                       "surfaces": ["face20", "face21", "face99", "face113", "face112"] },
        "features": [
            { "name": "col-z400", "type": "section_scan",
              "plane": { "origin_mm": [0, 0, 400], "normal": [0, 0, 1] },
              "surfaces": ["face129", "face130"], "tolerance_mm": [-0.05, 0.05] } ] });
    let (code, report) = run_default(&program, true);
    assert_eq!(code, Some(0), "{}", report["alignment"]);
    assert!(
        report["alignment"].get("notes").is_none(),
        "{}",
        report["alignment"]
    );
}

#[test]
fn alignment_touches_route_into_a_bolt_hole() {
    // A thirteenth point on a bolt hole's wall, facing round the axis,
    // fixes the turn; its touch comes down inside the hole (it drove the
    // ball straight at the wall through the flange before).
    let mut program = flange_alignment();
    program["alignment"]["points_mm"]
        .as_array_mut()
        .unwrap()
        .push(json!([3.0, 30.726, 21.781]));
    for face in ["face11", "face25"] {
        program["alignment"]["surfaces"]
            .as_array_mut()
            .unwrap()
            .push(json!(face));
    }
    program["as_machined"] = json!({ "transform": { "translate_mm": [0.02, -0.01, 0.01],
                                                    "rotate_deg": [0.05, 0, 0] } });
    let (code, report) = run_default(&program, true);
    let alignment = &report["alignment"];
    assert_eq!(code, Some(0), "{alignment}");
    assert_eq!(alignment["points"], 13, "{alignment}");
    assert!(alignment.get("notes").is_none(), "{alignment}");
    assert!(alignment["rms_mm"].as_f64().unwrap() < 1e-6, "{alignment}");
}

/// The flange moved 0.3 mm across its axis and 0.1 mm along y of the
/// machine: the alignment finds the shift itself (the reference: the
/// transform put into the part) and keeps the placement's turn about the
/// axis, which its points leave free. Removing the free turn's share of
/// each step afterwards fitted part of the shift as a turn about the
/// axis (0.12 degrees here), as the free turn's axis lies away from the
/// points' centroid.
#[test]
fn a_free_turn_stays_at_the_placement_when_the_part_is_shifted() {
    // Points on the flange's top face, the bore and the outside
    // cylinder, their centroid 4.4 mm off the axis.
    let points = vec![
        [31.0, 24.0, 0.0],
        [31.0, -12.0, 20.78],
        [31.0, -12.0, -20.78],
        [15.0, 18.0, 0.0],
        [15.0, 0.0, 18.0],
        [15.0, -18.0, 0.0],
        [15.0, 0.0, -18.0],
        [6.0, 40.0, 0.0],
        [6.0, -20.0, 34.64],
    ];
    let mut program = flange_alignment();
    program["alignment"] = json!({ "points_mm": points });
    program["probe"] = json!({ "tip_diameter_mm": 3.0, "stylus_length_mm": 50 });
    program["as_machined"] = json!({ "transform": { "translate_mm": [0.1, 0.3, -0.2] } });
    let (code, report) = run_default(&program, true);
    assert_eq!(code, Some(0), "{}", report["alignment"]);
    let pose = &report["part_to_machine"];
    let r = |i: usize, j: usize| pose["rotation"][i][j].as_f64().unwrap();
    // The placement's R0 = [[0,0,-1],[0,1,0],[1,0,0]] (-90 degrees about y).
    let r0 = [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
    for (i, row) in r0.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert!(
                (r(i, j) - want).abs() < 1e-9,
                "rotation {}",
                pose["rotation"]
            );
        }
    }
    // t = t0 + R0 (0.1, 0.3, -0.2).
    let want = [300.0 + 0.2, 400.0 + 0.3, 100.0 + 0.1];
    for (k, w) in want.iter().enumerate() {
        let t = pose["translation_mm"][k].as_f64().unwrap();
        assert!(
            (t - w).abs() < 1e-6,
            "translation {}",
            pose["translation_mm"]
        );
    }
}

/// CTC 05's counterbore (38.1 mm) scanned at z = 19 with a 2 mm ball on a
/// part moved 1.7 mm along x: the active scan stops on a trajectory error
/// with the ball 0.4 mm inside the design's material, where no route of
/// the design data starts. The probe goes back the way it came in, the
/// geometric correction touches its points, and the corrected path's
/// start (inside the design too) gets an approach from the nearest clear
/// standoff. The rescan completes; its points lie on the moved wall and
/// read their distance from the design's circle (the reference: the two
/// circles, 1.7 mm apart), and the touch points after it are reached.
#[test]
fn a_small_ball_stopped_inside_the_design_backs_out_and_corrects() {
    let program = json!({ "format": "cmm-program/1", "name": "cbore-shift",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, 20], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 2.0, "stylus_length_mm": 60 },
        "defaults": { "speed_mm_s": 50, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "as_machined": { "transform": { "translate_mm": [1.7, 0, 0] } },
        "features": [
            { "name": "cbore", "type": "section_scan",
              "plane": { "origin_mm": [0, 222.25, 19], "normal": [0, 0, 1] },
              "surfaces": ["face22", "face23"], "tolerance_mm": [-2, 2] },
            { "name": "slot-floor", "type": "touch_points",
              "points_mm": [[-250, 10, 45.72], [-250, -10, 45.72], [-215, 12, 45.72]],
              "surfaces": ["face187"], "tolerance_mm": [-0.05, 0.05] } ] });
    let (code, report) = run_default(&program, true);
    let f = &report["features"][0];
    assert_eq!(code, Some(0), "{}", f);
    let outcomes: Vec<&str> = (f["attempts"].as_array().unwrap().iter())
        .map(|a| a["outcome"].as_str().unwrap())
        .collect();
    assert_eq!(outcomes, ["trajectory_error", "completed", "completed"]);
    let points = f["points"].as_array().unwrap();
    // 2 pi 19.05 mm at a 0.5 mm pitch: 239.
    assert!(points.len() >= 216, "{} points", points.len());
    let radius = 19.05;
    for p in points {
        let m = &p["measured"];
        let (x, y) = (m[0].as_f64().unwrap(), m[1].as_f64().unwrap() - 222.25);
        // On the moved wall; its distance from the design's wall (the
        // material lies outside the bore: farther out reads negative).
        let on_true = (x - 1.7).hypot(y) - radius;
        assert!(
            on_true.abs() < 5e-4,
            "{on_true} mm off the true wall at {m}"
        );
        let want = radius - x.hypot(y);
        let got = p["deviation_mm"].as_f64().unwrap();
        assert!((got - want).abs() < 5e-4, "{got} mm, want {want} at {m}");
    }
    assert_eq!(report["features"][1]["status"], "pass");
}

/// CTC 05's wing cut at x = 230 (an open section over twelve faces, from
/// one end of the part to the other) in `mode` (the default when `None`),
/// on a part moved 2 mm along the section, scanned with `--ideal`: the
/// wing's feature report.
fn wing_moved_2mm(mode: Option<&str>) -> Value {
    wing_turned(json!({ "translate_mm": [0, 2.0, 0] }), mode)
}

/// The wing's program in `mode` (the default when `None`) on the nominal
/// part.
fn wing_program(mode: Option<&str>) -> Value {
    let faces = [
        "face21", "face182", "face179", "face170", "face9", "face7", "face4", "face5", "face16",
        "face13", "face72", "face20",
    ];
    let mut feature = json!({ "name": "wing", "type": "section_scan",
        "plane": { "origin_mm": [230, 0, 0], "normal": [1, 0, 0] },
        "surfaces": faces, "tolerance_mm": [-0.05, 0.05] });
    if let Some(m) = mode {
        feature["mode"] = json!(m);
    }
    json!({ "format": "cmm-program/1", "name": "wing",
        "workpiece": workpiece("nist-ctc05.stp"),
        "placement": { "translate_mm": [350, 500, 0], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
        "defaults": { "speed_mm_s": 50, "deflection_mm": 0.3, "pitch_mm": 0.5 },
        "features": [feature] })
}

/// The wing scanned autonomously on a part turned by 0.05 degrees about x
/// and 0.2 about z: at the slot's floor and wall the ball is held in the
/// corner, its deflection switching between the two. The scan stops
/// there with a note that says so, rather than jittering on until three
/// times the section's length (96 s of machine time, and a note of the
/// length only).
#[test]
fn an_autonomous_scan_held_in_a_corner_stops_and_says_so() {
    let f = wing_turned(json!({ "rotate_deg": [0.05, 0, 0.2] }), Some("autonomous"));
    let attempt = &f["attempts"][0];
    assert_eq!(attempt["outcome"], "aborted", "{f}");
    assert!(
        attempt["machine_time_s"].as_f64().unwrap() < 30.0,
        "{attempt}"
    );
    let note = f["notes"][0].as_str().unwrap();
    assert!(note.contains("stalled with the ball centre at"), "{note}");
}

/// The wing in `auto` mode on a part moved and turned by half a degree:
/// the corrections fail, and the autonomous scan's approach comes down
/// where the surface is not. It ends as lost contact a few millimetres
/// past the design's surface instead of coming on down until the probe
/// body struck the part.
#[test]
fn an_autonomous_approach_that_finds_no_surface_stops() {
    let moved = json!({ "translate_mm": [-0.6, 0.5, 0.2], "rotate_deg": [0.1, 0.08, 0.5] });
    let f = wing_turned(moved, None);
    for a in f["attempts"].as_array().unwrap() {
        assert_ne!(a["outcome"], "collision", "{a}");
    }
}

/// The wing in `mode` on a part placed by the as-machined `transform`,
/// with `--ideal`: the wing's feature report.
fn wing_turned(transform: Value, mode: Option<&str>) -> Value {
    let mut program = wing_program(mode);
    program["as_machined"] = json!({ "transform": transform });
    let (_, report) = run_default(&program, true);
    report["features"][0].clone()
}

/// On the rigidly moved part no point of the named faces (edge points
/// aside) reads more than the move (the reference: 2 mm), and each reads
/// its true deviation.
fn points_within_the_2mm_move(f: &Value) {
    let points = f["points"].as_array().unwrap();
    assert!(points.len() > 600, "{} points", points.len());
    for p in points.iter().filter(|p| p["edge"].as_bool() != Some(true)) {
        let dev = p["deviation_mm"].as_f64().unwrap();
        let truth = p["true_deviation_mm"].as_f64().unwrap();
        assert!(dev.abs() <= 2.0 + 1e-3, "{dev} mm at {}", p["measured"]);
        let at = &p["measured"];
        assert!((dev - truth).abs() < 5e-4, "{dev} vs {truth} at {at}");
    }
}

/// The wing scanned autonomously: the part ends 2 mm before the design's
/// section does. The scan ends where the ball rolls over the part's end,
/// rather than following the end face down and under the part (where it
/// measured points 25.4 mm off the design until the shaft struck).
#[test]
fn an_autonomous_scan_ends_where_the_part_ends() {
    let f = wing_moved_2mm(Some("autonomous"));
    let outcome = &f["attempts"][0]["outcome"];
    assert_eq!(outcome, "completed", "{}", f["attempts"]);
    points_within_the_2mm_move(&f);
}

/// The wing in `auto` mode: the active scan stops on a trajectory error,
/// and the geometric correction's touch points read the 2 mm move, except
/// one at a fillet's tangent edge, which lands on the moved fillet off
/// the plane its gap is measured along. The translation fitted to the
/// others is applied, and the rescan completes.
#[test]
fn a_translation_is_corrected_when_a_touch_at_a_fillet_edge_disagrees() {
    let f = wing_moved_2mm(None);
    let outcomes: Vec<&str> = (f["attempts"].as_array().unwrap().iter())
        .map(|a| a["outcome"].as_str().unwrap())
        .collect();
    let want = ["trajectory_error", "completed", "completed"];
    assert_eq!(outcomes, want, "{}", f["notes"]);
    let c = &f["corrections"][0];
    assert_eq!(c["model"], "translation", "{c}");
    assert!(c["points"].as_u64().unwrap() < 16, "{c}");
    points_within_the_2mm_move(&f);
}

/// The linkage's small ring bore (1.5 mm across, 2 mm deep) tilted 8
/// degrees, scanned at half its depth with a 0.3 mm ball on a 10 mm
/// stylus: the shaft (0.075 mm inside the ball's outline) leans 1 mm x
/// tan 8 = 0.14 mm over the bore's top edge, so it strikes. The ball's
/// path is 2.6 mm round; checked every 2 mm it was passed by `cmm check`,
/// and `cmm scan` then reported the collision.
#[test]
fn a_small_bore_tilted_under_a_small_ball_is_checked_all_round() {
    let dir = tempfile::tempdir().unwrap();
    let program = json!({
        "format": "cmm-program/1", "name": "linkrods-tilt8",
        "workpiece": workpiece("linkrods.step"),
        "placement": { "translate_mm": [300, 400, 100], "rotate_deg": [8, 0, 45] },
        "probe": { "tip_diameter_mm": 0.3, "stylus_length_mm": 10 },
        "defaults": { "speed_mm_s": 5, "deflection_mm": 0.05, "pitch_mm": 0.02 },
        "clearance": { "tight_margin_mm": 0.1 },
        "features": [ { "name": "ringA-bore", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 1.0], "normal": [0, 0, 1] },
            "surfaces": ["face11"], "tolerance_mm": [-0.05, 0.05] } ] });
    let prog = write_program(dir.path(), &program);
    let check = cmm(&["check", &prog]);
    let text = String::from_utf8_lossy(&check.stdout).to_string()
        + &String::from_utf8_lossy(&check.stderr);
    assert_eq!(check.status.code(), Some(3), "{text}");
    assert!(
        text.contains("ringA-bore [0]: not reachable: the probe's shaft"),
        "{text}"
    );
}

/// CTC 05 placed 266 mm along x, touched on its end face at part x =
/// -263.5 with a 3 mm ball: the approach starts 5 mm out, at machine x =
/// -4, beyond the travel's 0. `cmm check` says so, not that the part is
/// in the way; placed 9 mm further along x, the same touch is
/// reachable.
#[test]
fn a_touch_whose_approach_starts_beyond_the_travel_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let program = |x: f64| {
        json!({
            "format": "cmm-program/1", "name": "end-face",
            "workpiece": arg(&repo("workpieces/nist-ctc05.stp")),
            "placement": { "translate_mm": [x, 400, 0], "rotate_deg": [0, 0, 0] },
            "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 100 },
            "features": [ { "name": "end-face", "type": "touch_points",
                "points_mm": [[-263.525, 0, 40]], "tolerance_mm": [-0.05, 0.05] } ] })
    };
    let near = write_program(dir.path(), &program(266.0));
    let check = cmm(&["check", &near]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(3), "{text}");
    assert!(text.contains("lies outside the machine's travel"), "{text}");
    assert!(!text.contains("clear of the part"), "{text}");
    let inside = write_program(dir.path(), &program(275.0));
    let check = cmm(&["check", &inside]);
    let text = String::from_utf8_lossy(&check.stdout);
    assert_eq!(check.status.code(), Some(0), "{text}");
}
