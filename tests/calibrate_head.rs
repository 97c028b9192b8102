//! Probe vectors per probe-head orientation (JP2902285B2): the iterative
//! inverse correction against closed forms and an independent Newton solve,
//! the nominal head model against vectors worked out by hand, per-orientation
//! calibration against the simulator's truth, the quick 4-point measurement
//! against a full 25-point one, and the command line.
use std::path::PathBuf;
use std::process::{Command, Output};

use cmm::app::calibrate::simulate::SimulatedSetup;
use cmm::app::calibrate::simulate_head::{calibrate_head_simulated, HeadSetup};
use cmm::host::calibrate::orientation::{OrientationOptions, PointPattern};
use cmm::host::calibrate::CalibrationOptions;
use cmm::host::compensation::{ErrorMap, InverseError, InverseOptions};
use cmm::host::head::HeadModel;
use cmm::machine::{ErrorPolynomial, GeometricErrors, MachineModel, MachineProfile};
use cmm::math::{Point3, Vec3};
use cmm::world::dynamics::HeadErrors;
use serde_json::Value;

/// Per-orientation probe vector target, mm (0.5 um).
const VECTOR_TOL_MM: f64 = 5e-4;
/// Per-orientation tip radius target, mm (0.2 um).
const RADIUS_TOL_MM: f64 = 2e-4;

fn machines(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("part-programs/machines")
        .join(name)
}

fn head_machine() -> MachineModel {
    MachineModel::from_urdf_file(machines("bridge-ab-head.urdf")).unwrap()
}

fn error_profile() -> MachineProfile {
    MachineProfile::from_json_file(machines("bridge-profile-with-errors.json")).unwrap()
}

fn poly(c: &[f64]) -> ErrorPolynomial {
    ErrorPolynomial(c.to_vec())
}

const TARGET: Point3 = Point3::new(500.0, 300.0, 100.0);

fn probe() -> Vec3 {
    Vec3::new(10.0, -20.0, -150.0)
}

#[test]
fn inverse_matches_closed_form_for_scale_errors() {
    let (kx, ky, kz) = (2e-4, -1e-4, 3e-4);
    let mut g = GeometricErrors::default();
    g.x.scale_mm = poly(&[0.0, kx]);
    g.y.scale_mm = poly(&[0.0, ky]);
    g.z.scale_mm = poly(&[0.0, kz]);
    let inv = ErrorMap::new(g)
        .inverse(TARGET, &probe(), &InverseOptions::default())
        .unwrap();
    // t = s + P + k s per axis  =>  s = (t - P) / (1 + k).
    let p = probe();
    let expected = Point3::new(
        (TARGET.x - p.x) / (1.0 + kx),
        (TARGET.y - p.y) / (1.0 + ky),
        (TARGET.z - p.z) / (1.0 + kz),
    );
    assert!(
        (inv.scales - expected).amax() < 1e-9,
        "{inv:?} vs {expected}"
    );
    assert!(inv.iterations >= 2);
}

#[test]
fn inverse_matches_closed_form_for_squareness_errors() {
    let (xy, xz, yz) = (1e-4, -2e-4, 3e-4);
    let mut g = GeometricErrors::default();
    g.squareness.xy_rad = xy;
    g.squareness.xz_rad = xz;
    g.squareness.yz_rad = yz;
    let inv = ErrorMap::new(g)
        .inverse(TARGET, &probe(), &InverseOptions::default())
        .unwrap();
    // Triangular: z is free of errors, y leans with z, x with y and z.
    let p = probe();
    let sz = TARGET.z - p.z;
    let sy = TARGET.y - p.y - sz * yz;
    let sx = TARGET.x - p.x - sy * xy - sz * xz;
    assert!((inv.scales - Point3::new(sx, sy, sz)).amax() < 1e-9);
}

/// Newton with a central-difference Jacobian on `s + P + delta(s) = t`.
fn newton_reference(map: &ErrorMap, target: Point3, p: &Vec3) -> Point3 {
    let f = |s: Point3| map.forward(s, p) - target;
    let mut s = target - p;
    for _ in 0..20 {
        let h = 1e-3;
        let mut jac = nalgebra::Matrix3::zeros();
        for k in 0..3 {
            let mut e = Vec3::zeros();
            e[k] = h;
            jac.set_column(k, &((f(s + e) - f(s - e)) / (2.0 * h)));
        }
        s -= jac.lu().solve(&f(s)).unwrap();
    }
    s
}

