//! Probe calibration on the simulated reference sphere: the recovered probe
//! vector and tip radius against the simulator's truth, and the probing and
//! scanning errors before and after.
use cmm::app::calibrate::simulate::{calibrate_simulated, SimulatedSetup};
use cmm::host::calibrate::CalibrationOptions;
use cmm::machine::{MachineModel, MachineProfile};

/// Target for the probe vector, mm (0.5 um).
const VECTOR_TOL_MM: f64 = 5e-4;
/// Target for the tip radius, mm (0.2 um).
const RADIUS_TOL_MM: f64 = 2e-4;

fn setup(seed: u64, ideal: bool) -> SimulatedSetup {
    SimulatedSetup {
        machine: MachineModel::default_bridge(),
        profile: MachineProfile::default(),
        tip_diameter_mm: 3.0,
        stylus_length_mm: 50.0,
        shaft_diameter_mm: None,
        seed,
        ideal,
        keep_geometric_errors: false,
    }
}

#[test]
fn recovers_probe_vector_and_radius_for_three_seeds() {
    for seed in [1, 7, 42] {
        let (cal, truth) =
            calibrate_simulated(&setup(seed, false), &CalibrationOptions::default()).unwrap();
        let dv = (cal.probe.probe_vector - truth.probe_vector).norm();
        let dr = (cal.probe.tip_radius_mm - truth.tip_radius_mm).abs();
        assert!(
            dv <= VECTOR_TOL_MM,
            "seed {seed}: probe vector off by {dv} mm"
        );
        assert!(
            dr <= RADIUS_TOL_MM,
            "seed {seed}: tip radius off by {dr} mm"
        );
        assert!(cal.probing_error_mm < 0.25 * cal.probing_error_before_mm);
        for s in &cal.scans {
            assert!(s.after.rms_mm < 0.2 * s.before.rms_mm, "{s:?}");
        }
    }
}

#[test]
fn ideal_probe_needs_no_correction() {
    let (cal, truth) =
        calibrate_simulated(&setup(1, true), &CalibrationOptions::default()).unwrap();
    assert!((cal.probe.probe_vector - truth.probe_vector).norm() < 1e-7);
    assert!((cal.probe.tip_radius_mm - truth.tip_radius_mm).abs() < 1e-7);
    assert!(cal.probing_error_mm < 1e-6);
}

#[test]
fn iso_pattern_has_25_points_on_the_upper_hemisphere() {
    let dirs = cmm::host::calibrate::pattern::iso_25_directions();
    assert_eq!(dirs.len(), 25);
    assert!(dirs
        .iter()
        .all(|d| (d.norm() - 1.0).abs() < 1e-12 && d.z > -1e-12));
    assert_eq!(dirs.iter().filter(|d| d.z.abs() < 1e-12).count(), 8);
}

/// The tracker's shortcut for an uncalibrated probe gives bit-for-bit the
/// measurement of the general path with the identity correction, and a
/// calibrated correction does change it (so the comparison can fail).
#[test]
fn uncorrected_locate_matches_the_identity_correction() {
    use cmm::host::modes::HostProbe;
    use cmm::host::probe_correction::DeflectionCorrection;
    use cmm::math::{Point3, Vec3};
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let probe = HostProbe::nominal(Vec3::new(0.0, 0.0, -50.0), 1.5);
    let mut tilted = DeflectionCorrection::identity();
    tilted.gain[0] = cmm::math::Mat3::identity() * 0.01;
    for axis in tilted.tilt.iter_mut() {
        for dir in axis.iter_mut() {
            dir[0] = 0.01;
        }
    }
    let calibrated = HostProbe {
        correction: tilted,
        ..probe
    };
    let mut v = || Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::repeat(1.0);
    let mut differs = 0;
    for _ in 0..2000 {
        let scales = Point3::from(v() * 300.0);
        let (reading, motion) = (v() * 0.5, v() * 80.0);
        let fast = probe.locate_uncorrected(scales, reading, motion);
        assert_eq!(fast, probe.locate(scales, reading, motion));
        differs += usize::from(fast != calibrated.locate(scales, reading, motion));
    }
    assert!(
        differs > 1990,
        "a gain and tilt correction changed only {differs} points"
    );
}
