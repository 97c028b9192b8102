//! Probe vectors per probe-head orientation with one sphere measurement
//! each (JP2902285B2).
//!
//! The reference orientation is calibrated in full ([`super::calibrate`]).
//! For every other orientation the host
//! 1. predicts the probe vector from its nominal head model: the stylus
//!    found at the reference orientation, carried to the new angles
//!    ([`HeadModel`]);
//! 2. brings the ball to free air above the sphere and indexes the head;
//! 3. computes where the sphere's centre will appear with the predicted
//!    vector — the scale position that puts that ball on the sphere's known
//!    centre — by the iterative inverse of the machine's error correction
//!    ([`ErrorMap::inverse`]);
//! 4. touches the sphere at a few points only (4 by default, as in the
//!    seed: the pole facing the probe mount and 3 around it) and fits a
//!    sphere to the ball centres, corrected with the predicted vector:
//!    probe vector `P = P_pred + (known centre - fitted centre)`, tip radius
//!    `= fitted radius - sphere radius`;
//! 5. turns the ball centres corrected with `P_pred` into those the new
//!    vector gives (JP2902285B2's inverse then forward correction,
//!    [`ErrorMap::recompensate`]) and fits again: the result is what
//!    measuring the sphere a second time with the new vector would give.
//!
//! The deflection correction found at the reference orientation is carried
//! along with the head's nominal rotation ([`DeflectionCorrection::turned`]).
use super::measure::{modes, touch_pattern};
use super::pattern::{cap_around, iso_25_around};
use super::{CalibrateError, CalibrationOptions};
use crate::fit::{fit, Element, ElementKind, FitOptions, Method};
use crate::host::compensation::{ErrorMap, InverseOptions};
use crate::host::head::{HeadModel, Orientation};
use crate::host::modes::{move_to, recover, HostProbe, Measured, Tracker};
use crate::host::observe::Machine;
use crate::math::{Mat3, Point3, Vec3};

/// Where the sphere is touched at a further orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointPattern {
    /// The pole and `points - 1` points at `polar_deg` around it (JP2902285B2:
    /// 4 points).
    Cap,
    /// The full 25-point pattern of ISO 10360-5 around the pole (for
    /// checking the quick measurement; the 90 deg ring must be reachable).
    Iso25,
}

/// How each further orientation is measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientationOptions {
    /// Which points.
    pub pattern: PointPattern,
    /// Points on the sphere per orientation with [`PointPattern::Cap`]
    /// (at least 4).
    pub points: usize,
    /// Angle of the points around the pole from the pole, deg.
    pub polar_deg: f64,
    /// No point of the cap lies lower than this elevation, deg (a
    /// horizontal stylus would otherwise have to reach far under the
    /// sphere).
    pub min_elevation_deg: f64,
    /// The iterative inverse correction's tolerance and iteration limit.
    pub inverse: InverseOptions,
}

impl Default for OrientationOptions {
    fn default() -> Self {
        OrientationOptions {
            pattern: PointPattern::Cap,
            points: 4,
            polar_deg: 80.0,
            min_elevation_deg: -40.0,
            inverse: InverseOptions::default(),
        }
    }
}

/// The reference orientation's result the others start from.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The reference orientation.
    pub orientation: Orientation,
    /// Its calibrated probe.
    pub probe: HostProbe,
}

/// One orientation's calibration (host side only).
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationResult {
    /// Head angles as listed, deg.
    pub angles_deg: Vec<f64>,
    /// Head encoder readings after indexing, rad (chain order).
    pub head_readings_rad: Vec<f64>,
    /// Probe vector predicted by the nominal head model, mm.
    pub predicted_probe_vector: Vec3,
    /// Scale position at which the predicted ball sits on the sphere's
    /// known centre (iterative inverse), mm.
    pub predicted_center_scales: Point3,
    /// Iterations of the inverse correction.
    pub inverse_iterations: usize,
    /// Calibrated probe at this orientation.
    pub probe: HostProbe,
    /// Sphere centre seen with the predicted probe vector, mm.
    pub sphere_center_predicted_probe: Point3,
    /// Points measured.
    pub points: usize,
    /// Range of the points' residuals from the fitted sphere, mm (0 with 4
    /// points: the sphere goes through them).
    pub form_mm: f64,
}

/// The calibration of every listed orientation, the first being the
/// reference.
#[derive(Debug, Clone, PartialEq)]
pub struct HeadCalibration {
    /// The full calibration at the reference orientation.
    pub reference: super::Calibration,
    /// Head angles of the reference orientation, deg.
    pub reference_angles_deg: Vec<f64>,
    /// Every further orientation, in the order listed.
    pub orientations: Vec<OrientationResult>,
}

