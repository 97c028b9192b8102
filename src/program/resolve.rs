//! From a program file to a validated [`Program`].
use std::path::{Path, PathBuf};

use super::format::{FeatureSpec, ProgramFile, PROGRAM_FORMAT};
use super::{Feature, NominalPoint, Pose, ProbeSetup, Program, ProgramError, ScanSettings};
use crate::formats::as_machined::AsMachinedSpec;
use crate::geometry::{Plane, SectionOptions};
use crate::machine::MachineModel;
use crate::math::{rotation_xyz_deg, Point3, Vec3, MAX_ROTATION_DEG};
use crate::workpiece::section_faces;
use crate::workpiece::Workpiece;

use super::machine::Travel;
use super::machine::{nominal_machine, MachineFiles};

/// Largest distance from a touch point's given position to the design data, mm.
const TOUCH_POINT_REACH_MM: f64 = 1.0;
/// Largest deflection any probe mode may ask for, mm.
const MAX_DEFLECTION_MM: f64 = 1.0;
/// Largest scanning speed accepted, mm/s.
const MAX_SPEED_MM_S: f64 = 500.0;

struct Ctx<'a> {
    file: &'a Path,
}

impl Ctx<'_> {
    fn err(&self, path: impl Into<String>, reason: impl Into<String>) -> ProgramError {
        ProgramError::Invalid {
            file: self.file.to_path_buf(),
            json_path: path.into(),
            reason: reason.into(),
        }
    }

    fn positive(&self, v: f64, max: f64, path: String) -> Result<f64, ProgramError> {
        if v.is_finite() && v > 0.0 && v <= max {
            Ok(v)
        } else {
            Err(self.err(path, format!("{v} must be a finite number in (0, {max}]")))
        }
    }

    fn finite3(&self, v: [f64; 3], path: String) -> Result<Vec3, ProgramError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vec3::from(v))
        } else {
            Err(self.err(path, format!("{v:?} must be finite")))
        }
    }
}

/// Reads and validates a part program and everything it refers to: the
/// measuring side's view.
pub fn load(file: &Path) -> Result<Program, ProgramError> {
    read(file).map(|(program, _)| program)
}

/// [`load`], and apart from the program the simulated scenario it names
/// (the `as_machined` block, as written; the nominal part when absent).
/// Only the application layer that builds a simulated world reads the
/// scenario.
pub fn read(file: &Path) -> Result<(Program, AsMachinedSpec), ProgramError> {
    read_on(file, &MachineFiles::default()).map(|(p, s)| (p, s.as_machined))
}

/// What a program names for the simulation only (never given to the
/// measuring side).
#[derive(Debug, Clone, Default)]
pub struct ScenarioSpec {
    /// The `as_machined` block, as written (the nominal part when absent).
    pub as_machined: AsMachinedSpec,
    /// The machine profile: the command line's, else the program's
    /// `machine_profile` (resolved beside the program), else none.
    pub machine_profile: Option<ProfileSource>,
}

/// Where a machine profile comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum ProfileSource {
    /// The program's `machine_profile` key, resolved beside the program.
    Program(PathBuf),
    /// The command line.
    CommandLine(PathBuf),
}

/// [`read`] on the machine files `files` names (each overrides the
/// program's key).
pub fn read_on(file: &Path, files: &MachineFiles) -> Result<(Program, ScenarioSpec), ProgramError> {
    let text = crate::jsonfile::read_text(file).map_err(|source| ProgramError::Io {
        file: file.to_path_buf(),
        source,
    })?;
    let spec = parse(&text, file)?;
    let machine = nominal_machine(spec.machine.as_deref(), file, files)?;
    let program = resolve(&spec, file, machine)?;
    let machine_profile = match (&files.profile, &spec.machine_profile) {
        (Some(p), _) => Some(ProfileSource::CommandLine(p.clone())),
        (None, Some(key)) => Some(ProfileSource::Program(relative_to(file, key))),
        (None, None) => None,
    };
    let scenario = ScenarioSpec {
        as_machined: spec.as_machined.unwrap_or_default(),
        machine_profile,
    };
    Ok((program, scenario))
}

