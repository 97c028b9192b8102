//! The program's clearance margins: how far every move that is not a
//! measuring move keeps the probe from the design data.
use super::format::ClearanceSpec;
use super::ProgramError;
use std::path::Path;

/// Largest clearance margin accepted, mm.
pub const MAX_MARGIN_MM: f64 = 100.0;

/// Clearance margins, mm (see [`ClearanceSpec`] for their meaning).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceMargins {
    /// Free distance of positioning moves, approaches and retracts.
    pub margin_mm: f64,
    /// The smaller margin into narrow openings.
    pub tight_margin_mm: f64,
    /// Free distance of the shaft and the body while measuring.
    pub posture_margin_mm: f64,
}

impl Default for ClearanceMargins {
    fn default() -> Self {
        ClearanceMargins {
            margin_mm: 4.0,
            tight_margin_mm: 1.0,
            posture_margin_mm: 0.1,
        }
    }
}

/// The margins of `spec` (defaults for what it leaves out), checked:
/// each finite and in `(0, MAX_MARGIN_MM]`, the tight margin at most the
/// full one.
pub(super) fn margins(
    spec: Option<&ClearanceSpec>,
    file: &Path,
) -> Result<ClearanceMargins, ProgramError> {
    let d = ClearanceMargins::default();
    let Some(spec) = spec else {
        return Ok(d);
    };
    let err = |key: &str, reason: String| ProgramError::Invalid {
        file: file.to_path_buf(),
        json_path: format!("$.clearance.{key}"),
        reason,
    };
    let pick = |v: Option<f64>, default: f64, key: &str| {
        let v = v.unwrap_or(default);
        if v.is_finite() && v > 0.0 && v <= MAX_MARGIN_MM {
            Ok(v)
        } else {
            Err(err(
                key,
                format!("{v} must be a finite number in (0, {MAX_MARGIN_MM}] mm"),
            ))
        }
    };
    let m = ClearanceMargins {
        margin_mm: pick(spec.margin_mm, d.margin_mm, "margin_mm")?,
        tight_margin_mm: pick(spec.tight_margin_mm, d.tight_margin_mm, "tight_margin_mm")?,
        posture_margin_mm: pick(
            spec.posture_margin_mm,
            d.posture_margin_mm,
            "posture_margin_mm",
        )?,
    };
    if m.tight_margin_mm > m.margin_mm {
        let reason = format!(
            "{} must not exceed margin_mm ({})",
            m.tight_margin_mm, m.margin_mm
        );
        return Err(err("tight_margin_mm", reason));
    }
    Ok(m)
}
