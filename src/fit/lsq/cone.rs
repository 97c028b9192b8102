//! Least-squares cone, NIST parameterisation: in the frame of the current
//! axis (through the axis point nearest the centroid) the local parameters
//! are the axis point shift (x0, y0), the axis tilt (a, b), the half apex
//! angle psi and the orthogonal distance s from the axis point to the
//! surface. The distance of a local point is `rho cos(psi) - z sin(psi) - s`.
//! Starting values: for each principal axis, the Kasa circle of the
//! projected points gives the axis, a straight-line fit of radius against
//! height gives psi and s; the best start after refinement on a sample wins.
use crate::fit::frame::{centre, subsample, Centred};
use crate::fit::gauss_newton::{least_squares, Solved};
use crate::fit::lsq::cylinder::{best_of, start_on_axis, step_axis, CylinderModel};
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{Cone, FitError, FitOptions};
use crate::math::{Mat3, Point3, Vec3};

const NAME: &str = "cone";

/// A cone in centred coordinates.
#[derive(Debug, Clone)]
pub(crate) struct ConeModel {
    /// Rows `(e1, e2, axis)`.
    pub rot: Mat3,
    /// Point of the axis nearest the origin, mm.
    pub origin: Vec3,
    /// Half apex angle, radians (negative: radius shrinks along the axis).
    pub psi: f64,
    /// Orthogonal distance from `origin` to the surface, mm.
    pub s: f64,
}

impl ConeModel {
    /// A model whose axis passes through `origin` along `axis`.
    fn new(axis: &Vec3, origin: Vec3, psi: f64, s: f64) -> Self {
        let axis = axis.normalize();
        let t = -axis.dot(&origin);
        let rot = crate::fit::frame::frame_for(&axis);
        ConeModel {
            rot,
            origin: origin + axis * t,
            psi,
            s: s + t * psi.sin(),
        }
    }
}

impl Model for ConeModel {
    const SHAPE: usize = 5;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        let q = self.rot * (p - self.origin);
        let rho = (q.x * q.x + q.y * q.y).sqrt();
        let inv = if rho > 0.0 { 1.0 / rho } else { 0.0 };
        let (sn, cs) = self.psi.sin_cos();
        let (ux, uy) = (q.x * inv, q.y * inv);
        grad[0] = -ux * cs;
        grad[1] = -uy * cs;
        grad[2] = -ux * q.z * cs - q.x * sn;
        grad[3] = -uy * q.z * cs - q.y * sn;
        grad[4] = -rho * sn - q.z * cs;
        rho * cs - q.z * sn
    }

    fn value(&self, p: &Vec3) -> f64 {
        let q = self.rot * (p - self.origin);
        let (sn, cs) = self.psi.sin_cos();
        (q.x * q.x + q.y * q.y).sqrt() * cs - q.z * sn
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        let (axis, origin) = step_axis(&self.rot, &self.origin, delta);
        ConeModel::new(&axis, origin, self.psi + delta[4], self.s + delta[5])
    }

    fn size(&self) -> f64 {
        self.s
    }

    fn with_size(&self, size: f64) -> Self {
        ConeModel {
            s: size,
            ..self.clone()
        }
    }

    fn angular(k: usize) -> bool {
        (2..=4).contains(&k)
    }

    fn is_finite(&self) -> bool {
        let parts = [self.rot.as_slice(), self.origin.as_slice()];
        (self.s + self.psi).is_finite() && parts.iter().all(|s| crate::math::all_finite(s))
    }
}

/// A cone start from a cylinder start: radius against height by least squares.
fn cone_start(points: &[Vec3], cyl: &CylinderModel) -> Option<ConeModel> {
    let n = points.len() as f64;
    let (mut sz, mut sr, mut szz, mut szr) = (0.0, 0.0, 0.0, 0.0);
    for p in points {
        let q = cyl.rot * (p - cyl.origin);
        let r = (q.x * q.x + q.y * q.y).sqrt();
        (sz, sr, szz, szr) = (sz + q.z, sr + r, szz + q.z * q.z, szr + q.z * r);
    }
    let slope = (n * szr - sz * sr) / (n * szz - sz * sz);
    let r0 = (sr - slope * sz) / n;
    let psi = slope.atan();
    let model = ConeModel::new(&cyl.axis(), cyl.origin, psi, r0 * psi.cos());
    model.is_finite().then_some(model)
}

/// Checks and centres the points, then fits the least-squares cone.
pub(crate) fn lsq(
    points: &[Point3],
    opts: &FitOptions,
) -> Result<(Centred, Solved<ConeModel>), FitError> {
    let c = centre(points, NAME, 6)?;
    let pa = c.principal();
    pa.check_volume(NAME, c.points.len(), opts.degenerate_ratio)?;
    let sample = subsample(&c.points, opts.start_sample);
    let starts = pa
        .axes
        .iter()
        .filter_map(|a| start_on_axis(&sample, a))
        .filter_map(|cyl| cone_start(&sample, &cyl))
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

/// The cone of a model in the frame of `c`: axis turned towards growing
/// radius, apex where the radius vanishes.
pub(crate) fn to_element(c: &Centred, m: &ConeModel) -> Result<Cone, FitError> {
    let axis = m.rot.row(2).transpose();
    let (axis, psi) = if m.psi < 0.0 {
        (-axis, -m.psi)
    } else {
        (axis, m.psi)
    };
    let sin = psi.sin();
    if sin.is_nan() || sin <= f64::EPSILON {
        return Err(FitError::DegenerateCone {
            half_angle_deg: psi.to_degrees(),
        });
    }
    let apex = c.centroid + m.origin - axis * (m.s / sin);
    Ok(Cone {
        apex: Point3::from(apex),
        axis_direction: axis,
        half_angle_rad: psi,
    })
}