fn parse(text: &str, file: &Path) -> Result<ProgramFile, ProgramError> {
    Ok(crate::jsonfile::parse_json(text, file)?)
}

/// Validates a parsed program on the nominal `machine`; `file` locates
/// relative paths and messages.
pub fn resolve(
    spec: &ProgramFile,
    file: &Path,
    machine: MachineModel,
) -> Result<Program, ProgramError> {
    let cx = Ctx { file };
    super::limits::check_program(spec, file)?;
    check_header(&cx, spec)?;
    let workpiece = load_workpiece(&cx, spec)?;
    let placement = placement(&cx, spec)?;
    let probe = probe(&cx, spec)?;
    check_defaults(&cx, spec)?;
    let features = spec
        .features
        .iter()
        .enumerate()
        .map(|(i, f)| feature(&cx, spec, &workpiece, &probe, f, i))
        .collect::<Result<Vec<_>, _>>()?;
    let alignment = match &spec.alignment {
        Some(a) => Some(alignment_points(&cx, &workpiece, a)?),
        None => None,
    };
    let clearance = super::clearance::margins(
        spec.clearance.as_ref(),
        file,
        (probe.tip_radius_mm, probe.shaft_radius_mm),
    )?;
    let program = Program {
        alignment,
        name: spec.name.clone(),
        file: file.to_path_buf(),
        workpiece,
        placement,
        probe,
        features,
        machine,
        clearance,
    };
    check_reach(&cx, &program, &Travel::of(&program.machine))?;
    check_fits(&cx, &program)?;
    Ok(program)
}

/// Every fit the program asks for can be made from its nominal points (a
/// sphere from four coplanar touch points cannot, nor a cylinder from one
/// section's circle): else an error at the feature's `fit`, before
/// anything is measured.
fn check_fits(cx: &Ctx, program: &Program) -> Result<(), ProgramError> {
    use crate::fit::{fit, FitOptions, Method};
    for (i, f) in program.features.iter().enumerate() {
        let Some(spec) = f.fit() else {
            continue;
        };
        let points: Vec<Point3> = match f {
            Feature::Section { curves, .. } => (curves.iter())
                .flat_map(|c| c.points.iter().map(|p| p.point))
                .collect(),
            Feature::Touch { points, .. } => points.iter().map(|p| p.point).collect(),
        };
        let opts = FitOptions::default();
        if let Err(e) = fit(spec.element.kind(), Method::Lsq, &points, &opts) {
            return Err(cx.err(format!("$.features[{i}].fit"), e.to_string()));
        }
    }
    Ok(())
}

fn check_header(cx: &Ctx, spec: &ProgramFile) -> Result<(), ProgramError> {
    if spec.format != PROGRAM_FORMAT {
        return Err(cx.err(
            "$.format",
            format!(
                "unknown format '{}', expected '{PROGRAM_FORMAT}'",
                spec.format
            ),
        ));
    }
    if spec.name.trim().is_empty() {
        return Err(cx.err("$.name", "program name is empty"));
    }
    if spec.features.is_empty() {
        return Err(cx.err("$.features", "no features: at least one is required"));
    }
    for (i, f) in spec.features.iter().enumerate() {
        if f.name().trim().is_empty() {
            return Err(cx.err(format!("$.features[{i}].name"), "feature name is empty"));
        }
        if let Some(first) = spec.features[..i].iter().position(|o| o.name() == f.name()) {
            return Err(cx.err(
                format!("$.features[{i}].name"),
                format!(
                    "duplicate feature name '{}' (also features[{first}])",
                    f.name()
                ),
            ));
        }
    }
    Ok(())
}

/// A path in the program, relative to the program's folder.
pub fn relative_to(file: &Path, rel: &str) -> PathBuf {
    file.parent()
        .map_or_else(|| PathBuf::from(rel), |dir| dir.join(rel))
}

fn load_workpiece(cx: &Ctx, spec: &ProgramFile) -> Result<Workpiece, ProgramError> {
    let path = relative_to(cx.file, &spec.workpiece);
    if let Some(problem) = crate::jsonfile::file_problem(&path) {
        return Err(cx.err(
            "$.workpiece",
            format!("workpiece file {} {problem}", path.display()),
        ));
    }
    Ok(Workpiece::from_path(&path)?)
}

