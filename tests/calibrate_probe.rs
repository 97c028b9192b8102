//! Probe calibration on the simulated reference sphere: the recovered probe
//! vector and tip radius against the simulator's truth, and the probing and
//! scanning errors before and after.
use cmm::calibrate::simulate::{calibrate_simulated, SimulatedSetup};
use cmm::calibrate::CalibrationOptions;
use cmm::world::machine::{MachineModel, MachineProfile};

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
    let dirs = cmm::calibrate::pattern::iso_25_directions();
    assert_eq!(dirs.len(), 25);
    assert!(dirs
        .iter()
        .all(|d| (d.norm() - 1.0).abs() < 1e-12 && d.z > -1e-12));
    assert_eq!(dirs.iter().filter(|d| d.z.abs() < 1e-12).count(), 8);
}