/// Calibrates a probe on a head: in full at `orientations[0]` (nominal
/// stylus `stylus` in the mount frame, mm, and tip radius `tip_radius_mm`),
/// then every further orientation by [`calibrate_orientation`]. The
/// machine's ball must be in free air above the sphere at the reference
/// orientation's angles.
#[allow(clippy::too_many_arguments)]
pub fn calibrate_head(
    cmm: &mut dyn Machine,
    head: &HeadModel,
    (stylus, tip_radius_mm): (Vec3, f64),
    orientations: &[Orientation],
    map: &ErrorMap,
    opts: &CalibrationOptions,
    oopts: &OrientationOptions,
) -> Result<HeadCalibration, CalibrateError> {
    let Some(first) = orientations.first() else {
        return Err(CalibrateError::NoOrientation);
    };
    cmm.index_head(&first.chain_angles_rad)
        .map_err(|source| CalibrateError::Head {
            orientation: 1,
            source,
        })?;
    let nominal = HostProbe::nominal(head.probe_vector(first, &stylus), tip_radius_mm);
    let cal = super::calibrate_compensated(cmm, nominal, map, opts)?;
    let reference = Reference {
        orientation: first.clone(),
        probe: cal.probe,
    };
    let mut current = cal.probe;
    let mut results = Vec::new();
    for (k, o) in orientations.iter().enumerate().skip(1) {
        let number = k + 1;
        let r = calibrate_orientation(
            cmm,
            head,
            &reference,
            &mut current,
            (number, o),
            map,
            opts,
            oopts,
        )?;
        results.push(r);
    }
    Ok(HeadCalibration {
        reference: cal,
        reference_angles_deg: first.angles_deg.clone(),
        orientations: results,
    })
}

/// Calibrates orientation number `number` (1-based, for messages); `current`
/// is the probe the head carries now (updated to the new one).
#[allow(clippy::too_many_arguments)]
pub fn calibrate_orientation(
    cmm: &mut dyn Machine,
    head: &HeadModel,
    reference: &Reference,
    current: &mut HostProbe,
    (number, o): (usize, &Orientation),
    map: &ErrorMap,
    opts: &CalibrationOptions,
    oopts: &OrientationOptions,
) -> Result<OrientationResult, CalibrateError> {
    if oopts.points < 4 {
        return Err(CalibrateError::TooFewPoints {
            points: oopts.points,
        });
    }
    let predicted = predicted_probe(head, reference, o);
    clear_above_sphere(cmm, *current, &predicted.probe_vector, number, opts)?;
    let head_readings_rad =
        cmm.index_head(&o.chain_angles_rad)
            .map_err(|source| CalibrateError::Head {
                orientation: number,
                source,
            })?;
    *current = predicted;
    let inv = map
        .inverse(
            opts.sphere_center_mm,
            &predicted.probe_vector,
            &oopts.inverse,
        )
        .map_err(|source| CalibrateError::Inverse {
            orientation: number,
            source,
        })?;
    let centre_seen = inv.scales + predicted.probe_vector;
    let touches = touch_around(cmm, head, (number, o), predicted, centre_seen, opts, oopts)?;
    let solved = solve_orientation(&touches, &predicted, map, opts, &oopts.inverse)
        .map_err(|e| with_orientation(e, number))?;
    *current = solved.probe;
    Ok(OrientationResult {
        angles_deg: o.angles_deg.clone(),
        head_readings_rad,
        predicted_probe_vector: predicted.probe_vector,
        predicted_center_scales: inv.scales,
        inverse_iterations: inv.iterations,
        ..solved
    })
}

/// Touches the sphere (centre expected at `centre_seen`) at the points of
/// the options' pattern around the pole of orientation `o`.
fn touch_around(
    cmm: &mut dyn Machine,
    head: &HeadModel,
    (number, o): (usize, &Orientation),
    predicted: HostProbe,
    centre_seen: Point3,
    opts: &CalibrationOptions,
    oopts: &OrientationOptions,
) -> Result<Vec<Measured>, CalibrateError> {
    let pole = pole(head, o, &head.stylus(o, &predicted.probe_vector));
    let dirs = match oopts.pattern {
        PointPattern::Cap => cap_around(
            &pole,
            oopts.points,
            oopts.polar_deg,
            oopts.min_elevation_deg,
        ),
        PointPattern::Iso25 => iso_25_around(&pole),
    };
    touch_pattern(cmm, predicted, centre_seen, &dirs, opts).map_err(|e| match e {
        CalibrateError::Touch { index, outcome } => CalibrateError::OrientationTouch {
            orientation: number,
            index,
            outcome,
        },
        other => other,
    })
}

fn with_orientation(e: CalibrateError, orientation: usize) -> CalibrateError {
    match e {
        CalibrateError::Inverse { source, .. } => CalibrateError::Inverse {
            orientation,
            source,
        },
        other => other,
    }
}