fn placement(cx: &Ctx, spec: &ProgramFile) -> Result<Pose, ProgramError> {
    let t = cx.finite3(
        spec.placement.translate_mm,
        "$.placement.translate_mm".into(),
    )?;
    let r = cx.finite3(spec.placement.rotate_deg, "$.placement.rotate_deg".into())?;
    if r.amax() > MAX_ROTATION_DEG {
        return Err(cx.err(
            "$.placement.rotate_deg",
            format!(
                "{:?}: angles must lie within +-{MAX_ROTATION_DEG} degrees",
                spec.placement.rotate_deg
            ),
        ));
    }
    Ok(Pose {
        rotation: rotation_xyz_deg(r.into()),
        translation: t,
    })
}

fn probe(cx: &Ctx, spec: &ProgramFile) -> Result<ProbeSetup, ProgramError> {
    let d = cx.positive(
        spec.probe.tip_diameter_mm,
        50.0,
        "$.probe.tip_diameter_mm".into(),
    )?;
    let l = cx.positive(
        spec.probe.stylus_length_mm,
        1000.0,
        "$.probe.stylus_length_mm".into(),
    )?;
    let calibration = match &spec.probe.calibration {
        Some(rel) => {
            let path = relative_to(cx.file, rel);
            if let Some(problem) = crate::jsonfile::file_problem(&path) {
                return Err(cx.err(
                    "$.probe.calibration",
                    format!("calibration file {} {problem}", path.display()),
                ));
            }
            Some(path)
        }
        None => None,
    };
    let (shaft, body, body_length) = probe_body(cx, spec, d)?;
    Ok(ProbeSetup {
        tip_radius_mm: 0.5 * d,
        stylus_length_mm: l,
        shaft_radius_mm: 0.5 * shaft,
        body_radius_mm: 0.5 * body,
        body_length_mm: body_length,
        calibration,
    })
}

/// Shaft diameter, body diameter and body length of the probe block, mm:
/// the shaft no thicker than the ball (it would touch before the ball).
fn probe_body(cx: &Ctx, spec: &ProgramFile, tip: f64) -> Result<(f64, f64, f64), ProgramError> {
    let p = &spec.probe;
    let shaft_path = "$.probe.shaft_diameter_mm";
    let shaft = cx.positive(
        p.shaft_diameter_mm.unwrap_or(tip * 0.5),
        tip,
        shaft_path.into(),
    )?;
    let body = cx.positive(p.body_diameter_mm, 500.0, "$.probe.body_diameter_mm".into())?;
    let length = cx.positive(p.body_length_mm, 1000.0, "$.probe.body_length_mm".into())?;
    Ok((shaft, body, length))
}

fn faces_of(
    cx: &Ctx,
    wp: &Workpiece,
    names: Option<&[String]>,
    base: &str,
) -> Result<Vec<usize>, ProgramError> {
    let Some(names) = names else {
        return Ok((0..wp.faces.len()).collect());
    };
    if names.is_empty() {
        return Err(cx.err(
            format!("{base}.surfaces"),
            "empty surface list (omit it to use every surface)",
        ));
    }
    names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            wp.face_index(n).ok_or_else(|| {
                cx.err(
                    format!("{base}.surfaces[{k}]"),
                    format!("no surface named '{n}' in the workpiece"),
                )
            })
        })
        .collect()
}

fn tolerance(cx: &Ctx, t: [f64; 2], base: &str) -> Result<(f64, f64), ProgramError> {
    if !(t[0].is_finite() && t[1].is_finite()) || t[0] > t[1] {
        return Err(cx.err(
            format!("{base}.tolerance_mm"),
            format!("{t:?} must be finite with lower <= upper"),
        ));
    }
    Ok((t[0], t[1]))
}

