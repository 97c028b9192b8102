//! The probe calibration file `cmm-probe-cal/1` (the cmm-probe-cal/1 format).
//!
//! ```json
//! { "format": "cmm-probe-cal/1", "probe_vector_mm": [x, y, z],
//!   "tip_radius_mm": r, "sphere_center_mm": [x, y, z],
//!   "probing_error_mm": P, "probing_error_before_mm": P0,
//!   "scanning_error_mm": S, "scanning_error_before_mm": S0,
//!   "deflection_correction": { "gain": [E0, E1, E2],
//!       "tilt_rad": { "xy": { "cw": [..], "ccw": [..] }, "xz": .., "yz": .. } },
//!   "scans": [ ... ], "conditions": { ... },
//!   "head_axes": ["a", "b"], "head_angles_deg": [0, 0],
//!   "orientations": [ { "head_angles_deg": [90, 0], "probe_vector_mm": [..],
//!                       "tip_radius_mm": r, ... }, ... ],
//!   "simulation_truth": { "probe_vector_mm": [..], "tip_radius_mm": r,
//!                         "orientations": [ ... ] } }
//! ```
//! On a machine with a probe head the top-level probe keys belong to the
//! reference orientation `head_angles_deg`; `orientations` lists every
//! calibrated orientation, the reference first (see [`super::file_head`]).
//! `sphere_center_mm` is the sphere's centre as measured with the nominal
//! probe vector; the sphere's known position is in `conditions`. The
//! gain matrices `E_k` are row-major 3x3 (units 1/mm^k) and the tilts
//! polynomials in the deflection amount (see
//! [`crate::host::probe_correction`]). `simulation_truth` is written by the
//! simulator for comparison only: the reader accepts it and throws it away
//! unread ([`serde::de::IgnoredAny`]).
use std::path::{Path, PathBuf};

use serde::de::IgnoredAny;
use serde::{Deserialize, Serialize};

use super::file_head::{OrientationJson, OrientationTruthJson};
use super::{Calibration, CalibrationOptions, ScanSummary};
use crate::formats::probe_truth::ProbeTruth;
use crate::host::modes::HostProbe;
use crate::host::probe_correction::{DeflectionCorrection, DeflectionPoly, CORRECTION_TERMS};
use crate::math::{Mat3, Vec3};

/// The `format` tag.
pub const PROBE_CAL_FORMAT: &str = "cmm-probe-cal/1";

/// Tilt polynomials of one plane.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionTilts {
    /// Clockwise, rad per power of the deflection in mm.
    pub cw: Vec<f64>,
    /// Counter-clockwise.
    pub ccw: Vec<f64>,
}

/// Tilts of the three planes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneTilts {
    /// XY plane (normal axis z).
    pub xy: DirectionTilts,
    /// XZ plane (normal axis y).
    pub xz: DirectionTilts,
    /// YZ plane (normal axis x).
    pub yz: DirectionTilts,
}

/// The deflection correction as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionJson {
    /// `E0, E1, ..`: gain correction matrices (row-major) per power of the
    /// deflection amount.
    pub gain: Vec<[[f64; 3]; 3]>,
    /// Normal tilts.
    pub tilt_rad: PlaneTilts,
}

/// How the calibration was measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conditions {
    /// Reference sphere diameter, mm.
    pub sphere_diameter_mm: f64,
    /// Known sphere position, mm.
    pub sphere_position_mm: [f64; 3],
    /// Touch points (ISO 10360-5 pattern).
    pub touch_points: usize,
    /// Touch trigger deflection, mm.
    pub trigger_mm: f64,
    /// Scan deflections, mm.
    pub deflections_mm: Vec<f64>,
    /// Scan directions.
    pub directions: Vec<String>,
    /// Scanning speed, mm/s.
    pub scan_speed_mm_s: f64,
    /// Gain correction terms (polynomial degree + 1; 0 = none).
    pub gain_terms: usize,
    /// RMS of the ball-centre fit, mm.
    pub fit_residual_rms_mm: f64,
}

/// The file's content (everything but the simulation truth).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeCalFile {
    /// Always [`PROBE_CAL_FORMAT`].
    pub format: String,
    /// Probe vector, mm.
    pub probe_vector_mm: [f64; 3],
    /// Effective tip radius, mm.
    pub tip_radius_mm: f64,
    /// Sphere centre measured with the nominal probe vector, mm.
    pub sphere_center_mm: [f64; 3],
    /// Probing error P after calibration, mm.
    pub probing_error_mm: f64,
    /// Probing error with nominal probe values, mm.
    #[serde(default)]
    pub probing_error_before_mm: Option<f64>,
    /// Largest scan radial range after calibration, mm.
    #[serde(default)]
    pub scanning_error_mm: Option<f64>,
    /// The same with nominal probe values, mm.
    #[serde(default)]
    pub scanning_error_before_mm: Option<f64>,
    /// The deflection correction (none: plain readings).
    #[serde(default)]
    pub deflection_correction: Option<CorrectionJson>,
    /// Per scan errors.
    #[serde(default)]
    pub scans: Vec<ScanSummary>,
    /// Measuring conditions.
    #[serde(default)]
    pub conditions: Option<Conditions>,
    /// Probe-head axes (URDF joint names) in the order angles are listed;
    /// absent without a head.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub head_axes: Option<Vec<String>>,
    /// Head angles of the reference orientation, deg: the orientation the
    /// keys above belong to. Absent without a head.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub head_angles_deg: Option<Vec<f64>>,
    /// Every calibrated head orientation, the reference first
    /// ([`super::file_head`]); empty without a head.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub orientations: Vec<OrientationJson>,
    /// Accepted and discarded unread.
    #[serde(default, skip_serializing)]
    pub simulation_truth: Option<IgnoredAny>,
}

