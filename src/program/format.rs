//! The `cmm-program/1` part-program format (the cmm-program/1 format): serde types,
//! from which `cmm schema program` is generated. Unknown keys are rejected.
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::formats::as_machined::AsMachinedSpec;

/// The format tag every part program carries.
pub const PROGRAM_FORMAT: &str = "cmm-program/1";

/// A part program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProgramFile {
    /// Always `"cmm-program/1"`.
    pub format: String,
    /// Program name (used in reports).
    pub name: String,
    /// Workpiece file, relative to the program file.
    pub workpiece: String,
    /// Machine description (URDF), relative to the program; the embedded
    /// bridge CMM when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<String>,
    /// Machine profile (`cmm-machine-profile/1`: control cycle, dynamics,
    /// scale noise, the 21 geometric error terms), relative to the
    /// program; the default profile when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine_profile: Option<String>,
    /// Nominal pose of the part on the machine table.
    #[serde(default)]
    pub placement: Placement,
    /// The probe.
    #[serde(default)]
    pub probe: ProbeSpec,
    /// Defaults for every feature.
    #[serde(default)]
    pub defaults: Defaults,
    /// How the simulated part differs from its design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub as_machined: Option<AsMachinedSpec>,
    /// Alignment: touch these points first and best-fit the part frame
    /// to the design data; the features are then measured in that frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alignment: Option<AlignmentSpec>,
    /// Free distances every move that is not a measuring move keeps from
    /// the design data (defaults when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<ClearanceSpec>,
    /// What to measure, in order.
    pub features: Vec<FeatureSpec>,
}

/// Clearance margins of the moves between measurements, mm; each
/// optional (its default when absent).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClearanceSpec {
    /// Free distance the ball and the stylus keep from the design data on
    /// positioning moves, approaches and retracts (default 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin_mm: Option<f64>,
    /// The smaller margin taken where the full one leaves no way, into
    /// narrow bores and pockets (default 1; at most `margin_mm`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tight_margin_mm: Option<f64>,
    /// Free distance the stylus shaft and the probe body keep from the
    /// design data while the ball measures (default 0.1, or half the ball
    /// radius less the shaft radius when that is less).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub posture_margin_mm: Option<f64>,
}

/// A best-fit alignment from touch points on the design surfaces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AlignmentSpec {
    /// Approximate nominal positions (part coordinates, within 1 mm of the
    /// surfaces), at least 6, spread so that they fix all six degrees of
    /// freedom.
    pub points_mm: Vec<[f64; 3]>,
    /// Surfaces the points lie on (all when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surfaces: Option<Vec<String>>,
}

/// `x_machine = R x_part + t`, `R = Rz(rz) Ry(ry) Rx(rx)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Translation `t`, mm.
    #[serde(default)]
    pub translate_mm: [f64; 3],
    /// Rotation `[rx, ry, rz]` about the fixed axes, degrees.
    #[serde(default)]
    pub rotate_deg: [f64; 3],
}

/// Probe geometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Stylus tip (ball) diameter, mm.
    #[serde(default = "default_tip")]
    pub tip_diameter_mm: f64,
    /// Stylus length from the probe mount to the ball centre, mm.
    #[serde(default = "default_stylus")]
    pub stylus_length_mm: f64,
    /// Diameter of the stylus shaft (stem) between the ball and the probe
    /// mount, mm; default half the tip diameter (a 3 mm ball on a 1.5 mm
    /// stem, as on common M2 styli).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft_diameter_mm: Option<f64>,
    /// Diameter of the probe body above the probe mount, mm (a cylinder;
    /// default 25, a scanning probe's body).
    #[serde(default = "default_body_diameter")]
    pub body_diameter_mm: f64,
    /// Length of the probe body above the probe mount, mm (default 80).
    #[serde(default = "default_body_length")]
    pub body_length_mm: f64,
    /// Probe calibration file (`cmm-probe-cal/1`), relative to the program.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<String>,
}

fn default_tip() -> f64 {
    3.0
}
fn default_stylus() -> f64 {
    50.0
}
fn default_body_diameter() -> f64 {
    25.0
}
fn default_body_length() -> f64 {
    80.0
}

impl Default for ProbeSpec {
    fn default() -> Self {
        ProbeSpec {
            tip_diameter_mm: default_tip(),
            stylus_length_mm: default_stylus(),
            shaft_diameter_mm: None,
            body_diameter_mm: default_body_diameter(),
            body_length_mm: default_body_length(),
            calibration: None,
        }
    }
}

/// Measuring mode of a section scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Error-correcting design-value scanning with automatic fallbacks.
    Auto,
    /// The same with passive design-value scanning (a trajectory error is
    /// lost contact or over-deflection).
    AutoPassive,
    /// Active design-value scanning only.
    Active,
    /// Passive design-value scanning only.
    Passive,
    /// Autonomous scanning (no design data for the path).
    Autonomous,
}

