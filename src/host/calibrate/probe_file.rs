//! The nominal probe of `cmm calibrate-probe --probe FILE`: a JSON file
//! holding a part program's `probe` block (`{"tip_diameter_mm": 3,
//! "stylus_length_mm": 50}`), or a whole part program, whose `probe` block
//! is used (its other keys are not read here).
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::jsonfile::{parse_json, JsonSyntaxError};
use crate::program::format::ProbeSpec;

/// Largest tip diameter accepted, mm.
pub const MAX_TIP_DIAMETER_MM: f64 = 50.0;
/// Largest stylus length accepted, mm.
pub const MAX_STYLUS_LENGTH_MM: f64 = 1000.0;

/// Nominal probe dimensions, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NominalProbe {
    /// Tip (ball) diameter, mm.
    pub tip_diameter_mm: f64,
    /// Stylus length, mm.
    pub stylus_length_mm: f64,
    /// Stylus shaft diameter, mm (`None`: half the tip's, the part
    /// program's default).
    pub shaft_diameter_mm: Option<f64>,
}

/// Why a probe file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ProbeFileError {
    /// The file could not be read.
    #[error("{}: cannot read: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// Not JSON, or keys and types that do not fit.
    #[error(transparent)]
    Syntax(#[from] JsonSyntaxError),
    /// A dimension out of range.
    #[error("{}: {json_path}: {value} must be a finite number in (0, {max}] mm", file.display())]
    Value {
        /// The file.
        file: PathBuf,
        /// JSON path of the value.
        json_path: String,
        /// The value found, mm.
        value: f64,
        /// Largest value accepted, mm.
        max: f64,
    },
}

/// A part program, read only for its probe block.
#[derive(Deserialize)]
struct ProgramProbe {
    probe: ProbeSpec,
}

/// Reads and checks a probe file.
pub fn read_probe_file(path: &Path) -> Result<NominalProbe, ProbeFileError> {
    let text = crate::jsonfile::read_text(path).map_err(|source| ProbeFileError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let value: serde_json::Value = parse_json(&text, path)?;
    let (spec, prefix) = if value.get("probe").is_some() {
        (parse_json::<ProgramProbe>(&text, path)?.probe, "$.probe")
    } else {
        (parse_json::<ProbeSpec>(&text, path)?, "$")
    };
    let check = |value: f64, key: &str, max: f64| {
        if value.is_finite() && value > 0.0 && value <= max {
            Ok(value)
        } else {
            Err(ProbeFileError::Value {
                file: path.to_path_buf(),
                json_path: format!("{prefix}.{key}"),
                value,
                max,
            })
        }
    };
    let tip = check(spec.tip_diameter_mm, "tip_diameter_mm", MAX_TIP_DIAMETER_MM)?;
    // A shaft thicker than the ball would touch before it.
    let shaft = (spec.shaft_diameter_mm)
        .map(|d| check(d, "shaft_diameter_mm", tip))
        .transpose()?;
    Ok(NominalProbe {
        tip_diameter_mm: tip,
        stylus_length_mm: check(
            spec.stylus_length_mm,
            "stylus_length_mm",
            MAX_STYLUS_LENGTH_MM,
        )?,
        shaft_diameter_mm: shaft,
    })
}
