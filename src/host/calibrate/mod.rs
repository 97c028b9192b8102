//! Probe calibration on a reference sphere (condition-dependent probe correction and JP2902285B2;
//! `cmm calibrate-probe`).
//!
//! The host side ([`calibrate`]) measures the sphere through the
//! [`Cmm`] seam — the 25 touch points of ISO 10360-5 and circle scans in the
//! XY, XZ and YZ planes at several deflections in both directions — and
//! computes, from the readings only, the probe vector, the effective tip
//! radius and the condition-dependent deflection correction
//! ([`crate::host::probe_correction`]). With the machine's geometric error
//! map ([`crate::host::compensation`]) every reading is corrected through
//! the probe vector (JP2902285B2). On a machine with a probe head,
//! [`orientation`] calibrates the reference orientation in full and every
//! further one from a few points around its predicted sphere centre (seed
//! 003's iterative inverse). [`simulate`] and [`simulate_head`] set up the
//! simulated machine; [`file`] and [`file_head`] read and write
//! `cmm-probe-cal/1`.
pub mod file;
pub mod file_head;
pub mod measure;
pub mod orientation;
pub mod pattern;
pub mod probe_file;
pub mod solve;

use measure::{measure_sphere, SphereReadings};
use pattern::{ScanPlane, SCAN_PLANES};

use crate::fit::{fit, ElementKind, FitOptions, Method};
use crate::host::compensation::ErrorMap;
use crate::host::modes::{HostProbe, Measured, ModeOptions, Outcome};
use crate::host::observe::Machine;
use crate::math::{Point3, Vec3};

/// How the calibration measures and solves (mm, mm/s, deg).
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationOptions {
    /// Reference sphere diameter, mm (known exactly).
    pub sphere_diameter_mm: f64,
    /// Where the sphere's centre is on the machine, mm (known).
    pub sphere_center_mm: Point3,
    /// Deflections of the circle scans, mm.
    pub deflections_mm: Vec<f64>,
    /// Scanning directions: `true` = counter-clockwise.
    pub directions: Vec<bool>,
    /// Planes of the circle scans.
    pub planes: Vec<ScanPlane>,
    /// Scanning speed, mm/s.
    pub scan_speed_mm_s: f64,
    /// Spacing of the readings kept from a scan, mm.
    pub scan_pitch_mm: f64,
    /// Points defining a circle (the path is a cubic spline through them).
    pub circle_points: usize,
    /// XZ and YZ arcs start and end this far below the equator, deg, or
    /// less where the stylus shaft would come nearer the sphere than
    /// [`Self::shaft_clearance_mm`] ([`Self::arc_below_equator_for`]).
    pub arc_below_equator_deg: f64,
    /// The stylus shaft's radius, mm (`None`: half the tip's radius, the
    /// default stylus).
    pub shaft_radius_mm: Option<f64>,
    /// Below the equator the arcs keep the vertical shaft this far off the
    /// sphere at the largest deflection, mm.
    pub shaft_clearance_mm: f64,
    /// The XY circle runs this far above the equator, deg.
    pub xy_elevation_deg: f64,
    /// Active scanning's trajectory tolerance, mm.
    pub trajectory_tolerance_mm: f64,
    /// Contact is searched this far past the nominal touch point, mm.
    pub touch_search_mm: f64,
    /// Moves between measurements pass this high above the sphere, mm.
    pub clearance_mm: f64,
    /// Gauss-Newton stops when no parameter moves more than this, mm (or
    /// 1/mm^k for the gain terms).
    pub step_tolerance_mm: f64,
    /// Most Gauss-Newton iterations.
    pub max_iterations: usize,
    /// Deflections closer than this count as one level, mm.
    pub level_tolerance_mm: f64,
    /// A level of the scans' readings counts towards the degree of the
    /// normal-tilt polynomials only when it holds at least this share
    /// (dimensionless, 0..1) of its group's readings: the few readings of
    /// a scan's start and end, on the way to or from the target
    /// deflection, are no level the scans were made at.
    pub level_min_share: f64,
    /// Measuring-mode gains and thresholds (trigger deflection etc.).
    pub modes: ModeOptions,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        CalibrationOptions {
            sphere_diameter_mm: 25.0,
            sphere_center_mm: Point3::new(500.0, 300.0, 100.0),
            deflections_mm: vec![0.1, 0.2, 0.3, 0.5],
            directions: vec![false, true],
            planes: SCAN_PLANES.to_vec(),
            scan_speed_mm_s: 20.0,
            scan_pitch_mm: 0.2,
            circle_points: 72,
            arc_below_equator_deg: 10.0,
            shaft_radius_mm: None,
            shaft_clearance_mm: 0.02,
            xy_elevation_deg: 15.0,
            trajectory_tolerance_mm: 1.5,
            touch_search_mm: 3.0,
            clearance_mm: 10.0,
            step_tolerance_mm: 1e-10,
            max_iterations: 30,
            level_tolerance_mm: 0.02,
            level_min_share: 0.1,
            modes: ModeOptions::default(),
        }
    }
}

