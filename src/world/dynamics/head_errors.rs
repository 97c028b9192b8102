//! Geometric errors of a probe head (world side): the true head differs from
//! the nominal URDF the measuring software was given.
//!
//! Per revolute joint (chain order): the joint's frame is displaced by a
//! small offset (mm, in the parent link's frame: the axis does not sit
//! exactly where the drawing says) and its axis is turned by a small
//! rotation vector (rad: the axis is not exactly parallel to the drawing's).
//! Together with the stylus error of [`crate::world::probe::TrueProbe`]
//! this makes the true probe vector at a head orientation differ from the
//! one the host predicts from its nominal model by a few micrometres, which
//! the per-orientation calibration has to find.
use crate::machine::MachineModel;
use crate::math::Vec3;

/// Errors of the head's revolute joints, chain order; joints beyond the
/// lists are perfect.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HeadErrors {
    /// Offset of each revolute joint's frame, mm.
    pub origin_offsets_mm: Vec<Vec3>,
    /// Small rotation (rotation vector) of each revolute joint's axis, rad.
    pub axis_tilts_rad: Vec<Vec3>,
}

impl HeadErrors {
    /// A perfect head (`--ideal`).
    pub fn none() -> HeadErrors {
        HeadErrors::default()
    }

    /// Errors of the size a real indexing head has after assembly: joint
    /// offsets of 2-5 um and axis misalignments of 10-25 urad (2.5 um over a
    /// 100 mm lever).
    pub fn realistic() -> HeadErrors {
        HeadErrors {
            origin_offsets_mm: vec![
                Vec3::new(0.004, -0.003, 0.002),
                Vec3::new(-0.002, 0.005, -0.003),
            ],
            axis_tilts_rad: vec![Vec3::new(15e-6, -10e-6, 0.0), Vec3::new(0.0, 20e-6, -12e-6)],
        }
    }
}

/// This machine with the head errors applied to its revolute joints: the
/// world's true machine built from the nominal one.
pub fn with_head_errors(machine: &MachineModel, errors: &HeadErrors) -> MachineModel {
    machine.with_revolute_errors(&errors.origin_offsets_mm, &errors.axis_tilts_rad)
}