#[test]
fn inverse_matches_newton_on_a_full_error_map() {
    // The example profile's 21 terms, plus large rotations so that the lever
    // arms through the probe vector matter.
    let mut g = error_profile().geometric;
    g.x.pitch_rad = poly(&[1e-4, 2e-7]);
    g.y.yaw_rad = poly(&[-2e-4, 0.0, 1e-10]);
    g.z.roll_rad = poly(&[5e-5, -1e-7]);
    let map = ErrorMap::new(g);
    for p in [
        probe(),
        Vec3::new(0.0, 70.0, -80.0),
        Vec3::new(-70.0, 0.0, -80.0),
    ] {
        let inv = map.inverse(TARGET, &p, &InverseOptions::default()).unwrap();
        let reference = newton_reference(&map, TARGET, &p);
        assert!((inv.scales - reference).amax() < 1e-9, "P = {p}");
        assert!((map.forward(inv.scales, &p) - TARGET).amax() < 1e-9);
    }
}

#[test]
fn inverse_reports_no_convergence_with_its_numbers() {
    let mut g = GeometricErrors::default();
    g.x.scale_mm = poly(&[0.0, -1.5]);
    let opts = InverseOptions {
        step_tolerance_mm: 1e-6,
        max_iterations: 7,
    };
    match ErrorMap::new(g).inverse(TARGET, &probe(), &opts) {
        Err(e @ InverseError::NotConverged { .. }) => {
            let InverseError::NotConverged {
                iterations,
                tolerance_mm,
                last_step_mm,
            } = e;
            assert_eq!(iterations, 7);
            assert_eq!(tolerance_mm, 1e-6);
            assert!(last_step_mm > 1.0);
            let text = e.to_string();
            assert!(
                text.contains("7 iterations") && text.contains("0.000001 mm"),
                "{text}"
            );
        }
        other => panic!("expected no convergence, got {other:?}"),
    }
}

#[test]
fn recompensation_equals_correcting_the_raw_scales_with_the_new_vector() {
    let mut g = error_profile().geometric;
    g.x.pitch_rad = poly(&[1e-4]);
    g.z.pitch_rad = poly(&[-1e-4]);
    let map = ErrorMap::new(g);
    let s = Point3::new(480.0, 320.0, 260.0);
    let (old, new) = (Vec3::new(0.0, 0.0, -150.0), Vec3::new(0.0, 70.0, -80.0));
    let turned = map
        .recompensate(map.forward(s, &old), &old, &new, &InverseOptions::default())
        .unwrap();
    assert!((turned - map.forward(s, &new)).amax() < 1e-9);
    // The two corrections differ by far more than that (the check bites).
    assert!((map.forward(s, &new) - s - new - (map.forward(s, &old) - s - old)).amax() > 1e-3);
}

#[test]
fn nominal_head_model_gives_the_vectors_worked_out_by_hand() {
    let head = HeadModel::new(head_machine(), &["a".into(), "b".into()]).unwrap();
    let stylus = Vec3::new(0.0, 0.0, -50.0);
    // B axis 50 mm below the spindle point, A 30 mm below that, mount 20 mm
    // further: 70 mm from the A axis to the ball.
    for (angles, expected) in [
        ([0.0, 0.0], Vec3::new(0.0, 0.0, -150.0)),
        ([90.0, 0.0], Vec3::new(0.0, 70.0, -80.0)),
        ([90.0, 90.0], Vec3::new(-70.0, 0.0, -80.0)),
        (
            [30.0, 0.0],
            Vec3::new(0.0, 35.0, -80.0 - 70.0 * 30f64.to_radians().cos()),
        ),
    ] {
        let o = head.orientation(1, &angles).unwrap();
        let p = head.probe_vector(&o, &stylus);
        assert!((p - expected).amax() < 1e-9, "{angles:?}: {p}");
    }
}