fn feature(
    cx: &Ctx,
    spec: &ProgramFile,
    wp: &Workpiece,
    probe: &ProbeSetup,
    f: &FeatureSpec,
    i: usize,
) -> Result<Feature, ProgramError> {
    let base = format!("$.features[{i}]");
    match f {
        FeatureSpec::SectionScan {
            name,
            plane,
            surfaces,
            tolerance_mm,
            fit,
            ..
        } => {
            let fit = check_fit(cx, fit.as_ref(), &base)?;
            let faces = faces_of(cx, wp, surfaces.as_deref(), &base)?;
            let origin = cx.finite3(plane.origin_mm, format!("{base}.plane.origin_mm"))?;
            let normal = cx.finite3(plane.normal, format!("{base}.plane.normal"))?;
            let plane = Plane::try_new(Point3::from(origin), normal)
                .map_err(|e| cx.err(format!("{base}.plane.normal"), e.to_string()))?;
            let curves = section_faces(wp, &faces, &plane, &SectionOptions::default());
            if curves.is_empty() {
                return Err(cx.err(
                    format!("{base}.plane"),
                    "the plane does not cut the selected surfaces: nothing to scan",
                ));
            }
            let settings = settings(cx, spec, probe, f, &base)?;
            Ok(Feature::Section {
                name: name.clone(),
                plane,
                faces,
                curves,
                settings,
                tolerance: tolerance(cx, *tolerance_mm, &base)?,
                fit,
            })
        }
        FeatureSpec::TouchPoints {
            name,
            points_mm,
            surfaces,
            tolerance_mm,
            fit,
        } => {
            let fit = check_fit(cx, fit.as_ref(), &base)?;
            let faces = faces_of(cx, wp, surfaces.as_deref(), &base)?;
            if points_mm.is_empty() {
                return Err(cx.err(format!("{base}.points_mm"), "no points"));
            }
            let points = points_mm
                .iter()
                .enumerate()
                .map(|(k, p)| nominal_point(cx, wp, &faces, *p, &format!("{base}.points_mm[{k}]")))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(Feature::Touch {
                name: name.clone(),
                points,
                tolerance: tolerance(cx, *tolerance_mm, &base)?,
                fit,
            })
        }
    }
}

fn check_fit(
    cx: &Ctx,
    fit: Option<&super::FitSpec>,
    base: &str,
) -> Result<Option<super::FitSpec>, ProgramError> {
    let Some(f) = fit else { return Ok(None) };
    if let Some([lo, hi]) = f.size_mm {
        if !(lo.is_finite() && hi.is_finite()) || lo > hi {
            return Err(cx.err(
                format!("{base}.fit.size_mm"),
                format!("[{lo}, {hi}] must be finite with lower <= upper"),
            ));
        }
    }
    for (key, v) in [("form_mm", f.form_mm), ("position_mm", f.position_mm)] {
        if let Some(v) = v {
            cx.positive(v, 1000.0, format!("{base}.fit.{key}"))?;
        }
    }
    Ok(Some(f.clone()))
}

/// Fewest alignment points accepted (six degrees of freedom).
const MIN_ALIGNMENT_POINTS: usize = 6;

fn alignment_points(
    cx: &Ctx,
    wp: &Workpiece,
    a: &super::AlignmentSpec,
) -> Result<Vec<NominalPoint>, ProgramError> {
    let faces = faces_of(cx, wp, a.surfaces.as_deref(), "$.alignment")?;
    if a.points_mm.len() < MIN_ALIGNMENT_POINTS {
        let reason = format!(
            "{} points cannot fix six degrees of freedom: at least {MIN_ALIGNMENT_POINTS} needed",
            a.points_mm.len()
        );
        return Err(cx.err("$.alignment.points_mm", reason));
    }
    a.points_mm
        .iter()
        .enumerate()
        .map(|(k, p)| nominal_point(cx, wp, &faces, *p, &format!("$.alignment.points_mm[{k}]")))
        .collect()
}

fn nominal_point(
    cx: &Ctx,
    wp: &Workpiece,
    faces: &[usize],
    p: [f64; 3],
    path: &str,
) -> Result<NominalPoint, ProgramError> {
    let p = Point3::from(cx.finite3(p, path.to_string())?);
    let fp = wp
        .closest_point_among(p, faces.iter().copied())
        .map_err(|e| cx.err(path, e.to_string()))?;
    let pr = fp.projection;
    if pr.distance > TOUCH_POINT_REACH_MM {
        return Err(cx.err(
            path,
            format!(
                "point lies {:.3} mm from the surfaces (at most {TOUCH_POINT_REACH_MM} mm allowed)",
                pr.distance
            ),
        ));
    }
    Ok(NominalPoint {
        face: fp.face,
        uv: pr.uv,
        point: pr.point,
        normal: pr.normal,
    })
}

