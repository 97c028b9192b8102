//! Least-squares plane: the normal is the least principal axis of the
//! centred points, refined by Gauss-Newton (tilt about the centroid plus
//! offset along the normal).
use crate::fit::frame::{canonical_sign, centre, frame_for, Centred};
use crate::fit::gauss_newton::{least_squares, Solved};
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{FitError, FitOptions, Plane};
use crate::math::{Mat3, Point3, Vec3};

const NAME: &str = "plane";

/// The plane `n . p = offset` in centred coordinates; `rot` has rows
/// `(e1, e2, n)`.
#[derive(Debug, Clone)]
pub(crate) struct PlaneModel {
    /// Local frame, third row the normal.
    pub rot: Mat3,
    /// Signed distance of the plane from the centroid along the normal, mm.
    pub offset: f64,
}

impl PlaneModel {
    /// The unit normal.
    pub fn normal(&self) -> Vec3 {
        self.rot.row(2).transpose()
    }
}

impl Model for PlaneModel {
    const SHAPE: usize = 2;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        let q = self.rot * p;
        (grad[0], grad[1]) = (q.x, q.y);
        q.z
    }

    fn value(&self, p: &Vec3) -> f64 {
        self.normal().dot(p)
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        let n = self.rot.transpose() * Vec3::new(delta[0], delta[1], 1.0).normalize();
        PlaneModel {
            rot: frame_for(&n),
            offset: self.offset + delta[2],
        }
    }

    fn size(&self) -> f64 {
        self.offset
    }

    fn with_size(&self, size: f64) -> Self {
        PlaneModel {
            offset: size,
            ..self.clone()
        }
    }

    fn angular(k: usize) -> bool {
        k < 2
    }

    fn is_finite(&self) -> bool {
        self.offset.is_finite() && crate::math::all_finite(self.rot.as_slice())
    }
}

/// Checks and centres the points, then fits the least-squares plane.
pub(crate) fn lsq(
    points: &[Point3],
    opts: &FitOptions,
    element: &'static str,
) -> Result<(Centred, Solved<PlaneModel>), FitError> {
    let c = centre(points, element, 3)?;
    let pa = c.principal();
    pa.check_spread(element, c.points.len(), opts.degenerate_ratio)?;
    let start = PlaneModel {
        rot: frame_for(&pa.axes[2]),
        offset: 0.0,
    };
    let solved = least_squares(start, &c.points, c.extent, opts, element)?;
    Ok((c, solved))
}

/// The plane of a model in the frame of `c`.
pub(crate) fn to_element(c: &Centred, m: &PlaneModel) -> Plane {
    let normal = canonical_sign(m.normal());
    let point = Point3::from(c.centroid + m.normal() * m.offset);
    Plane { point, normal }
}

/// Least-squares plane of `points`.
pub(crate) fn fit(points: &[Point3], opts: &FitOptions) -> Result<(Plane, usize), FitError> {
    let (c, solved) = lsq(points, opts, NAME)?;
    Ok((to_element(&c, &solved.model), solved.iterations))
}
