//! Validation of an `as_machined` block into the model's parts: the
//! transform and the form terms with the faces they act on.
use super::form::Form;
use super::AsMachinedError;
use crate::formats::as_machined::{FormTerm, Scale, TransformSpec};
use crate::math::{rotation_xyz_deg, Mat3, Point3, Vec3, MAX_ROTATION_DEG};
use crate::workpiece::Workpiece;

/// A validation error at `path` (relative to the `as_machined` block).
pub(super) fn err(path: impl Into<String>, reason: impl Into<String>) -> AsMachinedError {
    AsMachinedError {
        json_path: path.into(),
        reason: reason.into(),
    }
}

fn finite3(v: [f64; 3], path: &str) -> Result<Vec3, AsMachinedError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(Vec3::from(v))
    } else {
        Err(err(path, format!("{v:?} must be finite")))
    }
}

/// The validated transform as `(L, t)` of `T(x) = L x + t`.
pub(super) fn transform(t: &TransformSpec) -> Result<(Mat3, Vec3), AsMachinedError> {
    let tr = finite3(t.translate_mm, "transform.translate_mm")?;
    let deg = finite3(t.rotate_deg, "transform.rotate_deg")?;
    if deg.amax() > MAX_ROTATION_DEG {
        return Err(err(
            "transform.rotate_deg",
            format!(
                "{:?}: angles must lie within +-{MAX_ROTATION_DEG} degrees",
                t.rotate_deg
            ),
        ));
    }
    let rot = rotation_xyz_deg(deg.into());
    let c = finite3(t.about_mm, "transform.about_mm")?;
    let s = t.scale.map_or([1.0; 3], Scale::factors);
    if !s.iter().all(|k| k.is_finite() && *k > 0.0) {
        return Err(err(
            "transform.scale",
            format!("{s:?}: scale factors must be finite and positive"),
        ));
    }
    let linear = rot * Mat3::from_diagonal(&Vec3::from(s));
    Ok((linear, c + tr - linear * c))
}

fn positive(v: f64, path: String) -> Result<f64, AsMachinedError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(err(path, format!("{v} must be finite and positive")))
    }
}

fn finite(v: f64, path: String) -> Result<f64, AsMachinedError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(path, format!("{v} must be finite")))
    }
}

/// Form term `i` validated.
pub(super) fn form_of(t: &FormTerm, i: usize) -> Result<Form, AsMachinedError> {
    let at = |k: &str| format!("form[{i}].{k}");
    Ok(match t {
        FormTerm::Offset { mm, .. } => Form::Offset(finite(*mm, at("mm"))?),
        FormTerm::Bump {
            center_mm,
            radius_mm,
            height_mm,
            ..
        } => Form::Bump {
            center: Point3::from(finite3(*center_mm, &at("center_mm"))?),
            radius: positive(*radius_mm, at("radius_mm"))?,
            height: finite(*height_mm, at("height_mm"))?,
        },
        FormTerm::Waviness {
            amplitude_mm,
            wavelength_mm,
            direction,
            phase_deg,
            ..
        } => Form::Waviness {
            amplitude: finite(*amplitude_mm, at("amplitude_mm"))?,
            wavenumber: std::f64::consts::TAU / positive(*wavelength_mm, at("wavelength_mm"))?,
            direction: finite3(*direction, &at("direction"))?
                .try_normalize(1e-12)
                .ok_or_else(|| err(at("direction"), "direction must not be the zero vector"))?,
            phase: finite(*phase_deg, at("phase_deg"))?.to_radians(),
        },
    })
}

/// The faces form term `i` acts on (`None` = all), by surface name.
pub(super) fn faces_of(
    t: &FormTerm,
    i: usize,
    wp: &Workpiece,
) -> Result<Option<Vec<usize>>, AsMachinedError> {
    let Some(names) = t.surfaces() else {
        return Ok(None);
    };
    names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            wp.face_index(n).ok_or_else(|| {
                err(
                    format!("form[{i}].surfaces[{k}]"),
                    format!("no surface named '{n}' in the workpiece"),
                )
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}
