//! The calibration's computation, from readings only.
//!
//! Ball model: every ball centre `b = s + P0 + m + E(|m|) m` (scales `s`,
//! nominal probe vector `P0`, raw reading `m`, symmetric gain corrections
//! `E(dp) = E0 + E1 dp + E2 dp^2`) lies on the sphere of radius `R + r`
//! around the centre `c` seen with the nominal probe vector (`R` the known
//! sphere radius, `r` the effective tip radius). Gauss-Newton on the
//! orthogonal distances finds `c`, `r` and `E`; the probe vector is
//! `P = P0 + (known sphere position - c)` (JP2902285B2: the centre seen from
//! the probe mount against the sphere's known position). The number of
//! gain terms is limited by the number of distinct deflections measured.
//! Normal tilts per plane and direction then come from the angle between
//! the corrected deflection and the sphere's normal at the ball.
use nalgebra::{DMatrix, DVector};

use super::measure::SphereReadings;
use super::{CalibrateError, CalibrationOptions};
use crate::fit::{fit, Element, ElementKind, FitOptions, Method};
use crate::host::modes::Measured;
use crate::host::probe_correction::{
    DeflectionCorrection, DeflectionPoly, ScanCondition, CORRECTION_TERMS,
};
use crate::math::{Mat3, Point3, Vec3};

/// The solved ball model.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// Sphere centre seen with the nominal probe vector, mm.
    pub centre: Point3,
    /// Effective tip radius, mm.
    pub tip_radius_mm: f64,
    /// Gain correction and normal tilts.
    pub correction: DeflectionCorrection,
    /// RMS of the ball-centre distances from the fitted sphere, mm.
    pub residual_rms_mm: f64,
    /// Gain correction terms used (polynomial degree + 1; 0 = none).
    pub gain_terms: usize,
    /// Gauss-Newton iterations.
    pub iterations: usize,
}

/// Independent parameters of one symmetric 3x3 matrix.
const SYM: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// Solves the ball model and the tilts from everything measured.
pub fn solve(
    data: &SphereReadings,
    p0: Vec3,
    opts: &CalibrationOptions,
) -> Result<Solved, CalibrateError> {
    let samples: Vec<&Measured> = data
        .touches
        .iter()
        .chain(data.scans.iter().flat_map(|s| s.samples.iter()))
        .collect();
    let terms = gain_terms(data, opts);
    let (mut centre, mut r) = start(&data.touches, p0, opts)?;
    let mut gain = [Mat3::zeros(); CORRECTION_TERMS];
    let mut iterations = 0;
    while iterations < opts.max_iterations {
        iterations += 1;
        let step = gauss_newton_step(&samples, p0, centre, r, &gain, terms, opts)?;
        centre += Vec3::new(step[0], step[1], step[2]);
        r += step[3];
        apply_gain_step(&mut gain, &step, terms);
        if step.amax() <= opts.step_tolerance_mm {
            break;
        }
    }
    let mut correction = DeflectionCorrection {
        gain,
        ..DeflectionCorrection::identity()
    };
    correction.tilt = tilts(data, p0, centre, &correction, opts);
    let residual_rms_mm = rms(samples
        .iter()
        .map(|m| residual(m, p0, centre, r, &correction.gain, opts)));
    Ok(Solved {
        centre,
        tip_radius_mm: r,
        correction,
        residual_rms_mm,
        gain_terms: terms,
        iterations,
    })
}

/// Root mean square of values.
pub fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n.max(1) as f64).sqrt()
}

/// Gain terms `E_0 .. E_{n-1}` the data can carry: the radial effect of the
/// gain is `dp (e_0 + e_1 dp + ..)` beside the constant tip radius, so `n`
/// terms need `n + 1` distinct deflections (touch trigger and scan targets).
fn gain_terms(data: &SphereReadings, opts: &CalibrationOptions) -> usize {
    let mut levels: Vec<f64> = data.scans.iter().map(|s| s.deflection_mm).collect();
    levels.push(opts.modes.trigger_mm);
    levels.sort_by(f64::total_cmp);
    levels.dedup_by(|a, b| (*a - *b).abs() < opts.level_tolerance_mm);
    (levels.len().max(1) - 1).min(CORRECTION_TERMS)
}