fn head_setup(angles: &str, errors: Option<HeadErrors>) -> HeadSetup {
    let angles_deg = angles
        .split(';')
        .map(|e| e.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    HeadSetup {
        axes: vec!["a".into(), "b".into()],
        angles_deg,
        true_head_errors: errors,
    }
}

const ORIENTATIONS: &str = "0,0;90,0;90,90;45,30;90,-90;105,179";

fn sim(seed: u64, ideal: bool) -> SimulatedSetup {
    SimulatedSetup {
        machine: head_machine(),
        profile: error_profile(),
        seed,
        ideal,
        keep_geometric_errors: ideal,
        ..SimulatedSetup::default()
    }
}

/// Largest probe vector and tip radius errors against the truth, mm.
fn worst(setup: &SimulatedSetup, head: &HeadSetup, oopts: &OrientationOptions) -> (f64, f64) {
    let (cal, truth) =
        calibrate_head_simulated(setup, head, &CalibrationOptions::default(), oopts).unwrap();
    assert_eq!(cal.orientations.len() + 1, truth.len());
    let reference = std::iter::once(&cal.reference.probe);
    let probes = reference.chain(cal.orientations.iter().map(|o| &o.probe));
    probes.zip(&truth).fold((0.0f64, 0.0f64), |(v, r), (p, t)| {
        (
            v.max((p.probe_vector - t.probe_vector).norm()),
            r.max((p.tip_radius_mm - t.tip_radius_mm).abs()),
        )
    })
}

#[test]
fn ideal_probe_with_geometric_and_head_errors_matches_the_truth() {
    // Ideal probe and no noise, but the profile's geometric errors (which
    // the host corrects with its map) and a head that differs from its
    // nominal model: the predicted vectors are micrometres off, the 4-point
    // measurement must find the truth.
    let head = head_setup(ORIENTATIONS, Some(HeadErrors::realistic()));
    let (cal, truth) = calibrate_head_simulated(
        &sim(1, true),
        &head,
        &CalibrationOptions::default(),
        &OrientationOptions::default(),
    )
    .unwrap();
    for (o, t) in cal.orientations.iter().zip(truth.iter().skip(1)) {
        let predicted = (o.predicted_probe_vector - t.probe_vector).norm();
        assert!(
            predicted > 2e-3,
            "{:?}: prediction already exact",
            o.angles_deg
        );
        assert!((o.probe.probe_vector - t.probe_vector).norm() <= VECTOR_TOL_MM);
        assert!((o.probe.tip_radius_mm - t.tip_radius_mm).abs() <= RADIUS_TOL_MM);
        assert_eq!(o.points, 4);
        assert!(o.inverse_iterations >= 2, "{o:?}");
    }
    for seed in [1, 2, 3] {
        let (v, r) = worst(
            &sim(seed, true),
            &head_setup(ORIENTATIONS, None),
            &Default::default(),
        );
        assert!(
            v <= VECTOR_TOL_MM && r <= RADIUS_TOL_MM,
            "seed {seed}: {v} {r}"
        );
    }
}

/// With default noise the error is a random draw: over 12 seeds each
/// probe vector is within 0.75 um and their mean within 0.4 um (the
/// 0.5 um tolerance of the ideal cases is crossed by about one seed in
/// ten), each tip radius within 0.25 um.
#[test]
fn default_noise_four_points_per_orientation_for_twelve_seeds() {
    let mut sum = 0.0;
    for seed in 1..=12 {
        let (v, r) = worst(
            &sim(seed, false),
            &head_setup(ORIENTATIONS, None),
            &Default::default(),
        );
        assert!(v <= 0.75e-3, "seed {seed}: probe vector off by {v} mm");
        assert!(r <= 0.25e-3, "seed {seed}: tip radius off by {r} mm");
        sum += v;
    }
    assert!(
        sum / 12.0 <= 0.4e-3,
        "mean probe vector error {} mm",
        sum / 12.0
    );
}

#[test]
fn four_points_from_the_predicted_centre_agree_with_25_points() {
    // A = 30 deg keeps the 25-point pattern's 90 deg ring above -30 deg.
    let head = head_setup("0,0;30,30;30,-120", None);
    let run = |pattern| {
        let oopts = OrientationOptions {
            pattern,
            ..OrientationOptions::default()
        };
        let opts = CalibrationOptions::default();
        calibrate_head_simulated(&sim(5, false), &head, &opts, &oopts).unwrap()
    };
    let ((quick, truth), (full, _)) = (run(PointPattern::Cap), run(PointPattern::Iso25));
    for ((q, f), t) in quick
        .orientations
        .iter()
        .zip(&full.orientations)
        .zip(&truth[1..])
    {
        assert_eq!((q.points, f.points), (4, 25));
        let dv = (q.probe.probe_vector - f.probe.probe_vector).norm();
        let dr = (q.probe.tip_radius_mm - f.probe.tip_radius_mm).abs();
        assert!(
            dv <= VECTOR_TOL_MM && dr <= 0.25e-3,
            "{:?}: {dv} {dr}",
            q.angles_deg
        );
        assert!((f.probe.probe_vector - t.probe_vector).norm() <= 0.25e-3);
    }
}

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn bad_head_angles_exit_2_naming_the_entry() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.json");
    let head = machines("bridge-ab-head.urdf");
    let (out_s, head_s) = (out.to_str().unwrap(), head.to_str().unwrap());
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["--head-angles", "0,0;90,x"],
            &["entry 2", "'x' is not a number"],
        ),
        (&["--head-angles", "0,0;;90,0"], &["entry 2", "empty"]),
        (
            &["--head-angles", "0,0;90"],
            &["orientation 2", "1 angles given", "2 axes"],
        ),
        (
            &["--head-angles", "0,0;120,0"],
            &["orientation 2", "'a' at 120 deg", "travel"],
        ),
        (
            &["--head-angles", "0,0", "--head-axes", "a,c"],
            &["'c'", "not a revolute joint"],
        ),
        (
            &["--head-angles", "0,0", "--orientation-points", "3"],
            &["at least 4"],
        ),
    ];
    for (extra, wanted) in cases {
        let mut args = vec!["calibrate-probe", "--machine", head_s, "--out", out_s];
        args.extend(extra);
        let o = cmm(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        for w in wanted {
            assert!(err.contains(w), "{extra:?}: '{w}' missing from: {err}");
        }
        assert!(!out.exists(), "{extra:?} left a file");
    }
    let o = cmm(&["calibrate-probe", "--head-angles", "0,0", "--out", out_s]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("has no probe head"));
}

