//! Validation of `cmm-workpiece/1` files, with JSON paths in every message.
use std::path::Path;

use super::format::{SurfaceSpec, TrimSpec, WorkpieceFile, WORKPIECE_FORMAT};
use super::WorkpieceError;
use crate::geometry::{KnotError, NurbsError, NurbsSurface};

/// Parses JSON text into the file types, reporting the JSON path on error.
pub(super) fn parse(text: &str, file: &Path) -> Result<WorkpieceFile, WorkpieceError> {
    Ok(crate::jsonfile::parse_json(text, file)?)
}

fn invalid(file: &Path, json_path: String, reason: impl Into<String>) -> WorkpieceError {
    WorkpieceError::Invalid {
        file: file.to_path_buf(),
        json_path,
        reason: reason.into(),
    }
}

/// Format tag, units, non-empty and uniquely named surfaces.
pub(super) fn check_header(wp: &WorkpieceFile, file: &Path) -> Result<(), WorkpieceError> {
    if wp.format != WORKPIECE_FORMAT {
        let reason = format!(
            "unknown format '{}', expected '{WORKPIECE_FORMAT}'",
            wp.format
        );
        return Err(invalid(file, "$.format".into(), reason));
    }
    if wp.units != "mm" {
        return Err(invalid(
            file,
            "$.units".into(),
            format!("unsupported units '{}', expected 'mm'", wp.units),
        ));
    }
    if wp.surfaces.is_empty() {
        return Err(invalid(
            file,
            "$.surfaces".into(),
            "no surfaces: at least one is required",
        ));
    }
    for (i, s) in wp.surfaces.iter().enumerate() {
        if s.name.trim().is_empty() {
            return Err(invalid(
                file,
                format!("$.surfaces[{i}].name"),
                "surface name is empty",
            ));
        }
        if let Some(first) = wp.surfaces[..i].iter().position(|o| o.name == s.name) {
            let reason = format!(
                "duplicate surface name '{}' (also surfaces[{first}])",
                s.name
            );
            return Err(invalid(file, format!("$.surfaces[{i}].name"), reason));
        }
    }
    Ok(())
}

/// Builds surface `i`, translating geometry errors into JSON paths.
pub(super) fn surface(
    spec: &SurfaceSpec,
    i: usize,
    file: &Path,
) -> Result<NurbsSurface, WorkpieceError> {
    let base = format!("$.surfaces[{i}]");
    let surface = spec.to_surface().map_err(|e| {
        let (path, reason) = locate(&e, &base);
        invalid(file, path, reason)
    })?;
    if let Some(trim) = &spec.trim {
        check_trim(trim, &surface, &base).map_err(|(p, r)| invalid(file, p, r))?;
    }
    Ok(surface)
}

fn locate(err: &NurbsError, base: &str) -> (String, String) {
    match err {
        NurbsError::Knots { dir, source } => (knot_path(base, dir, source), source.to_string()),
        NurbsError::Count {
            dir,
            expected,
            found,
        } => (
            format!("{base}.{dir}"),
            format!("expected {expected} entries (from the knots and degree), found {found}"),
        ),
        NurbsError::NotFinite { index } => (
            format!("{base}.control_points{}", brackets(index)),
            err.to_string(),
        ),
        NurbsError::Weight { index, value } => (
            format!("{base}.weights{}", brackets(index)),
            format!("weight {value} must be finite and positive"),
        ),
    }
}

fn knot_path(base: &str, dir: &str, e: &KnotError) -> String {
    match e {
        KnotError::DegreeZero | KnotError::DegreeTooHigh { .. } => {
            format!("{base}.degree[{}]", if dir == "u" { 0 } else { 1 })
        }
        KnotError::NotFinite { index }
        | KnotError::Decreasing { index, .. }
        | KnotError::Multiplicity { index, .. } => {
            format!("{base}.knots_{dir}[{index}]")
        }
        KnotError::TooFew { .. } | KnotError::EmptyDomain { .. } => format!("{base}.knots_{dir}"),
    }
}

fn brackets(index: &[usize]) -> String {
    index.iter().map(|i| format!("[{i}]")).collect()
}

type Located = (String, String);

fn check_trim(trim: &TrimSpec, s: &NurbsSurface, base: &str) -> Result<(), Located> {
    check_loop(&trim.outer, s, format!("{base}.trim.outer"))?;
    for (h, hole) in trim.holes.iter().enumerate() {
        check_loop(hole, s, format!("{base}.trim.holes[{h}]"))?;
    }
    Ok(())
}

/// Slack allowed for trim vertices outside the domain, relative to its size.
const TRIM_DOMAIN_SLACK: f64 = 1e-6;

fn check_loop(points: &[[f64; 2]], s: &NurbsSurface, path: String) -> Result<(), Located> {
    if points.len() < 3 {
        return Err((
            path,
            format!(
                "a trim loop needs at least 3 points, found {}",
                points.len()
            ),
        ));
    }
    let ((u0, u1), (v0, v1)) = s.domain();
    let (su, sv) = ((u1 - u0) * TRIM_DOMAIN_SLACK, (v1 - v0) * TRIM_DOMAIN_SLACK);
    for (k, [u, v]) in points.iter().enumerate() {
        let inside = (u0 - su..=u1 + su).contains(u) && (v0 - sv..=v1 + sv).contains(v);
        if !inside {
            let reason =
                format!("({u}, {v}) lies outside the parameter domain [{u0}, {u1}] x [{v0}, {v1}]");
            return Err((format!("{path}[{k}]"), reason));
        }
    }
    Ok(())
}
