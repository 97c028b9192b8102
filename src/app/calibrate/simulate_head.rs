//! The simulated setup of a calibration on a machine with a probe head:
//! the world's true machine is the given URDF with head assembly errors
//! (unless ideal), the host gets the nominal URDF, the machine's error map
//! and the list of orientations. The truth per orientation is kept for
//! comparison only.
use super::simulate::{
    host_error_map, sphere_pose, sphere_world, true_probe, world_profile, SimulatedCalError,
    SimulatedSetup,
};
pub use crate::formats::probe_truth::{OrientationTruth, ProbeTruth};
use crate::host::calibrate::orientation::{calibrate_head, HeadCalibration, OrientationOptions};
use crate::host::calibrate::CalibrationOptions;
use crate::host::head::{HeadModel, Orientation};
use crate::host::observe::Unobserved;
use crate::machine::MachineModel;
use crate::math::{Point3, Vec3};
use crate::world::cmm::{SimulatedCmm, TruePart};
use crate::world::dynamics::head_errors::with_head_errors;
use crate::world::dynamics::HeadErrors;

/// The orientations to calibrate.
#[derive(Debug, Clone, PartialEq)]
pub struct HeadSetup {
    /// Head axis (URDF joint) names, in the order the angles are listed.
    pub axes: Vec<String>,
    /// Angles per orientation, deg; the first is the reference.
    pub angles_deg: Vec<Vec<f64>>,
    /// The true head's assembly errors; `None`: none when ideal, otherwise
    /// [`HeadErrors::realistic`]. (Tests set them with an ideal probe to see
    /// the few-point measurement find them free of noise.)
    pub true_head_errors: Option<HeadErrors>,
}

/// The world's true machine: the given head errors, or by default none
/// when ideal and realistic ones otherwise.
pub fn true_machine(setup: &SimulatedSetup, head: &HeadSetup) -> MachineModel {
    let errors = match (&head.true_head_errors, setup.ideal) {
        (Some(e), _) => e.clone(),
        (None, true) => HeadErrors::none(),
        (None, false) => HeadErrors::realistic(),
    };
    with_head_errors(&setup.machine, &errors)
}

/// Checks the orientations against the nominal head model.
pub fn orientations(
    head: &HeadModel,
    setup: &HeadSetup,
) -> Result<Vec<Orientation>, SimulatedCalError> {
    let checked = setup.angles_deg.iter().enumerate();
    let list: Result<Vec<_>, _> = checked.map(|(k, a)| head.orientation(k + 1, a)).collect();
    Ok(list?)
}

/// Calibrates every orientation on the simulated machine; returns the
/// calibration and the truth per orientation (reference first).
pub fn calibrate_head_simulated(
    setup: &SimulatedSetup,
    head_setup: &HeadSetup,
    opts: &CalibrationOptions,
    oopts: &OrientationOptions,
) -> Result<(HeadCalibration, Vec<OrientationTruth>), SimulatedCalError> {
    let head = HeadModel::new(setup.machine.clone(), &head_setup.axes)?;
    let list = orientations(&head, head_setup)?;
    let machine = true_machine(setup, head_setup);
    let probe = true_probe(setup);
    let truth = list
        .iter()
        .map(|o| OrientationTruth {
            angles_deg: o.angles_deg.clone(),
            probe_vector: true_probe_vector(&machine, o, &probe.probe_vector),
            tip_radius_mm: probe.tip_radius_mm,
        })
        .collect();
    let (sphere, truth_part) = sphere_world(opts)?;
    let part = TruePart {
        workpiece: &sphere,
        as_machined: &truth_part,
        pose: sphere_pose(opts),
    };
    let stylus = Vec3::new(0.0, 0.0, -setup.stylus_length_mm);
    let radius = 0.5 * setup.tip_diameter_mm;
    let p_ref = list
        .first()
        .map_or(stylus, |o| head.probe_vector(o, &stylus));
    let lift = opts.sphere_radius() + radius + opts.clearance_mm;
    let start = opts.sphere_center_mm + Vec3::z() * lift - p_ref;
    let profile = world_profile(setup);
    let map = host_error_map(&profile);
    let mut cmm = SimulatedCmm::new(part, machine, profile, probe, setup.seed, start)?;
    let cal = calibrate_head(
        &mut Unobserved(&mut cmm),
        &head,
        (stylus, radius),
        &list,
        &map,
        opts,
        oopts,
    )?;
    Ok((cal, truth))
}

/// True probe vector at an orientation: the stylus through the true chain
/// with the linear axes at zero (so the spindle reference point is the
/// origin).
fn true_probe_vector(machine: &MachineModel, o: &Orientation, stylus: &Vec3) -> Vec3 {
    let pose = machine.pose(o.axis_values()).unwrap_or_default();
    (pose * Point3::from(*stylus)).coords
}
