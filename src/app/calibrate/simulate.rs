//! The simulated setup of a calibration: the reference sphere (an exact
//! rational NURBS sphere) at its known position on the simulated machine,
//! the true probe, and the truth kept for comparison only. The calibration
//! itself ([`super::calibrate`]) sees the machine through the seam alone.
use std::path::Path;

pub use crate::formats::probe_truth::{OrientationTruth, ProbeTruth};
use crate::host::calibrate::{
    calibrate_compensated, nominal_probe, CalibrateError, Calibration, CalibrationOptions,
};
use crate::host::compensation::ErrorMap;
use crate::host::observe::Unobserved;
use crate::machine::{MachineModel, MachineProfile};
use crate::math::{rotation_xyz_deg, Vec3};
use crate::program::Pose;
use crate::workpiece::examples::reference_sphere;
use crate::workpiece::{Workpiece, WorkpieceError};
use crate::world::as_machined::AsMachined;
use crate::world::cmm::{SimError, SimulatedCmm, TruePart};
use crate::world::probe::TrueProbe;

/// Orientation (`rotate_deg`, the as-machined format) of the sphere workpiece on the
/// machine. The NURBS sphere is a surface of revolution whose parametric
/// poles make closest-point projection ill-conditioned within about 1 deg;
/// turning them to the horizontal at azimuth 22.5 deg keeps them at least
/// 15 deg from every probed point (the XY circle runs above the equator).
const SPHERE_POLES_DEG: [f64; 3] = [0.0, 90.0, 22.5];

/// The simulated machine and probe of a calibration run.
#[derive(Debug, Clone)]
pub struct SimulatedSetup {
    /// Machine kinematics.
    pub machine: MachineModel,
    /// Machine profile (dynamics, scales, geometric errors).
    pub profile: MachineProfile,
    /// Nominal tip diameter, mm.
    pub tip_diameter_mm: f64,
    /// Nominal stylus length (vertical), mm.
    pub stylus_length_mm: f64,
    /// Stylus shaft diameter, mm (`None`: half the tip's).
    pub shaft_diameter_mm: Option<f64>,
    /// Seed of every random draw.
    pub seed: u64,
    /// Switch off every simulated error and all noise.
    pub ideal: bool,
    /// With `ideal`, keep the profile's 21 geometric error terms (the host
    /// corrects them with its error map), to check the correction and the
    /// iterative inverse free of noise.
    pub keep_geometric_errors: bool,
}

impl Default for SimulatedSetup {
    /// The embedded bridge, default profile, 3 mm tip, 50 mm stylus, seed 1.
    fn default() -> Self {
        SimulatedSetup {
            machine: MachineModel::default_bridge(),
            profile: MachineProfile::default(),
            tip_diameter_mm: 3.0,
            stylus_length_mm: 50.0,
            shaft_diameter_mm: None,
            seed: 1,
            ideal: false,
            keep_geometric_errors: false,
        }
    }
}

/// Why a simulated calibration failed.
#[derive(Debug, thiserror::Error)]
pub enum SimulatedCalError {
    /// The sphere workpiece could not be built.
    #[error("reference sphere")]
    Sphere(#[from] WorkpieceError),
    /// The simulator could not start.
    #[error("cannot start the simulated machine")]
    Machine(#[from] SimError),
    /// The calibration failed.
    #[error("calibration failed")]
    Calibrate(#[from] CalibrateError),
    /// The head or an orientation does not fit the machine.
    #[error("probe head orientations")]
    Head(#[from] crate::host::head::HeadModelError),
}

/// The true probe of a setup (realistic unless ideal).
pub fn true_probe(setup: &SimulatedSetup) -> TrueProbe {
    let nominal = nominal_probe(setup.tip_diameter_mm, setup.stylus_length_mm);
    let mut probe = if setup.ideal {
        TrueProbe::ideal(nominal.probe_vector, nominal.tip_radius_mm)
    } else {
        TrueProbe::realistic(nominal.probe_vector, nominal.tip_radius_mm)
    };
    if let Some(d) = setup.shaft_diameter_mm {
        probe.shape.shaft_radius_mm = 0.5 * d;
    }
    probe
}

/// The machine profile the world runs with: the given one, or its ideal
/// version (keeping the geometric errors when asked).
pub fn world_profile(setup: &SimulatedSetup) -> MachineProfile {
    if !setup.ideal {
        return setup.profile.clone();
    }
    let mut ideal = setup.profile.ideal();
    if setup.keep_geometric_errors {
        ideal.geometric = setup.profile.geometric.clone();
    }
    ideal
}

/// The host's error map: the machine's geometric error terms as its own
/// calibration found them, here taken to be exactly the world's terms.
pub fn host_error_map(profile: &MachineProfile) -> ErrorMap {
    ErrorMap::new(profile.geometric.clone())
}

/// The reference sphere as a true part: workpiece and (nominal) as-machined
/// model, placed by [`sphere_pose`].
pub fn sphere_world(opts: &CalibrationOptions) -> Result<(Workpiece, AsMachined), WorkpieceError> {
    let file = reference_sphere(opts.sphere_diameter_mm);
    let sphere = Workpiece::from_file(&file, Path::new("<reference sphere>"))?;
    Ok((sphere, AsMachined::nominal()))
}

/// Where the sphere sits on the machine.
pub fn sphere_pose(opts: &CalibrationOptions) -> Pose {
    Pose {
        rotation: rotation_xyz_deg(SPHERE_POLES_DEG),
        translation: opts.sphere_center_mm.coords,
    }
}

/// Calibrates on the simulated machine; returns the calibration and the
/// truth to write beside it.
pub fn calibrate_simulated(
    setup: &SimulatedSetup,
    opts: &CalibrationOptions,
) -> Result<(Calibration, ProbeTruth), SimulatedCalError> {
    let (sphere, truth_part) = sphere_world(opts)?;
    let part = TruePart {
        workpiece: &sphere,
        as_machined: &truth_part,
        pose: sphere_pose(opts),
    };
    let probe = true_probe(setup);
    let truth = ProbeTruth {
        probe_vector: probe.probe_vector,
        tip_radius_mm: probe.tip_radius_mm,
    };
    let nominal = nominal_probe(setup.tip_diameter_mm, setup.stylus_length_mm);
    let lift = opts.sphere_radius() + nominal.tip_radius_mm + opts.clearance_mm;
    let start = opts.sphere_center_mm + Vec3::z() * lift - nominal.probe_vector;
    let profile = world_profile(setup);
    let map = host_error_map(&profile);
    let mut cmm = SimulatedCmm::new(
        part,
        setup.machine.clone(),
        profile,
        probe,
        setup.seed,
        start,
    )?;
    let cal = calibrate_compensated(&mut Unobserved(&mut cmm), nominal, &map, opts)?;
    Ok((cal, truth))
}
