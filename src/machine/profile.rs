//! The machine profile: dynamics, scales and geometric errors that URDF does
//! not describe (JSON, every field optional with an embedded default).
//!
//! ```json
//! { "format": "cmm-machine-profile/1", "control_cycle_s": 0.001,
//!   "linear": { "max_velocity_mm_s": 500, "max_acceleration_mm_s2": 2000,
//!               "servo_lag_s": 0.005, "scale_resolution_mm": 0.0001,
//!               "scale_noise_mm": 0.00002 },
//!   "geometric": { "x": { "scale_mm": [0, 5e-6] },
//!                  "squareness": { "xy_rad": 2e-6 } } }
//! ```
use std::path::{Path, PathBuf};

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::geometric::GeometricErrors;
use crate::math::Vec3;

/// The `format` tag of machine profile files.
pub const PROFILE_FORMAT: &str = "cmm-machine-profile/1";

/// Dynamics and scales of the linear (prismatic) axes, mm and s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct LinearAxesProfile {
    /// Largest axis speed, mm/s (the URDF velocity limit also applies).
    pub max_velocity_mm_s: f64,
    /// Largest axis acceleration, mm/s^2.
    pub max_acceleration_mm_s2: f64,
    /// First-order servo lag time constant, s (0 = no lag).
    pub servo_lag_s: f64,
    /// Scale reading quantum, mm (0 = continuous).
    pub scale_resolution_mm: f64,
    /// Standard deviation of Gaussian scale noise, mm.
    pub scale_noise_mm: f64,
}

impl Default for LinearAxesProfile {
    fn default() -> Self {
        Self {
            max_velocity_mm_s: 500.0,
            max_acceleration_mm_s2: 2000.0,
            servo_lag_s: 0.005,
            scale_resolution_mm: 1e-4,
            scale_noise_mm: 2e-5,
        }
    }
}

/// Dynamics and encoders of the rotary (revolute) axes, rad and s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct RotaryAxesProfile {
    /// Largest axis speed, rad/s (the URDF velocity limit also applies).
    pub max_velocity_rad_s: f64,
    /// Largest axis acceleration, rad/s^2.
    pub max_acceleration_rad_s2: f64,
    /// First-order servo lag time constant, s (0 = no lag).
    pub servo_lag_s: f64,
    /// Encoder reading quantum, rad (0 = continuous).
    pub scale_resolution_rad: f64,
    /// Standard deviation of Gaussian encoder noise, rad.
    pub scale_noise_rad: f64,
}

impl Default for RotaryAxesProfile {
    fn default() -> Self {
        Self {
            max_velocity_rad_s: 1.5,
            max_acceleration_rad_s2: 10.0,
            servo_lag_s: 0.005,
            scale_resolution_rad: 1e-6,
            scale_noise_rad: 2e-7,
        }
    }
}

/// Everything about the simulated machine beyond its URDF kinematics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct MachineProfile {
    /// Always `cmm-machine-profile/1`.
    pub format: String,
    /// Controller sampling period, s.
    pub control_cycle_s: f64,
    /// Linear axes (X, Y, Z).
    pub linear: LinearAxesProfile,
    /// Rotary axes (probe head, rotary table).
    pub rotary: RotaryAxesProfile,
    /// The 21 geometric error terms; zero by default.
    pub geometric: GeometricErrors,
}

impl Default for MachineProfile {
    fn default() -> Self {
        Self {
            format: PROFILE_FORMAT.into(),
            control_cycle_s: 0.001,
            linear: LinearAxesProfile::default(),
            rotary: RotaryAxesProfile::default(),
            geometric: GeometricErrors::default(),
        }
    }
}

/// Why a machine profile was rejected; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ProfileError {
    /// The file could not be read.
    #[error("{file}: cannot read machine profile: {source}")]
    Io {
        /// The profile file.
        file: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Not valid JSON, or a value of the wrong type or an unknown key.
    #[error(transparent)]
    Syntax(#[from] crate::jsonfile::JsonSyntaxError),
    /// The `format` tag is not [`PROFILE_FORMAT`].
    #[error("{file}: $.format: unknown format '{found}', expected '{PROFILE_FORMAT}'")]
    Format {
        /// The profile file.
        file: PathBuf,
        /// The tag found.
        found: String,
    },
    /// A number out of its range.
    #[error("{file}: {json_path}: {value} must be {requirement}")]
    Invalid {
        /// The profile file.
        file: PathBuf,
        /// Where, e.g. `$.geometric.x.scale_mm[1]`.
        json_path: String,
        /// The value found.
        value: f64,
        /// e.g. `finite and positive`, `within [1e-5, 0.1]`.
        requirement: String,
    },
}

impl MachineProfile {
    /// Reads and validates a profile file.
    pub fn from_json_file(path: impl AsRef<Path>) -> Result<Self, ProfileError> {
        let path = path.as_ref();
        let text = crate::jsonfile::read_text(path).map_err(|source| ProfileError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Self::from_json_str(&text, path)
    }

    /// Parses and validates profile JSON; `path_for_messages` names it.
    pub fn from_json_str(
        text: &str,
        path_for_messages: impl AsRef<Path>,
    ) -> Result<Self, ProfileError> {
        let file = path_for_messages.as_ref();
        let profile = super::profile_check::parse(text, file)?;
        super::profile_check::validate(&profile, file)?;
        Ok(profile)
    }

    /// JSON Schema of the profile file.
    pub fn json_schema() -> schemars::Schema {
        schemars::schema_for!(MachineProfile)
    }

    /// The same machine with every error and all noise switched off
    /// (`--ideal`): no geometric errors, no scale noise, no quantisation.
    /// Dynamics (limits, lag, control cycle) are kept.
    pub fn ideal(&self) -> Self {
        let mut ideal = self.clone();
        ideal.geometric = GeometricErrors::default();
        ideal.linear.scale_noise_mm = 0.0;
        ideal.linear.scale_resolution_mm = 0.0;
        ideal.rotary.scale_noise_rad = 0.0;
        ideal.rotary.scale_resolution_rad = 0.0;
        ideal
    }

    /// Displacement (mm) at the stylus tip caused by the geometric error
    /// terms, for nominal linear axis positions `xyz` = X, Y, Z in mm (see
    /// [`super::MachineModel::linear_xyz`]) and the probe vector (mm, from the
    /// spindle reference point to the tip). Rotational errors act through the
    /// lever arm (JP2902285B2); see [`super::geometric`].
    pub fn geometric_error(&self, xyz: [f64; 3], probe_vector: &Vec3) -> Vec3 {
        self.geometric.displacement(xyz, probe_vector)
    }
}