impl CalibrationOptions {
    /// Sphere radius, mm.
    pub fn sphere_radius(&self) -> f64 {
        0.5 * self.sphere_diameter_mm
    }

    /// How far below the equator the XZ and YZ arcs of a ball of radius
    /// `tip_radius_mm` reach, deg: [`Self::arc_below_equator_deg`], or
    /// less where the vertical shaft above a ball centre at angle `a` below
    /// the equator, `(R + r - e) cos a` from the sphere's axis at the
    /// largest deflection `e`, would come within the clearance of the
    /// sphere (radius `R`); none for a shaft as thick as the ball less the
    /// deflection (a 0.6 mm ball deflected 0.1 mm: 3.9 degrees).
    pub fn arc_below_equator_for(&self, tip_radius_mm: f64) -> f64 {
        let shaft = self.shaft_radius_mm.unwrap_or(0.5 * tip_radius_mm);
        let deepest = self.deflections_mm.iter().copied().fold(0.0, f64::max);
        let big_r = self.sphere_radius();
        let ratio = (big_r + shaft + self.shaft_clearance_mm) / (big_r + tip_radius_mm - deepest);
        let clear_deg = if ratio >= 1.0 {
            0.0
        } else {
            ratio.acos().to_degrees()
        };
        self.arc_below_equator_deg.min(clear_deg)
    }
}

/// Why a calibration failed.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// A touch point of the pattern could not be measured.
    #[error("touch point {index} of the 25-point pattern failed: {outcome:?}")]
    Touch {
        /// Index in the pattern.
        index: usize,
        /// How it ended.
        outcome: Outcome,
    },
    /// A circle scan could not be completed.
    #[error("{plane:?} scan ({}, deflection {deflection_mm} mm) failed: {outcome:?}", if *ccw { "ccw" } else { "cw" })]
    Scan {
        /// Plane.
        plane: ScanPlane,
        /// Direction.
        ccw: bool,
        /// Wanted deflection, mm.
        deflection_mm: f64,
        /// How it ended.
        outcome: Outcome,
    },
    /// The sphere fit failed.
    #[error("sphere fit")]
    Fit(#[from] crate::fit::FitError),
    /// The normal equations of the model are singular.
    #[error(
        "calibration model with {unknowns} unknowns is singular (too few conditions measured)"
    )]
    Singular {
        /// Number of unknowns.
        unknowns: usize,
    },
    /// The fit did not give a sphere.
    #[error("sphere fit did not converge after {iterations} iterations")]
    NotConverged {
        /// Iterations made.
        iterations: usize,
    },
    /// The probe head refused an orientation.
    #[error("orientation {orientation}: cannot index the probe head: {source}")]
    Head {
        /// Orientation number (1-based, as listed).
        orientation: usize,
        /// Why.
        source: crate::seam::HeadCommandError,
    },
    /// The iterative inverse correction did not converge.
    #[error("orientation {orientation}: predicted sphere centre: {source}")]
    Inverse {
        /// Orientation number (1-based, as listed).
        orientation: usize,
        /// Why.
        source: crate::host::compensation::InverseError,
    },
    /// A touch point at a head orientation failed.
    #[error("orientation {orientation}: point {index} on the sphere failed: {outcome:?}")]
    OrientationTouch {
        /// Orientation number (1-based, as listed).
        orientation: usize,
        /// Index of the point (0 = the pole).
        index: usize,
        /// How it ended.
        outcome: Outcome,
    },
    /// The move to free air before turning the head failed.
    #[error(
        "orientation {orientation}: move clear of the sphere before indexing failed: {outcome:?}"
    )]
    Clear {
        /// Orientation number (1-based, as listed).
        orientation: usize,
        /// How it ended.
        outcome: Outcome,
    },
    /// No head orientation was listed.
    #[error("no probe-head orientation listed")]
    NoOrientation,
    /// Too few points for a sphere at a head orientation.
    #[error("orientation options: {points} points per orientation, at least 4 are needed")]
    TooFewPoints {
        /// Points asked for.
        points: usize,
    },
    /// Bad options.
    #[error("{what} = {value} must be {requirement}")]
    Option {
        /// The option.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The requirement.
        requirement: &'static str,
    },
}

