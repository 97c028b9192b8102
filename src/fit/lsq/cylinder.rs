//! Least-squares cylinder, NIST parameterisation: in the frame of the
//! current axis (through the axis point nearest the centroid) the local
//! parameters are the axis point shift (x0, y0), the axis tilt (a, b) and
//! the radius. Starting values: each principal axis of the points in turn,
//! with the Kasa circle of the points projected along it; every start is
//! refined on a sample and the best is refined on all points. This handles
//! long, short (disc-like) and partial-arc cylinders alike.
use crate::fit::algebraic::kasa;
use crate::fit::frame::{canonical_sign, centre, frame_for, subsample, Centred};
use crate::fit::gauss_newton::{iterate, least_squares, Solved, START_ITERATIONS};
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{Cylinder, FitError, FitOptions};
use crate::math::{Mat3, Point3, Vec3};

const NAME: &str = "cylinder";

/// A cylinder (or, with radius 0, a line) in centred coordinates.
#[derive(Debug, Clone)]
pub(crate) struct CylinderModel {
    /// Rows `(e1, e2, axis)`.
    pub rot: Mat3,
    /// Point of the axis nearest the origin, mm.
    pub origin: Vec3,
    /// Radius, mm.
    pub radius: f64,
}

impl CylinderModel {
    /// A model on the axis through `origin` along `axis`.
    pub fn new(axis: &Vec3, origin: Vec3, radius: f64) -> Self {
        let axis = axis.normalize();
        let origin = origin - axis * axis.dot(&origin);
        CylinderModel {
            rot: frame_for(&axis),
            origin,
            radius,
        }
    }

    /// The unit axis.
    pub fn axis(&self) -> Vec3 {
        self.rot.row(2).transpose()
    }
}

/// Moves the axis through `origin` along the local axis by a step.
pub(crate) fn step_axis(rot: &Mat3, origin: &Vec3, delta: &[f64; MAX_PARAMS]) -> (Vec3, Vec3) {
    let origin = origin + rot.transpose() * Vec3::new(delta[0], delta[1], 0.0);
    let axis = rot.transpose() * Vec3::new(delta[2], delta[3], 1.0).normalize();
    (axis, origin)
}

impl Model for CylinderModel {
    const SHAPE: usize = 4;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        let q = self.rot * (p - self.origin);
        let rho = (q.x * q.x + q.y * q.y).sqrt();
        let inv = if rho > 0.0 { 1.0 / rho } else { 0.0 };
        let (cx, cy) = (-q.x * inv, -q.y * inv);
        (grad[0], grad[1], grad[2], grad[3]) = (cx, cy, cx * q.z, cy * q.z);
        rho
    }

    fn value(&self, p: &Vec3) -> f64 {
        let q = self.rot * (p - self.origin);
        (q.x * q.x + q.y * q.y).sqrt()
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        let (axis, origin) = step_axis(&self.rot, &self.origin, delta);
        CylinderModel::new(&axis, origin, self.radius + delta[4])
    }

    fn size(&self) -> f64 {
        self.radius
    }

    fn with_size(&self, size: f64) -> Self {
        CylinderModel {
            radius: size,
            ..self.clone()
        }
    }

    fn angular(k: usize) -> bool {
        k == 2 || k == 3
    }

    fn is_finite(&self) -> bool {
        let parts = [self.rot.as_slice(), self.origin.as_slice()];
        self.radius.is_finite() && parts.iter().all(|s| crate::math::all_finite(s))
    }
}

/// The start on axis direction `axis`: the Kasa circle of the projection.
pub(crate) fn start_on_axis(points: &[Vec3], axis: &Vec3) -> Option<CylinderModel> {
    let rot = frame_for(axis);
    let local: Vec<Vec3> = points.iter().map(|p| rot * p).collect();
    let (c, r) = kasa(&local, 2)?;
    Some(CylinderModel::new(
        axis,
        rot.transpose() * Vec3::new(c.x, c.y, 0.0),
        r,
    ))
}

/// The best of several starts after at most `START_ITERATIONS` iterations
/// each on `points` (converged or not; the winner is refined later).
pub(crate) fn best_of<M: Model + Sync>(
    starts: Vec<M>,
    points: &[Vec3],
    extent: f64,
    opts: &FitOptions,
    name: &'static str,
) -> Result<Solved<M>, FitError> {
    let tried = starts.len();
    starts
        .into_iter()
        .map(|s| iterate(s, points, extent, opts, START_ITERATIONS).0)
        .filter(|s| s.rms.is_finite())
        .min_by(|a, b| a.rms.total_cmp(&b.rms))
        .ok_or(FitError::NoStart {
            element: name,
            tried,
        })
}

/// Checks and centres the points, then fits the least-squares cylinder.
pub(crate) fn lsq(
    points: &[Point3],
    opts: &FitOptions,
) -> Result<(Centred, Solved<CylinderModel>), FitError> {
    let c = centre(points, NAME, 5)?;
    let pa = c.principal();
    pa.check_volume(NAME, c.points.len(), opts.degenerate_ratio)?;
    let sample = subsample(&c.points, opts.start_sample);
    let starts = pa
        .axes
        .iter()
        .filter_map(|a| start_on_axis(&sample, a))
        .collect();
    let best = best_of(starts, &sample, c.extent, opts, NAME)?;
    let solved = least_squares(best.model, &c.points, c.extent, opts, NAME)?;
    let iterations = solved.iterations + best.iterations;
    Ok((
        c,
        Solved {
            iterations,
            ..solved
        },
    ))
}

/// [`lsq`], and the least-squares cylinder started on the axis direction
/// `axis` (the nominal one) when that comes within
/// [`FitOptions::nominal_preference_mm`] of its RMS residual.
pub(crate) fn lsq_near(
    points: &[Point3],
    opts: &FitOptions,
    axis: &Vec3,
) -> Result<(Centred, Solved<CylinderModel>), FitError> {
    let (c, free) = lsq(points, opts)?;
    let near = start_on_axis(&c.points, axis)
        .and_then(|s| least_squares(s, &c.points, c.extent, opts, NAME).ok());
    match near {
        Some(n) if n.rms <= free.rms + opts.nominal_preference_mm => Ok((c, n)),
        _ => Ok((c, free)),
    }
}

/// The cylinder of a model in the frame of `c`.
pub(crate) fn to_element(c: &Centred, m: &CylinderModel) -> Cylinder {
    Cylinder {
        axis_point: Point3::from(c.centroid + m.origin),
        axis_direction: canonical_sign(m.axis()),
        radius: m.radius,
    }
}