/// The simulator's truth as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthJson {
    /// True probe vector, mm (the reference orientation's with a head).
    pub probe_vector_mm: [f64; 3],
    /// True tip radius, mm.
    pub tip_radius_mm: f64,
    /// The truth per head orientation, in the order of `orientations`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientations: Option<Vec<OrientationTruthJson>>,
}

#[derive(Serialize)]
struct Written<'a> {
    #[serde(flatten)]
    body: &'a ProbeCalFile,
    simulation_truth: Option<TruthJson>,
}

/// A calibration as the host uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeCalibration {
    /// The file it came from.
    pub source: PathBuf,
    /// Calibrated probe.
    pub probe: HostProbe,
}

/// Why a calibration file was rejected; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ProbeCalError {
    /// The file could not be read.
    #[error("{file}: cannot read probe calibration: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// Not JSON, or not of the file's shape.
    #[error(transparent)]
    Syntax(#[from] crate::jsonfile::JsonSyntaxError),
    /// Wrong `format` tag.
    #[error("{file}: $.format: unknown format '{found}', expected '{PROBE_CAL_FORMAT}'")]
    Format {
        /// The file.
        file: PathBuf,
        /// The tag found.
        found: String,
    },
    /// A value out of range.
    #[error("{file}: {json_path}: {value} must be {requirement}")]
    Invalid {
        /// The file.
        file: PathBuf,
        /// Where.
        json_path: String,
        /// The value found.
        value: f64,
        /// The requirement.
        requirement: &'static str,
    },
}

/// The file content of a calibration.
pub fn to_file(cal: &Calibration, opts: &CalibrationOptions) -> ProbeCalFile {
    let max_range = |f: fn(&ScanSummary) -> f64| cal.scans.iter().map(f).reduce(f64::max);
    ProbeCalFile {
        format: PROBE_CAL_FORMAT.into(),
        probe_vector_mm: cal.probe.probe_vector.into(),
        tip_radius_mm: cal.probe.tip_radius_mm,
        sphere_center_mm: cal.sphere_center_nominal_probe.coords.into(),
        probing_error_mm: cal.probing_error_mm,
        probing_error_before_mm: Some(cal.probing_error_before_mm),
        scanning_error_mm: max_range(|s| s.after.range_mm),
        scanning_error_before_mm: max_range(|s| s.before.range_mm),
        deflection_correction: Some(correction_json(&cal.probe.correction)),
        scans: cal.scans.clone(),
        conditions: Some(conditions(cal, opts)),
        head_axes: None,
        head_angles_deg: None,
        orientations: Vec::new(),
        simulation_truth: None,
    }
}

fn conditions(cal: &Calibration, opts: &CalibrationOptions) -> Conditions {
    Conditions {
        sphere_diameter_mm: opts.sphere_diameter_mm,
        sphere_position_mm: opts.sphere_center_mm.coords.into(),
        touch_points: super::pattern::iso_25_directions().len(),
        trigger_mm: opts.modes.trigger_mm,
        deflections_mm: opts.deflections_mm.clone(),
        directions: opts
            .directions
            .iter()
            .map(|&c| super::direction_name(c).to_string())
            .collect(),
        scan_speed_mm_s: opts.scan_speed_mm_s,
        gain_terms: cal.solved.gain_terms,
        fit_residual_rms_mm: cal.solved.residual_rms_mm,
    }
}

fn correction_json(c: &DeflectionCorrection) -> CorrectionJson {
    let dir = |p: &[DeflectionPoly; 2]| DirectionTilts {
        cw: p[0].to_vec(),
        ccw: p[1].to_vec(),
    };
    CorrectionJson {
        gain: c
            .gain
            .iter()
            .map(|m| [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]))
            .collect(),
        tilt_rad: PlaneTilts {
            yz: dir(&c.tilt[0]),
            xz: dir(&c.tilt[1]),
            xy: dir(&c.tilt[2]),
        },
    }
}

/// Pretty JSON of a calibration file with the simulation truth appended.
pub fn to_json(file: &ProbeCalFile, truth: Option<ProbeTruth>) -> String {
    let truth = truth.map(|t| TruthJson {
        probe_vector_mm: t.probe_vector.into(),
        tip_radius_mm: t.tip_radius_mm,
        orientations: None,
    });
    to_json_with_truth(file, truth)
}

