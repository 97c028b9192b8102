//! Per head orientation entries of `cmm-probe-cal/1` (added keys; the
//! top-level keys of the cmm-probe-cal/1 format keep meaning the reference orientation).
//!
//! ```json
//! "orientations": [
//!   { "head_angles_deg": [0, 0], "method": "reference", "points": 25,
//!     "probe_vector_mm": [..], "tip_radius_mm": r, "sphere_center_mm": [..] },
//!   { "head_angles_deg": [90, 0], "method": "predicted", "points": 4,
//!     "probe_vector_mm": [..], "tip_radius_mm": r, "sphere_center_mm": [..],
//!     "predicted_probe_vector_mm": [..], "predicted_center_scales_mm": [..],
//!     "inverse_iterations": 2, "form_mm": 0.0, "head_readings_deg": [..] } ]
//! ```
//! `sphere_center_mm` is the sphere's centre as measured with the probe
//! vector used while measuring (nominal at the reference, predicted at the
//! others); `predicted_center_scales_mm` is the scale position at which the
//! predicted ball sits on the sphere's known centre (iterative inverse).
use serde::{Deserialize, Serialize};

use super::file::{to_file, ProbeCalFile, TruthJson};
use super::orientation::{HeadCalibration, OrientationResult};
use super::CalibrationOptions;
use crate::formats::probe_truth::OrientationTruth;

/// One orientation as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationJson {
    /// Head angles, deg, in the order of `head_axes`.
    pub head_angles_deg: Vec<f64>,
    /// `reference` (full calibration) or `predicted` (few points from the
    /// predicted centre).
    pub method: String,
    /// Points measured on the sphere.
    pub points: usize,
    /// Calibrated probe vector, mm.
    pub probe_vector_mm: [f64; 3],
    /// Effective tip radius, mm.
    pub tip_radius_mm: f64,
    /// Sphere centre seen with the probe vector used while measuring, mm.
    pub sphere_center_mm: [f64; 3],
    /// Probe vector predicted by the nominal head model, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_probe_vector_mm: Option<[f64; 3]>,
    /// Scale position putting the predicted ball on the sphere centre, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_center_scales_mm: Option<[f64; 3]>,
    /// Iterations of the inverse correction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inverse_iterations: Option<usize>,
    /// Range of the residuals from the fitted sphere, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form_mm: Option<f64>,
    /// Head encoder readings after indexing, deg (chain order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub head_readings_deg: Option<Vec<f64>>,
}

/// One orientation's truth as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrientationTruthJson {
    /// Head angles, deg.
    pub head_angles_deg: Vec<f64>,
    /// True probe vector, mm.
    pub probe_vector_mm: [f64; 3],
    /// True tip radius, mm.
    pub tip_radius_mm: f64,
}

/// The file content of a calibration on a head.
pub fn head_file(
    cal: &HeadCalibration,
    axes: &[String],
    opts: &CalibrationOptions,
) -> ProbeCalFile {
    let mut file = to_file(&cal.reference, opts);
    file.head_axes = Some(axes.to_vec());
    file.head_angles_deg = Some(cal.reference_angles_deg.clone());
    let r = &cal.reference;
    let reference = OrientationJson {
        head_angles_deg: cal.reference_angles_deg.clone(),
        method: "reference".into(),
        points: super::pattern::iso_25_directions().len(),
        probe_vector_mm: r.probe.probe_vector.into(),
        tip_radius_mm: r.probe.tip_radius_mm,
        sphere_center_mm: r.sphere_center_nominal_probe.coords.into(),
        predicted_probe_vector_mm: None,
        predicted_center_scales_mm: None,
        inverse_iterations: None,
        form_mm: None,
        head_readings_deg: None,
    };
    file.orientations = std::iter::once(reference)
        .chain(cal.orientations.iter().map(orientation_json))
        .collect();
    file
}

fn orientation_json(o: &OrientationResult) -> OrientationJson {
    OrientationJson {
        head_angles_deg: o.angles_deg.clone(),
        method: "predicted".into(),
        points: o.points,
        probe_vector_mm: o.probe.probe_vector.into(),
        tip_radius_mm: o.probe.tip_radius_mm,
        sphere_center_mm: o.sphere_center_predicted_probe.coords.into(),
        predicted_probe_vector_mm: Some(o.predicted_probe_vector.into()),
        predicted_center_scales_mm: Some(o.predicted_center_scales.coords.into()),
        inverse_iterations: Some(o.inverse_iterations),
        form_mm: Some(o.form_mm),
        head_readings_deg: Some(o.head_readings_rad.iter().map(|a| a.to_degrees()).collect()),
    }
}

/// The simulation truth of a head calibration (reference first).
pub fn head_truth(truth: &[OrientationTruth]) -> Option<TruthJson> {
    let first = truth.first()?;
    Some(TruthJson {
        probe_vector_mm: first.probe_vector.into(),
        tip_radius_mm: first.tip_radius_mm,
        orientations: Some(
            truth
                .iter()
                .map(|t| OrientationTruthJson {
                    head_angles_deg: t.angles_deg.clone(),
                    probe_vector_mm: t.probe_vector.into(),
                    tip_radius_mm: t.tip_radius_mm,
                })
                .collect(),
        ),
    })
}