/// Radial error figures of a set of points, mm.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadialError {
    /// RMS of the radial deviations.
    pub rms_mm: f64,
    /// Range (max - min) of the radial deviations.
    pub range_mm: f64,
}

/// One scan's errors before and after the correction.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScanSummary {
    /// Plane.
    pub plane: ScanPlane,
    /// `cw` or `ccw`.
    pub direction: String,
    /// Wanted deflection, mm.
    pub deflection_mm: f64,
    /// Readings used.
    pub points: usize,
    /// Radial deviations from the known sphere with nominal probe values.
    pub before: RadialError,
    /// The same with the calibration applied.
    pub after: RadialError,
}

/// The result of a calibration (host side only).
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// Calibrated probe vector (mount to ball centre), mm.
    pub probe: HostProbe,
    /// Sphere centre seen with the nominal probe vector, mm.
    pub sphere_center_nominal_probe: Point3,
    /// Probing error `P` (range of the 25 radial residuals from their own
    /// least-squares sphere), calibrated, mm.
    pub probing_error_mm: f64,
    /// The same with nominal probe values, mm.
    pub probing_error_before_mm: f64,
    /// Per scan errors.
    pub scans: Vec<ScanSummary>,
    /// The solver's details.
    pub solved: solve::Solved,
}

/// Calibrates the probe on the sphere through the seam; `nominal` is what
/// the host knows before (nominal probe vector and radius). No geometric
/// error compensation.
pub fn calibrate(
    cmm: &mut dyn Machine,
    nominal: HostProbe,
    opts: &CalibrationOptions,
) -> Result<Calibration, CalibrateError> {
    calibrate_compensated(cmm, nominal, &ErrorMap::none(), opts)
}

/// [`calibrate`] on a machine whose geometric errors the host corrects
/// with `map`: every reading's scales are corrected through the probe
/// vector (JP2902285B2), first the nominal one, then — once solved — the
/// calibrated one, and the model is solved again.
pub fn calibrate_compensated(
    cmm: &mut dyn Machine,
    nominal: HostProbe,
    map: &ErrorMap,
    opts: &CalibrationOptions,
) -> Result<Calibration, CalibrateError> {
    check(opts)?;
    let raw = measure_sphere(cmm, nominal, opts)?;
    let mut data = compensated(&raw, map, &nominal.probe_vector);
    let mut solved = solve::solve(&data, nominal.probe_vector, opts)?;
    if !map.is_zero() {
        let p = nominal.probe_vector + (opts.sphere_center_mm - solved.centre);
        data = compensated(&raw, map, &p);
        solved = solve::solve(&data, nominal.probe_vector, opts)?;
    }
    let probe = HostProbe {
        probe_vector: nominal.probe_vector + (opts.sphere_center_mm - solved.centre),
        tip_radius_mm: solved.tip_radius_mm,
        correction: solved.correction,
    };
    Ok(Calibration {
        probe,
        sphere_center_nominal_probe: solved.centre,
        probing_error_mm: probing_error(&data.touches, &probe)?,
        probing_error_before_mm: probing_error(&data.touches, &nominal)?,
        scans: scan_summaries(&data, &nominal, &probe, opts),
        solved,
    })
}

