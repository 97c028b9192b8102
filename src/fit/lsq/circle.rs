//! Least-squares circles. 3-D: least-squares plane first, then the circle
//! of the points projected into it (ISO / NIST practice). 2-D: the xy
//! plane at the points' mean z. The in-plane circle is Gauss-Newton from the
//! Kasa fit, which copes with partial arcs.
use crate::fit::algebraic::kasa;
use crate::fit::frame::{canonical_sign, centre, principal, subsample, Centred};
use crate::fit::gauss_newton::{least_squares, presolve, Solved};
use crate::fit::lsq::plane;
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{Circle, FitError, FitOptions};
use crate::math::{Mat3, Point3, Vec3};

/// A circle in plane coordinates (z ignored).
#[derive(Debug, Clone)]
pub(crate) struct CircleModel {
    /// Centre in plane coordinates (z unused), mm.
    pub center: Vec3,
    /// Radius, mm.
    pub radius: f64,
}

impl Model for CircleModel {
    const SHAPE: usize = 2;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        let (dx, dy) = (p.x - self.center.x, p.y - self.center.y);
        let rho = (dx * dx + dy * dy).sqrt();
        let inv = if rho > 0.0 { 1.0 / rho } else { 0.0 };
        (grad[0], grad[1]) = (-dx * inv, -dy * inv);
        rho
    }

    fn value(&self, p: &Vec3) -> f64 {
        {
            let (dx, dy) = (p.x - self.center.x, p.y - self.center.y);
            (dx * dx + dy * dy).sqrt()
        }
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        let center = self.center + Vec3::new(delta[0], delta[1], 0.0);
        CircleModel {
            center,
            radius: self.radius + delta[2],
        }
    }

    fn size(&self) -> f64 {
        self.radius
    }

    fn with_size(&self, size: f64) -> Self {
        CircleModel {
            radius: size,
            ..self.clone()
        }
    }

    fn is_finite(&self) -> bool {
        self.radius.is_finite() && self.center.x.is_finite() && self.center.y.is_finite()
    }
}

/// Points in the circle's plane: `local[i] = rot * (p_i - centroid)`, the
/// plane at local height `height`.
#[derive(Debug, Clone)]
pub(crate) struct InPlane {
    /// Centring of the input.
    pub centred: Centred,
    /// Rows `(e1, e2, normal)`.
    pub rot: Mat3,
    /// Local z of the plane, mm.
    pub height: f64,
    /// Local coordinates of the points, mm.
    pub local: Vec<Vec3>,
}

/// The plane of a 3-D circle (least squares) or of a 2-D circle (xy).
pub(crate) fn in_plane(
    points: &[Point3],
    opts: &FitOptions,
    flat: bool,
) -> Result<InPlane, FitError> {
    let name = if flat { "circle2d" } else { "circle" };
    let (centred, rot, height) = if flat {
        let c = centre(points, name, 3)?;
        (c, Mat3::identity(), 0.0)
    } else {
        let (c, solved) = plane::lsq(points, opts, name)?;
        (c, solved.model.rot, solved.model.offset)
    };
    let local: Vec<Vec3> = centred.points.iter().map(|p| rot * p).collect();
    let flat_pts: Vec<Vec3> = local.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect();
    principal(&flat_pts).check_spread(name, local.len(), opts.degenerate_ratio)?;
    Ok(InPlane {
        centred,
        rot,
        height,
        local,
    })
}

/// Fits the least-squares circle in the plane.
pub(crate) fn lsq(
    plane: &InPlane,
    opts: &FitOptions,
    name: &'static str,
) -> Result<Solved<CircleModel>, FitError> {
    let sample = subsample(&plane.local, opts.start_sample);
    let no_start = FitError::NoStart {
        element: name,
        tried: 1,
    };
    let (center, radius) = kasa(&sample, 2).ok_or(no_start)?;
    let extent = plane.centred.extent;
    let (start, pre) = presolve(CircleModel { center, radius }, &sample, extent, opts);
    let solved = least_squares(start, &plane.local, extent, opts, name)?;
    let iterations = solved.iterations + pre;
    Ok(Solved {
        iterations,
        ..solved
    })
}

/// The circle of a model.
pub(crate) fn to_element(plane: &InPlane, m: &CircleModel) -> Circle {
    let local = Vec3::new(m.center.x, m.center.y, plane.height);
    let center = Point3::from(plane.centred.centroid + plane.rot.transpose() * local);
    let normal = canonical_sign(plane.rot.row(2).transpose());
    Circle {
        center,
        normal,
        radius: m.radius,
    }
}