/// Start values: least-squares sphere through the touch-point ball centres.
fn start(
    touches: &[Measured],
    p0: Vec3,
    opts: &CalibrationOptions,
) -> Result<(Point3, f64), CalibrateError> {
    let balls: Vec<Point3> = touches.iter().map(|m| m.scales + p0 + m.reading).collect();
    let report = fit(
        ElementKind::Sphere,
        Method::Lsq,
        &balls,
        &FitOptions::default(),
    )?;
    match report.element {
        Element::Sphere(s) => Ok((s.center, s.radius - opts.sphere_radius())),
        _ => Err(CalibrateError::NotConverged {
            iterations: report.iterations,
        }),
    }
}

fn ball_offset(m: &Measured, p0: Vec3, centre: Point3, gain: &[Mat3; CORRECTION_TERMS]) -> Vec3 {
    let d = DeflectionCorrection {
        gain: *gain,
        ..DeflectionCorrection::identity()
    }
    .deflection(m.reading);
    m.scales + p0 + d - centre
}

fn residual(
    m: &Measured,
    p0: Vec3,
    centre: Point3,
    r: f64,
    gain: &[Mat3; CORRECTION_TERMS],
    opts: &CalibrationOptions,
) -> f64 {
    ball_offset(m, p0, centre, gain).norm() - opts.sphere_radius() - r
}

/// One Gauss-Newton step `[dc (3), dr, dE_0 (6), ..]` by the normal equations.
fn gauss_newton_step(
    samples: &[&Measured],
    p0: Vec3,
    centre: Point3,
    r: f64,
    gain: &[Mat3; CORRECTION_TERMS],
    terms: usize,
    opts: &CalibrationOptions,
) -> Result<DVector<f64>, CalibrateError> {
    let cols = 4 + 6 * terms;
    let mut jtj = DMatrix::<f64>::zeros(cols, cols);
    let mut jtf = DVector::<f64>::zeros(cols);
    for m in samples {
        let v = ball_offset(m, p0, centre, gain);
        let u = v.try_normalize(1e-12).unwrap_or_else(Vec3::z);
        let row = jacobian_row(m, &u, terms, cols);
        let f = v.norm() - opts.sphere_radius() - r;
        jtj += &row * row.transpose();
        jtf += &row * f;
    }
    let step = jtj
        .cholesky()
        .ok_or(CalibrateError::Singular { unknowns: cols })?
        .solve(&(-jtf));
    Ok(step)
}

fn jacobian_row(m: &Measured, u: &Vec3, terms: usize, cols: usize) -> DVector<f64> {
    let mut row = DVector::<f64>::zeros(cols);
    row.rows_mut(0, 3).copy_from(&(-u));
    row[3] = -1.0;
    let (rd, dp) = (m.reading, m.reading.norm());
    for k in 0..terms {
        let scale = dp.powi(k as i32);
        for (j, &(a, b)) in SYM.iter().enumerate() {
            let g = if a == b {
                u[a] * rd[a]
            } else {
                u[a] * rd[b] + u[b] * rd[a]
            };
            row[4 + 6 * k + j] = g * scale;
        }
    }
    row
}

fn apply_gain_step(gain: &mut [Mat3; CORRECTION_TERMS], step: &DVector<f64>, terms: usize) {
    for (k, e) in gain.iter_mut().enumerate().take(terms) {
        for (j, &(a, b)) in SYM.iter().enumerate() {
            let delta = step[4 + 6 * k + j];
            e[(a, b)] += delta;
            if a != b {
                e[(b, a)] += delta;
            }
        }
    }
}

/// Normal tilt polynomials per plane and direction from the scans.
fn tilts(
    data: &SphereReadings,
    p0: Vec3,
    centre: Point3,
    fix: &DeflectionCorrection,
    opts: &CalibrationOptions,
) -> [[DeflectionPoly; 2]; 3] {
    let mut groups: [[Vec<(f64, f64, f64)>; 2]; 3] = Default::default();
    for m in data.scans.iter().flat_map(|s| s.samples.iter()) {
        if let Some((k, dir, sample)) = tilt_sample(m, p0, centre, fix) {
            if let Some(g) = groups.get_mut(k).and_then(|g| g.get_mut(dir)) {
                g.push(sample);
            }
        }
    }
    let fitted = groups.map(|g| g.map(|s| fit_poly(&s, opts)));
    fill_missing(fitted)
}

