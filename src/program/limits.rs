//! Bounds on the size and the numbers of a part program, checked before
//! anything is computed from it, so that a mistyped or hostile file is
//! refused with its JSON path instead of running for minutes or filling
//! the memory.
use std::path::Path;

use super::format::{FeatureSpec, ProgramFile};
use super::ProgramError;
use crate::formats::as_machined::AsMachinedSpec;

/// Most features in one program.
pub const MAX_FEATURES: usize = 10_000;
/// Most touch or alignment points in one list.
pub const MAX_POINTS: usize = 100_000;
/// Most form terms of an as-machined part (each costs on every contact
/// of the simulation; real deviations need a handful).
pub const MAX_FORM_TERMS: usize = 1_000;
/// Largest magnitude of a tolerance limit, mm: beyond any CMM's travel,
/// so a limit like `1.797e308` (meant as "no limit") is refused.
pub const MAX_TOLERANCE_MM: f64 = 10_000.0;

fn invalid(file: &Path, json_path: String, reason: String) -> ProgramError {
    ProgramError::Invalid {
        file: file.to_path_buf(),
        json_path,
        reason,
    }
}

/// Checks the program's counts, tolerance magnitudes and surface lists
/// (a surface named twice in one list is refused: it would be scanned
/// twice).
pub(super) fn check_program(spec: &ProgramFile, file: &Path) -> Result<(), ProgramError> {
    if spec.features.len() > MAX_FEATURES {
        let reason = format!(
            "{} features, at most {MAX_FEATURES} accepted",
            spec.features.len()
        );
        return Err(invalid(file, "$.features".into(), reason));
    }
    for (i, f) in spec.features.iter().enumerate() {
        let base = format!("$.features[{i}]");
        let (surfaces, tolerance, points) = match f {
            FeatureSpec::SectionScan {
                surfaces,
                tolerance_mm,
                ..
            } => (surfaces, tolerance_mm, None),
            FeatureSpec::TouchPoints {
                surfaces,
                tolerance_mm,
                points_mm,
                ..
            } => (surfaces, tolerance_mm, Some(points_mm.len())),
        };
        check_count(
            file,
            points.unwrap_or(0),
            MAX_POINTS,
            &format!("{base}.points_mm"),
        )?;
        check_surface_list(file, surfaces.as_deref(), &format!("{base}.surfaces"))?;
        for (k, limit) in tolerance.iter().enumerate() {
            if limit.abs() > MAX_TOLERANCE_MM {
                let reason =
                    format!("{limit} mm: a tolerance limit must lie within ±{MAX_TOLERANCE_MM} mm");
                return Err(invalid(file, format!("{base}.tolerance_mm[{k}]"), reason));
            }
        }
    }
    if let Some(a) = &spec.alignment {
        check_count(file, a.points_mm.len(), MAX_POINTS, "$.alignment.points_mm")?;
        check_surface_list(file, a.surfaces.as_deref(), "$.alignment.surfaces")?;
    }
    if let Some(a) = &spec.as_machined {
        check_as_machined(a, file, "$.as_machined")?;
    }
    Ok(())
}

/// Checks an as-machined part: at most [`MAX_FORM_TERMS`] terms, no
/// surface named twice in a term. `base` is its JSON path.
pub fn check_as_machined(
    spec: &AsMachinedSpec,
    file: &Path,
    base: &str,
) -> Result<(), ProgramError> {
    check_count(
        file,
        spec.form.len(),
        MAX_FORM_TERMS,
        &format!("{base}.form"),
    )?;
    for (k, term) in spec.form.iter().enumerate() {
        check_surface_list(file, term.surfaces(), &format!("{base}.form[{k}].surfaces"))?;
    }
    Ok(())
}

fn check_count(file: &Path, n: usize, max: usize, path: &str) -> Result<(), ProgramError> {
    if n > max {
        let reason = format!("{n} entries, at most {max} accepted");
        return Err(invalid(file, path.into(), reason));
    }
    Ok(())
}

fn check_surface_list(
    file: &Path,
    names: Option<&[String]>,
    path: &str,
) -> Result<(), ProgramError> {
    let Some(names) = names else { return Ok(()) };
    let mut seen = std::collections::HashMap::new();
    for (k, name) in names.iter().enumerate() {
        if let Some(first) = seen.insert(name.as_str(), k) {
            let reason = format!("surface '{name}' is listed twice (also at [{first}])");
            return Err(invalid(file, format!("{path}[{k}]"), reason));
        }
    }
    Ok(())
}

/// Height of the run's start above the part's highest control point (plus
/// the tip radius), mm: the clearance the measuring run starts at.
pub const START_CLEARANCE_MM: f64 = 10.0;

/// Where a measuring run starts: the ball centre over the middle of the
/// part's control points, [`START_CLEARANCE_MM`] above the highest one
/// (plus the tip radius), machine coordinates, mm; and that height, the
/// clearance height of moves between measurements.
pub fn start_position(program: &super::Program) -> (crate::math::Point3, f64) {
    use crate::math::{Point3, Vec3};
    let pts: Vec<Point3> = program
        .workpiece
        .faces
        .iter()
        .flat_map(|f| {
            f.surface
                .homogeneous_points()
                .iter()
                .map(|p| Point3::new(p.x / p.w, p.y / p.w, p.z / p.w))
        })
        .map(|p| program.placement.to_machine(p))
        .collect();
    let n = pts.len().max(1) as f64;
    let centre = pts.iter().fold(Vec3::zeros(), |a, p| a + p.coords) / n;
    let top = pts.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max)
        + program.probe.tip_radius_mm
        + START_CLEARANCE_MM;
    (Point3::new(centre.x, centre.y, top), top)
}

/// The run starts at [`start_position`] with the stylus vertical (a head
/// at rest): ball and probe mount must both lie inside the travel `[lo, hi]` (machine
/// coordinates, mm), else the machine cannot start.
pub(super) fn check_start(
    program: &super::Program,
    lo: [f64; 3],
    hi: [f64; 3],
) -> Result<(), ProgramError> {
    use crate::math::Point3;
    let (ball, _) = start_position(program);
    let stylus_top = ball - program.probe_vector();
    let inside = |q: Point3| (0..3).all(|k| q[k] >= lo[k] && q[k] <= hi[k]);
    if inside(ball) && inside(stylus_top) {
        return Ok(());
    }
    let reason = format!(
        "the run would start with the ball at ({:.3}, {:.3}, {:.3}) mm and the stylus top at z = {:.3} mm \
         ({START_CLEARANCE_MM} mm over the part), outside the machine's travel {lo:?} .. {hi:?} mm: \
         move the part or use a shorter stylus ($.probe.stylus_length_mm = {} mm)",
        ball.x, ball.y, ball.z, stylus_top.z, program.probe.stylus_length_mm
    );
    Err(invalid(&program.file, "$.placement".into(), reason))
}