/// The reference probe carried to orientation `o` by the nominal head.
pub fn predicted_probe(head: &HeadModel, reference: &Reference, o: &Orientation) -> HostProbe {
    let stylus = head.stylus(&reference.orientation, &reference.probe.probe_vector);
    let turn: Mat3 = (head.mount(o).rotation
        * head.mount(&reference.orientation).rotation.inverse())
    .to_rotation_matrix()
    .into_inner();
    HostProbe {
        probe_vector: head.probe_vector(o, &stylus),
        tip_radius_mm: reference.probe.tip_radius_mm,
        correction: reference.probe.correction.turned(&turn),
    }
}

/// Outward direction on the sphere facing the probe mount: from the ball
/// back along the stylus.
pub fn pole(head: &HeadModel, o: &Orientation, stylus: &Vec3) -> Vec3 {
    let back = head.mount(o).rotation * -stylus;
    back.try_normalize(1e-12).unwrap_or_else(Vec3::z)
}

/// Moves the ball of `probe` up above the sphere, high enough that the ball
/// of `next` (after the head turns) is still above the clearance height.
fn clear_above_sphere(
    cmm: &mut dyn Machine,
    probe: HostProbe,
    next: &Vec3,
    number: usize,
    opts: &CalibrationOptions,
) -> Result<(), CalibrateError> {
    let m = modes(opts, &probe);
    let c = opts.sphere_center_mm;
    let top = c.z + opts.sphere_radius() + probe.tip_radius_mm + opts.clearance_mm;
    let z = m.clearance_z_mm.unwrap_or(top).max(top) + (next - probe.probe_vector).norm();
    let mut tr = Tracker::new(cmm, probe);
    let failed = |outcome| CalibrateError::Clear {
        orientation: number,
        outcome,
    };
    recover(cmm, &mut tr, &m).map_err(failed)?;
    let here = tr.ball_undeflected();
    let up = Point3::new(here.x, here.y, z.max(here.z));
    move_to(cmm, &mut tr, up, m.rapid_speed_mm_s, &m).map_err(failed)?;
    let over = Point3::new(c.x, c.y, z.max(here.z));
    move_to(cmm, &mut tr, over, m.rapid_speed_mm_s, &m).map_err(failed)
}

/// Fits the sphere to touches taken with `predicted`, corrects with the
/// resulting vector and fits again (see the module docs, steps 4 and 5).
pub fn solve_orientation(
    touches: &[Measured],
    predicted: &HostProbe,
    map: &ErrorMap,
    opts: &CalibrationOptions,
    inverse: &InverseOptions,
) -> Result<OrientationResult, CalibrateError> {
    let p_pred = predicted.probe_vector;
    let deflections: Vec<Vec3> = touches
        .iter()
        .map(|m| predicted.correction.deflection(m.reading))
        .collect();
    let undeflected: Vec<Point3> = touches
        .iter()
        .map(|m| map.forward(m.scales, &p_pred))
        .collect();
    let balls =
        |u: &[Point3]| -> Vec<Point3> { u.iter().zip(&deflections).map(|(b, d)| b + d).collect() };
    let (first, _) = fit_sphere(&balls(&undeflected))?;
    let p_first = p_pred + (opts.sphere_center_mm - first.0);
    let mut again = Vec::with_capacity(undeflected.len());
    for u in &undeflected {
        let turned = map.recompensate(*u, &p_pred, &p_first, inverse);
        again.push(turned.map_err(|source| CalibrateError::Inverse {
            orientation: 0,
            source,
        })?);
    }
    let ((centre, radius), form_mm) = fit_sphere(&balls(&again))?;
    let probe = HostProbe {
        probe_vector: p_first + (opts.sphere_center_mm - centre),
        tip_radius_mm: radius - opts.sphere_radius(),
        correction: predicted.correction,
    };
    Ok(OrientationResult {
        angles_deg: Vec::new(),
        head_readings_rad: Vec::new(),
        predicted_probe_vector: p_pred,
        predicted_center_scales: opts.sphere_center_mm - p_pred,
        inverse_iterations: 0,
        probe,
        sphere_center_predicted_probe: first.0,
        points: touches.len(),
        form_mm,
    })
}

/// Least-squares sphere (centre, radius) and the range of its residuals.
fn fit_sphere(balls: &[Point3]) -> Result<((Point3, f64), f64), CalibrateError> {
    let report = fit(
        ElementKind::Sphere,
        Method::Lsq,
        balls,
        &FitOptions::default(),
    )?;
    let form = report.residuals.max - report.residuals.min;
    match report.element {
        Element::Sphere(s) => Ok(((s.center, s.radius), form)),
        _ => Err(CalibrateError::NotConverged {
            iterations: report.iterations,
        }),
    }
}