/// (plane, direction, (deflection, tilt, weight)) of one scan reading.
fn tilt_sample(
    m: &Measured,
    p0: Vec3,
    centre: Point3,
    fix: &DeflectionCorrection,
) -> Option<(usize, usize, (f64, f64, f64))> {
    let d = fix.deflection(m.reading);
    let cond = ScanCondition::of(d, m.motion)?;
    let n = (m.scales + p0 + d - centre).try_normalize(1e-12)?;
    let u = d.try_normalize(1e-12)?;
    let phi = n.dot(&cond.across).atan2(n.dot(&u));
    let (k, dir) = cond.dominant();
    Some((k, dir, (m.reading.norm(), phi, cond.axis[k].powi(2))))
}

/// Weighted least-squares polynomial in the deflection, its degree limited
/// by the levels the readings were taken at; `None` without data.
fn fit_poly(samples: &[(f64, f64, f64)], opts: &CalibrationOptions) -> Option<DeflectionPoly> {
    let levels: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let terms = held_levels(levels, opts).min(CORRECTION_TERMS);
    if terms == 0 {
        return None;
    }
    let mut ata = DMatrix::<f64>::zeros(terms, terms);
    let mut atb = DVector::<f64>::zeros(terms);
    for &(x, y, w) in samples {
        let row = DVector::from_fn(terms, |i, _| x.powi(i as i32));
        ata += &row * row.transpose() * w;
        atb += &row * (y * w);
    }
    let sol = ata.cholesky()?.solve(&atb);
    let mut poly = [0.0; CORRECTION_TERMS];
    poly.iter_mut().zip(sol.iter()).for_each(|(p, s)| *p = *s);
    Some(poly)
}

/// The number of levels among the deflections `d` (runs within
/// [`CalibrationOptions::level_tolerance_mm`] of their first, sorted) that
/// hold at least [`CalibrationOptions::level_min_share`] of them; at least
/// one when there are any.
fn held_levels(mut d: Vec<f64>, opts: &CalibrationOptions) -> usize {
    d.sort_by(f64::total_cmp);
    let need = opts.level_min_share * d.len() as f64;
    let mut runs: Vec<(f64, usize)> = Vec::new();
    for x in d {
        match runs.last_mut() {
            Some((first, n)) if x - *first < opts.level_tolerance_mm => *n += 1,
            _ => runs.push((x, 1)),
        }
    }
    let held = runs.iter().filter(|r| r.1 as f64 >= need).count();
    held.max(usize::from(!runs.is_empty()))
}

/// Missing (plane, direction) groups take the other direction of the same
/// plane, else the mean of all fitted groups, else zero.
fn fill_missing(fitted: [[Option<DeflectionPoly>; 2]; 3]) -> [[DeflectionPoly; 2]; 3] {
    let all: Vec<DeflectionPoly> = fitted.iter().flatten().flatten().copied().collect();
    let mean = mean_poly(&all);
    fitted.map(|[cw, ccw]| {
        let other = cw.or(ccw).unwrap_or(mean);
        [cw.unwrap_or(other), ccw.unwrap_or(other)]
    })
}

fn mean_poly(polys: &[DeflectionPoly]) -> DeflectionPoly {
    let n = polys.len().max(1) as f64;
    let mut out = [0.0; CORRECTION_TERMS];
    for p in polys {
        out.iter_mut().zip(p).for_each(|(o, c)| *o += c / n);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Readings of scans at 0.2 and 0.5 mm with a few on the way to and
    /// from each (a scan's start and end): two levels, not five.
    #[test]
    fn the_readings_on_the_way_to_a_level_are_no_level() {
        let opts = CalibrationOptions::default();
        let mut d: Vec<f64> = (0..200).map(|i| 0.196 + 1e-5 * (i % 7) as f64).collect();
        d.extend((0..150).map(|i| 0.497 + 1e-5 * (i % 5) as f64));
        d.extend([0.05, 0.12, 0.219, 0.31, 0.44]);
        assert_eq!(held_levels(d.clone(), &opts), 2);
        // Every run counts when each holds its share.
        let loose = CalibrationOptions {
            level_min_share: 0.0,
            ..opts.clone()
        };
        assert_eq!(held_levels(d, &loose), 7);
        assert_eq!(held_levels(vec![0.3], &opts), 1);
        assert_eq!(held_levels(Vec::new(), &opts), 0);
    }
}
