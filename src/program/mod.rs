//! Part programs (`cmm-program/1`, the cmm-program/1 format): reading, validation
//! against the workpiece and the machine, and the resolved [`Program`] the
//! inspection runs. Everything is checked before anything is measured; every
//! error names the file, the JSON path and the reason.

mod clearance;
pub mod format;
pub mod limits;
pub mod machine;
mod resolve;

use std::path::PathBuf;

pub use clearance::{ClearanceMargins, MAX_MARGIN_MM};
pub use format::{
    AlignmentSpec, ClearanceSpec, Defaults, FeatureSpec, FitElement, FitSpec, Mode, PlaneSpec,
    ProgramFile, PROGRAM_FORMAT,
};
pub use machine::{MachineFiles, Travel};
pub use resolve::{load, read, read_on, ProfileSource, ScenarioSpec};

use crate::geometry::{Plane, SectionCurve};
use crate::math::{Mat3, Point3, Vec2, Vec3};
use crate::workpiece::{Workpiece, WorkpieceError};

/// Why a part program is invalid.
#[derive(Debug, thiserror::Error)]
pub enum ProgramError {
    /// The program file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// Not valid JSON, or a value of the wrong type or an unknown key.
    #[error(transparent)]
    Syntax(#[from] crate::jsonfile::JsonSyntaxError),
    /// The content is invalid.
    #[error("{file}: {json_path}: {reason}")]
    Invalid {
        /// The file.
        file: PathBuf,
        /// JSON path of the offending value.
        json_path: String,
        /// What is wrong.
        reason: String,
    },
    /// The referenced workpiece file is invalid.
    #[error(transparent)]
    Workpiece(#[from] WorkpieceError),
    /// The machine file given on the command line is invalid.
    #[error(transparent)]
    Machine(#[from] crate::machine::MachineError),
    /// The machine profile given on the command line is invalid.
    #[error(transparent)]
    Profile(#[from] crate::machine::ProfileError),
}

/// The nominal pose of the part on the machine: `x_machine = R x_part + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Rotation.
    pub rotation: Mat3,
    /// Translation, mm.
    pub translation: Vec3,
}

impl Pose {
    /// Part to machine coordinates.
    pub fn to_machine(&self, p: Point3) -> Point3 {
        Point3::from(self.rotation * p.coords + self.translation)
    }
    /// A part direction in machine coordinates.
    pub fn dir_to_machine(&self, v: Vec3) -> Vec3 {
        self.rotation * v
    }
    /// Machine to part coordinates.
    pub fn to_part(&self, p: Point3) -> Point3 {
        Point3::from(self.rotation.transpose() * (p.coords - self.translation))
    }
}

/// The probe as the program describes it (nominal values).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeSetup {
    /// Nominal tip radius, mm.
    pub tip_radius_mm: f64,
    /// Stylus length, mm.
    pub stylus_length_mm: f64,
    /// Radius of the stylus shaft, mm.
    pub shaft_radius_mm: f64,
    /// Radius of the probe body, mm.
    pub body_radius_mm: f64,
    /// Length of the probe body above the probe mount, mm.
    pub body_length_mm: f64,
    /// Calibration file, resolved against the program's folder.
    pub calibration: Option<PathBuf>,
}

/// Measuring parameters of a section scan, defaults applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanSettings {
    /// Measuring mode.
    pub mode: Mode,
    /// Scanning speed, mm/s.
    pub speed_mm_s: f64,
    /// Wanted deflection, mm.
    pub deflection_mm: f64,
    /// Reported point spacing, mm.
    pub pitch_mm: f64,
    /// Trajectory tolerance, mm.
    pub trajectory_tolerance_mm: f64,
}

/// A nominal touch point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NominalPoint {
    /// Face index.
    pub face: usize,
    /// Surface parameters.
    pub uv: Vec2,
    /// Nominal point, part coordinates.
    pub point: Point3,
    /// Outward unit normal.
    pub normal: Vec3,
}

/// A validated feature.
#[derive(Debug, Clone)]
pub enum Feature {
    /// A section scan with its nominal section curves.
    Section {
        /// Name.
        name: String,
        /// Plane in part coordinates.
        plane: Plane,
        /// Faces scanned.
        faces: Vec<usize>,
        /// Nominal section curves (at least one).
        curves: Vec<SectionCurve>,
        /// Measuring parameters.
        settings: ScanSettings,
        /// Allowed deviation `(lower, upper)`, mm.
        tolerance: (f64, f64),
        /// Element fitted to the measured points, with tolerances.
        fit: Option<FitSpec>,
    },
    /// Touch points.
    Touch {
        /// Name.
        name: String,
        /// Nominal points (projected onto the design data).
        points: Vec<NominalPoint>,
        /// Allowed deviation `(lower, upper)`, mm.
        tolerance: (f64, f64),
        /// Element fitted to the measured points, with tolerances.
        fit: Option<FitSpec>,
    },
}

impl Feature {
    /// The feature's name.
    pub fn name(&self) -> &str {
        match self {
            Feature::Section { name, .. } | Feature::Touch { name, .. } => name,
        }
    }

    /// The element to fit, if any.
    pub fn fit(&self) -> Option<&FitSpec> {
        match self {
            Feature::Section { fit, .. } | Feature::Touch { fit, .. } => fit.as_ref(),
        }
    }
}

impl Program {
    /// The stylus in the probe mount's frame: straight down, its length,
    /// mm.
    pub fn stylus(&self) -> Vec3 {
        Vec3::new(0.0, 0.0, -self.probe.stylus_length_mm)
    }

    /// The nominal probe vector (probe mount's linear position to the
    /// ball centre, machine coordinates, mm): the stylus carried by the
    /// machine's head at rest (the stylus itself without a head).
    pub fn probe_vector(&self) -> Vec3 {
        machine::machine_probe_vector(&self.machine, self.stylus())
    }
}

/// A validated program with everything it refers to loaded.
#[derive(Debug, Clone)]
pub struct Program {
    /// Program name.
    pub name: String,
    /// The program file.
    pub file: PathBuf,
    /// The nominal design data.
    pub workpiece: Workpiece,
    /// Nominal part pose on the machine.
    pub placement: Pose,
    /// Probe geometry.
    pub probe: ProbeSetup,
    /// Features in program order.
    pub features: Vec<Feature>,
    /// Alignment points (projected onto the design data), if any.
    pub alignment: Option<Vec<NominalPoint>>,
    /// The nominal machine the program runs on.
    pub machine: crate::machine::MachineModel,
    /// Clearance margins of the moves between measurements.
    pub clearance: ClearanceMargins,
}