fn vec3(v: &Value) -> Vec3 {
    Vec3::new(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

#[test]
fn cli_writes_every_orientation_with_its_truth() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal.json");
    let (head, profile) = (
        machines("bridge-ab-head.urdf"),
        machines("bridge-profile-with-errors.json"),
    );
    let o = cmm(&[
        "calibrate-probe",
        "--machine",
        head.to_str().unwrap(),
        "--machine-profile",
        profile.to_str().unwrap(),
        "--head-angles",
        "0,0;90,0;90,90",
        "--ideal",
        "--keep-geometric-errors",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("head orientation (a,b)"));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["format"], "cmm-probe-cal/1");
    assert_eq!(v["head_angles_deg"], serde_json::json!([0.0, 0.0]));
    let list = v["orientations"].as_array().unwrap();
    let truth = v["simulation_truth"]["orientations"].as_array().unwrap();
    assert_eq!((list.len(), truth.len()), (3, 3));
    // The DESIGN 6.7 keys keep meaning the reference orientation.
    assert_eq!(list[0]["method"], "reference");
    assert_eq!(list[0]["probe_vector_mm"], v["probe_vector_mm"]);
    assert_eq!(
        truth[0]["probe_vector_mm"],
        v["simulation_truth"]["probe_vector_mm"]
    );
    for (o, t) in list.iter().zip(truth) {
        assert_eq!(o["head_angles_deg"], t["head_angles_deg"]);
        let dv = (vec3(&o["probe_vector_mm"]) - vec3(&t["probe_vector_mm"])).norm();
        let dr = o["tip_radius_mm"].as_f64().unwrap() - t["tip_radius_mm"].as_f64().unwrap();
        assert!(dv <= VECTOR_TOL_MM && dr.abs() <= RADIUS_TOL_MM, "{o}");
    }
    assert_eq!(list[1]["points"], 4);
    assert!((vec3(&truth[1]["probe_vector_mm"]) - Vec3::new(0.0, 70.0, -80.0)).norm() < 1e-9);
    // The file reads back (the truth is skipped unread).
    cmm::host::calibrate::file::ProbeCalibration::read(&out).unwrap();
}

#[test]
fn the_simulated_head_refuses_bad_orientations_through_the_seam() {
    use cmm::app::calibrate::simulate::{sphere_pose, sphere_world};
    use cmm::seam::{Cmm, HeadCommandError};
    use cmm::world::cmm::{SimulatedCmm, TruePart};
    use cmm::world::probe::TrueProbe;
    let opts = CalibrationOptions::default();
    let (sphere, am) = sphere_world(&opts).unwrap();
    let part = TruePart {
        workpiece: &sphere,
        as_machined: &am,
        pose: sphere_pose(&opts),
    };
    let probe = TrueProbe::ideal(Vec3::new(0.0, 0.0, -50.0), 1.5);
    let start = Point3::new(300.0, 300.0, 400.0);
    let new = |machine: MachineModel| {
        let profile = MachineProfile::default();
        SimulatedCmm::new(part, machine, profile, probe.clone(), 1, start).unwrap()
    };
    let mut plain = new(MachineModel::default_bridge());
    assert_eq!(plain.head_axes(), 0);
    assert_eq!(plain.index_head(&[0.0]), Err(HeadCommandError::NoHead));
    let mut head = new(head_machine());
    assert_eq!(head.head_axes(), 2);
    assert!(matches!(
        head.index_head(&[0.0]),
        Err(HeadCommandError::Count {
            expected: 2,
            found: 1
        })
    ));
    // Chain order: b, then a (0..105 deg).
    match head.index_head(&[0.0, 2.0]) {
        Err(HeadCommandError::Travel {
            axis, angle_rad, ..
        }) => {
            assert_eq!((axis.as_str(), angle_rad), ("a", 2.0));
        }
        other => panic!("expected a travel error, got {other:?}"),
    }
    let t0 = head.readings().time_s;
    let encoders = head.index_head(&[0.5, 1.0]).unwrap();
    assert!((encoders[0] - 0.5).abs() < 1e-5 && (encoders[1] - 1.0).abs() < 1e-5);
    // Indexing takes the longest move at the rotary speed limit (1.5 rad/s).
    assert!((head.readings().time_s - t0 - 1.0 / 1.5).abs() < 1e-9);
}