/// Readings with their scales corrected by `map` for probe vector `p`.
fn compensated(raw: &SphereReadings, map: &ErrorMap, p: &Vec3) -> SphereReadings {
    let fix = |ms: &[Measured]| compensate_readings(ms, map, p);
    SphereReadings {
        touches: fix(&raw.touches),
        scans: raw
            .scans
            .iter()
            .map(|s| measure::ScanRecord {
                samples: fix(&s.samples),
                ..s.clone()
            })
            .collect(),
    }
}

/// Readings whose `scales` are corrected by `map` for probe vector `p`
/// (`scales + P` is then the corrected undeflected ball centre).
pub fn compensate_readings(ms: &[Measured], map: &ErrorMap, p: &Vec3) -> Vec<Measured> {
    ms.iter()
        .map(|m| Measured {
            scales: map.compensate(m.scales, p),
            ..*m
        })
        .collect()
}

fn check(opts: &CalibrationOptions) -> Result<(), CalibrateError> {
    let bad = |what, value, requirement| {
        Err(CalibrateError::Option {
            what,
            value,
            requirement,
        })
    };
    if !(opts.sphere_diameter_mm > 0.0 && opts.sphere_diameter_mm.is_finite()) {
        return bad(
            "sphere diameter",
            opts.sphere_diameter_mm,
            "finite and positive",
        );
    }
    match opts
        .deflections_mm
        .iter()
        .find(|d| !(**d > 0.0 && **d < 1.0))
    {
        Some(&d) => bad("scan deflection", d, "between 0 and 1 mm"),
        None => Ok(()),
    }
}

/// Recomputes a reading's point with another probe model.
fn relocate(m: &Measured, probe: &HostProbe) -> Option<Point3> {
    probe.locate(m.scales, m.reading, m.motion).map(|x| x.point)
}

/// Range of the touch points' residuals from their least-squares sphere.
fn probing_error(touches: &[Measured], probe: &HostProbe) -> Result<f64, CalibrateError> {
    let points: Vec<Point3> = touches.iter().filter_map(|m| relocate(m, probe)).collect();
    let report = fit(
        ElementKind::Sphere,
        Method::Lsq,
        &points,
        &FitOptions::default(),
    )?;
    Ok(report.residuals.max - report.residuals.min)
}

fn radial_error(samples: &[Measured], probe: &HostProbe, opts: &CalibrationOptions) -> RadialError {
    let dev: Vec<f64> = samples
        .iter()
        .filter_map(|m| relocate(m, probe))
        .map(|p| (p - opts.sphere_center_mm).norm() - opts.sphere_radius())
        .collect();
    let max = dev.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = dev.iter().copied().fold(f64::INFINITY, f64::min);
    RadialError {
        rms_mm: solve::rms(dev.iter().copied()),
        range_mm: if dev.is_empty() { 0.0 } else { max - min },
    }
}

fn scan_summaries(
    data: &SphereReadings,
    nominal: &HostProbe,
    probe: &HostProbe,
    opts: &CalibrationOptions,
) -> Vec<ScanSummary> {
    data.scans
        .iter()
        .map(|s| ScanSummary {
            plane: s.plane,
            direction: direction_name(s.ccw).into(),
            deflection_mm: s.deflection_mm,
            points: s.samples.len(),
            before: radial_error(&s.samples, nominal, opts),
            after: radial_error(&s.samples, probe, opts),
        })
        .collect()
}

/// `ccw` or `cw`.
pub fn direction_name(ccw: bool) -> &'static str {
    if ccw {
        "ccw"
    } else {
        "cw"
    }
}

/// The nominal probe of a tip diameter and a vertical stylus length, mm.
pub fn nominal_probe(tip_diameter_mm: f64, stylus_length_mm: f64) -> HostProbe {
    HostProbe::nominal(
        Vec3::new(0.0, 0.0, -stylus_length_mm),
        0.5 * tip_diameter_mm,
    )
}
