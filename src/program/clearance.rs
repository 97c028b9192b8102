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

/// The posture margin a program gets when it sets none, for a ball of
/// radius `tip` on a shaft of radius `shaft` (mm): the default, or half
/// the gap the shaft keeps from a wall the ball touches at its equator
/// (the ball radius less the shaft radius) when that is less, so that a
/// small ball's touches are not all called shaft strikes.
pub(super) fn default_posture_margin(tip: f64, shaft: f64) -> f64 {
    let default = ClearanceMargins::default().posture_margin_mm;
    let half = 0.5 * (tip - shaft);
    if half > 0.0 {
        default.min(half)
    } else {
        default
    }
}

/// The margins of `spec` (defaults for what it leaves out, the posture
/// margin's for the ball and shaft radii `probe`, mm), checked: each
/// finite and in `(0, MAX_MARGIN_MM]`, the tight margin at most the full
/// one.
pub(super) fn margins(
    spec: Option<&ClearanceSpec>,
    file: &Path,
    (tip, shaft): (f64, f64),
) -> Result<ClearanceMargins, ProgramError> {
    let d = ClearanceMargins {
        posture_margin_mm: default_posture_margin(tip, shaft),
        ..ClearanceMargins::default()
    };
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The default posture margin: 0.1 mm for a 2 mm ball on a 1 mm shaft
    /// (gap 0.5), half the gap for a 0.3 mm ball on a 0.15 mm shaft (gap
    /// 0.075), and a margin the program sets is kept as it is.
    #[test]
    fn the_default_posture_margin_follows_a_small_balls_gap() {
        assert_eq!(default_posture_margin(1.0, 0.5), 0.1);
        assert!((default_posture_margin(0.15, 0.075) - 0.0375).abs() < 1e-15);
        assert_eq!(default_posture_margin(0.5, 0.5), 0.1);
        let file = Path::new("p.json");
        let m = margins(None, file, (0.15, 0.075)).unwrap();
        assert!((m.posture_margin_mm - 0.0375).abs() < 1e-15);
        let spec = ClearanceSpec {
            posture_margin_mm: Some(0.2),
            ..ClearanceSpec::default()
        };
        let m = margins(Some(&spec), file, (0.15, 0.075)).unwrap();
        assert_eq!(m.posture_margin_mm, 0.2);
    }
}
