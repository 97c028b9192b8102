//! The machine a program runs on, as the measuring side knows it: the
//! nominal kinematics from the program's `machine` key (a URDF file,
//! relative to the program; the embedded bridge CMM when absent) or from
//! the file given on the command line, which overrides the key, and the
//! travel the program's reach is checked against.
use std::path::{Path, PathBuf};

use super::ProgramError;
use crate::machine::{AxisKind, MachineModel};
use crate::math::{Iso3, Point3, Vec3};

/// Machine files given on the command line (`--machine`,
/// `--machine-profile`); each overrides the program's own key.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MachineFiles {
    /// The machine's URDF.
    pub machine: Option<PathBuf>,
    /// The machine profile (`cmm-machine-profile/1`).
    pub profile: Option<PathBuf>,
}

/// Machine travel used to check that the part can be reached, mm: the
/// box the probe mount's linear axes span.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Travel {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
}

impl Default for Travel {
    /// The embedded bridge CMM's travel.
    fn default() -> Self {
        Travel {
            lo: [0.0, 0.0, 0.0],
            hi: [700.0, 1000.0, 600.0],
        }
    }
}

impl Travel {
    /// The box the prismatic axes of `model` span (each axis adds its
    /// range along its home direction).
    pub fn of(model: &MachineModel) -> Travel {
        let mut t = Travel {
            lo: [0.0; 3],
            hi: [0.0; 3],
        };
        let linear = model
            .axes()
            .iter()
            .filter(|a| a.kind == AxisKind::Prismatic);
        for axis in linear {
            let (a, b) = (
                axis.home_direction * axis.limits.lower,
                axis.home_direction * axis.limits.upper,
            );
            for k in 0..3 {
                t.lo[k] += a[k].min(b[k]);
                t.hi[k] += a[k].max(b[k]);
            }
        }
        t
    }
}

/// The nominal machine of a program whose `machine` key is `key` (as
/// written, relative to the program `file`), unless `files` names one.
pub(super) fn nominal_machine(
    key: Option<&str>,
    file: &Path,
    files: &MachineFiles,
) -> Result<MachineModel, ProgramError> {
    if let Some(path) = &files.machine {
        return Ok(MachineModel::from_urdf_file(path)?);
    }
    let Some(key) = key else {
        return Ok(MachineModel::default_bridge());
    };
    let path = super::resolve::relative_to(file, key);
    MachineModel::from_urdf_file(&path).map_err(|e| ProgramError::Invalid {
        file: file.to_path_buf(),
        json_path: "$.machine".into(),
        reason: e.to_string(),
    })
}

/// The probe mount relative to the position of the linear axes, with
/// every revolute axis (a probe head) at zero: what carries the stylus
/// of a machine with a head.
pub fn mount_at_rest(model: &MachineModel) -> Iso3 {
    let q = vec![0.0; model.axes().len()];
    model.pose(&q).unwrap_or_else(|_| Iso3::identity())
}

/// The probe vector (probe mount's linear position to ball centre,
/// machine coordinates, mm) of a stylus `stylus` (in the mount's frame)
/// on `model` with its head at rest.
pub fn machine_probe_vector(model: &MachineModel, stylus: Vec3) -> Vec3 {
    (mount_at_rest(model) * Point3::from(stylus)).coords
}