/// Program-wide defaults; each feature may override them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Defaults {
    /// Measuring mode of section scans.
    #[serde(default = "default_mode")]
    pub mode: Mode,
    /// Design-value scanning speed, mm/s.
    #[serde(default = "default_speed")]
    pub speed_mm_s: f64,
    /// Wanted stylus deflection while scanning, mm.
    #[serde(default = "default_deflection")]
    pub deflection_mm: f64,
    /// Spacing of reported points along a scan, mm.
    #[serde(default = "default_pitch")]
    pub pitch_mm: f64,
    /// Largest trajectory error before a correction, mm.
    #[serde(default = "default_trajectory_tolerance")]
    pub trajectory_tolerance_mm: f64,
}

fn default_mode() -> Mode {
    Mode::Auto
}
fn default_speed() -> f64 {
    80.0
}
fn default_deflection() -> f64 {
    0.3
}
fn default_pitch() -> f64 {
    0.5
}
fn default_trajectory_tolerance() -> f64 {
    1.5
}

impl Default for Defaults {
    fn default() -> Self {
        Defaults {
            mode: default_mode(),
            speed_mm_s: default_speed(),
            deflection_mm: default_deflection(),
            pitch_mm: default_pitch(),
            trajectory_tolerance_mm: default_trajectory_tolerance(),
        }
    }
}

/// A plane in part coordinates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    /// A point of the plane, mm.
    pub origin_mm: [f64; 3],
    /// Its normal (normalised on use).
    pub normal: [f64; 3],
}

/// One feature to measure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum FeatureSpec {
    /// Scan where a plane cuts the named surfaces (all when omitted).
    SectionScan {
        /// Unique feature name.
        name: String,
        /// The section plane.
        plane: PlaneSpec,
        /// Surfaces to scan (all when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surfaces: Option<Vec<String>>,
        /// Measuring mode (program default when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mode: Option<Mode>,
        /// Allowed deviation `[lower, upper]`, mm.
        tolerance_mm: [f64; 2],
        /// Scanning speed override, mm/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        speed_mm_s: Option<f64>,
        /// Deflection override, mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        deflection_mm: Option<f64>,
        /// Point pitch override, mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pitch_mm: Option<f64>,
        /// Trajectory tolerance override, mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        trajectory_tolerance_mm: Option<f64>,
        /// Fit a geometric element to the measured points and check it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fit: Option<FitSpec>,
    },
    /// Touch points near the given nominal positions (projected onto the
    /// design data for their exact nominal point and normal).
    TouchPoints {
        /// Unique feature name.
        name: String,
        /// Approximate nominal positions, mm (part coordinates).
        points_mm: Vec<[f64; 3]>,
        /// Surfaces the points lie on (all when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        surfaces: Option<Vec<String>>,
        /// Allowed deviation `[lower, upper]`, mm.
        tolerance_mm: [f64; 2],
        /// Fit a geometric element to the measured points and check it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fit: Option<FitSpec>,
    },
}

/// Element kinds a feature can be fitted with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FitElement {
    /// Circle (a bore or shaft section): diameter, centre, roundness.
    Circle,
    /// Plane: flatness, position along the normal.
    Plane,
    /// Sphere: diameter, centre, sphericity.
    Sphere,
    /// Cylinder: diameter, axis, cylindricity.
    Cylinder,
}

impl FitElement {
    /// The element's name in programs and reports (`circle`, `plane`,
    /// `sphere`, `cylinder`).
    pub fn name(self) -> &'static str {
        match self {
            FitElement::Circle => "circle",
            FitElement::Plane => "plane",
            FitElement::Sphere => "sphere",
            FitElement::Cylinder => "cylinder",
        }
    }

    /// The element kind the fitting code takes.
    pub fn kind(self) -> crate::fit::ElementKind {
        use crate::fit::ElementKind;
        match self {
            FitElement::Circle => ElementKind::Circle,
            FitElement::Plane => ElementKind::Plane,
            FitElement::Sphere => ElementKind::Sphere,
            FitElement::Cylinder => ElementKind::Cylinder,
        }
    }
}

/// A fitted element with its tolerances; the nominal element is the same fit
/// of the nominal points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FitSpec {
    /// Which element.
    pub element: FitElement,
    /// Allowed diameter deviation `[lower, upper]`, mm (circle, sphere, cylinder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size_mm: Option<[f64; 2]>,
    /// Largest form error (range of the residuals), mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form_mm: Option<f64>,
    /// Largest distance of the fitted centre / axis / plane from the nominal, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position_mm: Option<f64>,
}

impl FeatureSpec {
    /// The feature's name.
    pub fn name(&self) -> &str {
        match self {
            FeatureSpec::SectionScan { name, .. } | FeatureSpec::TouchPoints { name, .. } => name,
        }
    }
}
