//! The `as_machined` block of a part program (the as-machined format): serde types.
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// How the machined part differs from its design.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AsMachinedSpec {
    /// Affine transform applied after the form terms.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformSpec>,
    /// Form terms summed along the nominal normal.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub form: Vec<FormTerm>,
    /// Surface roughness: standard deviation of zero-mean Gaussian noise on
    /// the contact distance, micrometres. Not part of the deterministic truth.
    #[serde(default)]
    pub roughness_um: f64,
}

/// `x -> R (S (x - c)) + c + t`, `R = Rz(rz) Ry(ry) Rx(rx)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TransformSpec {
    /// Translation `t`, mm.
    #[serde(default)]
    pub translate_mm: [f64; 3],
    /// Rotation `[rx, ry, rz]` about the fixed part axes, degrees.
    #[serde(default)]
    pub rotate_deg: [f64; 3],
    /// Scale: one number (uniform) or three (per axis); default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Scale>,
    /// Centre `c` of rotation and scaling, mm (default origin).
    #[serde(default)]
    pub about_mm: [f64; 3],
}

/// A uniform or per-axis scale factor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Scale {
    /// The same factor on every axis.
    Uniform(f64),
    /// Factors along x, y, z.
    PerAxis([f64; 3]),
}

impl Scale {
    /// The three diagonal factors.
    pub fn factors(self) -> [f64; 3] {
        match self {
            Scale::Uniform(s) => [s; 3],
            Scale::PerAxis(s) => s,
        }
    }
}

/// One additive form term `h(p)` along the nominal outward normal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FormTerm {
    /// Constant offset; positive adds material.
    Offset {
        /// Offset, mm.
        mm: f64,
        /// Surfaces it acts on (all when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surfaces: Option<Vec<String>>,
    },
    /// Gaussian bump `h exp(-|p - c|^2 / rho^2)`.
    Bump {
        /// Centre `c`, mm.
        center_mm: [f64; 3],
        /// Radius `rho`, mm.
        radius_mm: f64,
        /// Height `h`, mm.
        height_mm: f64,
        /// Surfaces it acts on (all when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surfaces: Option<Vec<String>>,
    },
    /// Sinusoidal waviness `A sin(2 pi (p . d) / L + phi)`.
    Waviness {
        /// Amplitude `A`, mm.
        amplitude_mm: f64,
        /// Wavelength `L`, mm.
        wavelength_mm: f64,
        /// Direction `d` (normalised on use).
        direction: [f64; 3],
        /// Phase `phi`, degrees.
        #[serde(default)]
        phase_deg: f64,
        /// Surfaces it acts on (all when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surfaces: Option<Vec<String>>,
    },
}

impl FormTerm {
    /// The surfaces the term is restricted to, if any.
    pub fn surfaces(&self) -> Option<&[String]> {
        match self {
            FormTerm::Offset { surfaces, .. }
            | FormTerm::Bump { surfaces, .. }
            | FormTerm::Waviness { surfaces, .. } => surfaces.as_deref(),
        }
    }
}