/// The scan defaults are checked whether or not a feature takes them: a
/// program is valid or not whatever features it holds. (The deflection's
/// bound by the tip's size applies where a scan takes it: a touch-only
/// program with a small tip need not set a scan deflection.)
fn check_defaults(cx: &Ctx, spec: &ProgramFile) -> Result<(), ProgramError> {
    let d = &spec.defaults;
    let path = |key: &str| format!("$.defaults.{key}");
    cx.positive(d.speed_mm_s, MAX_SPEED_MM_S, path("speed_mm_s"))?;
    cx.positive(d.deflection_mm, MAX_DEFLECTION_MM, path("deflection_mm"))?;
    cx.positive(d.pitch_mm, 100.0, path("pitch_mm"))?;
    cx.positive(
        d.trajectory_tolerance_mm,
        100.0,
        path("trajectory_tolerance_mm"),
    )?;
    Ok(())
}

fn settings(
    cx: &Ctx,
    spec: &ProgramFile,
    probe: &ProbeSetup,
    f: &FeatureSpec,
    base: &str,
) -> Result<ScanSettings, ProgramError> {
    let FeatureSpec::SectionScan {
        mode,
        speed_mm_s,
        deflection_mm,
        pitch_mm,
        trajectory_tolerance_mm,
        ..
    } = f
    else {
        return Err(cx.err(base, "not a scan"));
    };
    let d = &spec.defaults;
    let pick = |o: &Option<f64>, dflt: f64, key: &str| match o {
        Some(v) => (*v, format!("{base}.{key}")),
        None => (dflt, format!("$.defaults.{key}")),
    };
    let (speed, sp) = pick(speed_mm_s, d.speed_mm_s, "speed_mm_s");
    let (defl, dp) = pick(deflection_mm, d.deflection_mm, "deflection_mm");
    let (pitch, pp) = pick(pitch_mm, d.pitch_mm, "pitch_mm");
    let (tol, tp) = pick(
        trajectory_tolerance_mm,
        d.trajectory_tolerance_mm,
        "trajectory_tolerance_mm",
    );
    Ok(ScanSettings {
        mode: mode.unwrap_or(d.mode),
        speed_mm_s: cx.positive(speed, MAX_SPEED_MM_S, sp)?,
        deflection_mm: cx.positive(defl, MAX_DEFLECTION_MM.min(0.9 * probe.tip_radius_mm), dp)?,
        pitch_mm: cx.positive(pitch, 100.0, pp)?,
        trajectory_tolerance_mm: cx.positive(tol, 100.0, tp)?,
    })
}

/// Every nominal point must be reachable: ball centre and stylus top
/// inside the machine's travel.
fn check_reach(cx: &Ctx, program: &Program, travel: &Travel) -> Result<(), ProgramError> {
    super::limits::check_start(program, travel.lo, travel.hi)?;
    for f in &program.features {
        let pts: Vec<(Point3, Vec3)> = match f {
            Feature::Section { curves, .. } => curves
                .iter()
                .flat_map(|c| c.points.iter().map(|p| (p.point, p.normal)))
                .collect(),
            Feature::Touch { points, .. } => points.iter().map(|p| (p.point, p.normal)).collect(),
        };
        for (p, n) in pts {
            let ball = program
                .placement
                .to_machine(p + n * program.probe.tip_radius_mm);
            let top = ball - program.probe_vector();
            let inside = |q: Point3| (0..3).all(|k| q[k] >= travel.lo[k] && q[k] <= travel.hi[k]);
            if !inside(ball) || !inside(top) {
                let reason = format!(
                    "feature '{}': the probe at machine position ({:.1}, {:.1}, {:.1}) mm would leave the machine's travel [{:?} .. {:?}] mm",
                    f.name(), ball.x, ball.y, ball.z, travel.lo, travel.hi
                );
                return Err(cx.err("$.placement", reason));
            }
        }
    }
    Ok(())
}