/// Pretty JSON of a calibration file with the given truth appended.
pub fn to_json_with_truth(file: &ProbeCalFile, truth: Option<TruthJson>) -> String {
    let written = Written {
        body: file,
        simulation_truth: truth,
    };
    let mut text = serde_json::to_string_pretty(&written).unwrap_or_default();
    text.push('\n');
    text
}

impl ProbeCalibration {
    /// Reads and validates a calibration file.
    pub fn read(path: &Path) -> Result<ProbeCalibration, ProbeCalError> {
        let text = crate::jsonfile::read_text(path).map_err(|source| ProbeCalError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses calibration JSON; `path` names it in messages.
    pub fn parse(text: &str, path: &Path) -> Result<ProbeCalibration, ProbeCalError> {
        let file = parse_file(text, path)?;
        let check = Checker { file: path };
        if file.format != PROBE_CAL_FORMAT {
            return Err(ProbeCalError::Format {
                file: path.to_path_buf(),
                found: file.format,
            });
        }
        let probe = HostProbe {
            probe_vector: check.vector(file.probe_vector_mm, "$.probe_vector_mm")?,
            tip_radius_mm: check.positive(file.tip_radius_mm, "$.tip_radius_mm")?,
            correction: match &file.deflection_correction {
                Some(c) => check.correction(c)?,
                None => DeflectionCorrection::identity(),
            },
        };
        for (k, o) in file.orientations.iter().enumerate() {
            let at = format!("$.orientations[{k}]");
            check.vector(o.probe_vector_mm, &format!("{at}.probe_vector_mm"))?;
            check.positive(o.tip_radius_mm, &format!("{at}.tip_radius_mm"))?;
        }
        Ok(ProbeCalibration {
            source: path.to_path_buf(),
            probe,
        })
    }
}

fn parse_file(text: &str, path: &Path) -> Result<ProbeCalFile, ProbeCalError> {
    Ok(crate::jsonfile::parse_json(text, path)?)
}

struct Checker<'a> {
    file: &'a Path,
}

impl Checker<'_> {
    fn invalid(&self, json_path: String, value: f64, requirement: &'static str) -> ProbeCalError {
        ProbeCalError::Invalid {
            file: self.file.to_path_buf(),
            json_path,
            value,
            requirement,
        }
    }

    fn finite(&self, v: f64, path: impl Fn() -> String) -> Result<f64, ProbeCalError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.invalid(path(), v, "finite"))
        }
    }

    fn positive(&self, v: f64, path: &str) -> Result<f64, ProbeCalError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(path.into(), v, "finite and positive"))
        }
    }

    fn vector(&self, v: [f64; 3], path: &str) -> Result<Vec3, ProbeCalError> {
        for (i, x) in v.iter().enumerate() {
            self.finite(*x, || format!("{path}[{i}]"))?;
        }
        Ok(Vec3::from(v))
    }

    fn correction(&self, c: &CorrectionJson) -> Result<DeflectionCorrection, ProbeCalError> {
        let mut out = DeflectionCorrection::identity();
        self.count(c.gain.len(), "$.deflection_correction.gain")?;
        for ((k, m), slot) in c.gain.iter().enumerate().zip(out.gain.iter_mut()) {
            *slot = self.matrix(m, &format!("$.deflection_correction.gain[{k}]"))?;
        }
        let t = &c.tilt_rad;
        for ((name, plane), slot) in [("yz", &t.yz), ("xz", &t.xz), ("xy", &t.xy)]
            .into_iter()
            .zip(out.tilt.iter_mut())
        {
            let path = format!("$.deflection_correction.tilt_rad.{name}");
            *slot = [
                self.poly(&plane.cw, &format!("{path}.cw"))?,
                self.poly(&plane.ccw, &format!("{path}.ccw"))?,
            ];
        }
        Ok(out)
    }

    fn matrix(&self, m: &[[f64; 3]; 3], path: &str) -> Result<Mat3, ProbeCalError> {
        let mut out = Mat3::zeros();
        for (i, row) in m.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                out[(i, j)] = self.finite(*v, || format!("{path}[{i}][{j}]"))?;
            }
        }
        Ok(out)
    }

    fn count(&self, n: usize, path: &str) -> Result<(), ProbeCalError> {
        if n <= CORRECTION_TERMS {
            Ok(())
        } else {
            Err(self.invalid(path.into(), n as f64, "at most 3 terms long"))
        }
    }

    fn poly(&self, p: &[f64], path: &str) -> Result<DeflectionPoly, ProbeCalError> {
        self.count(p.len(), path)?;
        let mut out = [0.0; CORRECTION_TERMS];
        for (i, (slot, v)) in out.iter_mut().zip(p).enumerate() {
            *slot = self.finite(*v, || format!("{path}[{i}]"))?;
        }
        Ok(out)
    }
}
