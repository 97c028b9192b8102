//! Least-squares lines. 3-D: the centroid and the principal axis, refined
//! by linearised regressions in the line's frame. 2-D (xy plane, z
//! ignored): Gauss-Newton on the angle and the offset.
use crate::fit::frame::{canonical_sign, centre, frame_for, Centred};
use crate::fit::gauss_newton::{least_squares, Solved};
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{FitError, FitOptions, Line};
use crate::math::{Point3, Vec3};

/// Most refinement passes of the 3-D line (each is one linear regression).
const LINE_PASSES: usize = 8;

/// A line in the xy plane: `left(theta) . p = offset` (centred coordinates).
#[derive(Debug, Clone)]
pub(crate) struct Line2dModel {
    /// Direction angle from +x, radians.
    pub theta: f64,
    /// Signed distance of the line from the centroid, mm.
    pub offset: f64,
}

impl Line2dModel {
    fn direction(&self) -> Vec3 {
        Vec3::new(self.theta.cos(), self.theta.sin(), 0.0)
    }

    fn left(&self) -> Vec3 {
        Vec3::new(-self.theta.sin(), self.theta.cos(), 0.0)
    }
}

impl Model for Line2dModel {
    const SHAPE: usize = 1;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        grad[0] = -self.direction().dot(p);
        self.left().dot(p)
    }

    fn value(&self, p: &Vec3) -> f64 {
        self.left().dot(p)
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        Line2dModel {
            theta: self.theta + delta[0],
            offset: self.offset + delta[1],
        }
    }

    fn size(&self) -> f64 {
        self.offset
    }

    fn with_size(&self, size: f64) -> Self {
        Line2dModel {
            offset: size,
            ..self.clone()
        }
    }

    fn angular(k: usize) -> bool {
        k == 0
    }

    fn is_finite(&self) -> bool {
        self.theta.is_finite() && self.offset.is_finite()
    }
}

/// Checks, flattens (z = 0) and centres the points, then fits the 2-D line.
pub(crate) fn lsq_2d(
    points: &[Point3],
    opts: &FitOptions,
) -> Result<(Centred, Solved<Line2dModel>), FitError> {
    let flat: Vec<Point3> = points.iter().map(|p| Point3::new(p.x, p.y, 0.0)).collect();
    let mut c = centre(&flat, "line2d", 2)?;
    let pa = c.principal();
    pa.check_spread("line2d", c.points.len(), 0.0)?;
    c.centroid.z = mean_z(points);
    let start = Line2dModel {
        theta: pa.axes[0].y.atan2(pa.axes[0].x),
        offset: 0.0,
    };
    let solved = least_squares(start, &c.points, c.extent, opts, "line2d")?;
    Ok((c, solved))
}

fn mean_z(points: &[Point3]) -> f64 {
    points.iter().map(|p| p.z).sum::<f64>() / points.len().max(1) as f64
}

/// The 2-D line of a model in the frame of `c`.
pub(crate) fn to_element_2d(c: &Centred, m: &Line2dModel) -> Line {
    let point = Point3::from(c.centroid + m.left() * m.offset);
    Line {
        point,
        direction: canonical_sign(m.direction()),
    }
}

/// Least-squares 3-D line: returns the centred points, the unit direction
/// (in the line through the centroid) and the passes made.
pub(crate) fn lsq_3d(
    points: &[Point3],
    opts: &FitOptions,
) -> Result<(Centred, Vec3, usize), FitError> {
    let c = centre(points, "line", 2)?;
    let pa = c.principal();
    pa.check_spread("line", c.points.len(), 0.0)?;
    let mut dir = pa.axes[0];
    for pass in 1..=LINE_PASSES {
        let (next, tilt) = regression_step(&c.points, &dir);
        dir = next;
        if tilt * c.extent <= opts.step_tolerance_mm.max(64.0 * f64::EPSILON * c.extent) {
            return Ok((c, dir, pass));
        }
    }
    Ok((c, dir, LINE_PASSES))
}

/// One regression `x = a z, y = b z` in the frame of `dir`; returns the
/// new direction and the tilt `|(a, b)|` (radians).
fn regression_step(points: &[Vec3], dir: &Vec3) -> (Vec3, f64) {
    let rot = frame_for(dir);
    let (mut xz, mut yz, mut zz) = (0.0, 0.0, 0.0);
    for p in points {
        let q = rot * p;
        (xz, yz, zz) = (xz + q.x * q.z, yz + q.y * q.z, zz + q.z * q.z);
    }
    let (a, b) = (xz / zz, yz / zz);
    let next = rot.transpose() * Vec3::new(a, b, 1.0).normalize();
    (next, a.hypot(b))
}

/// The 3-D line through the centroid of `c` along `dir`.
pub(crate) fn to_element_3d(c: &Centred, dir: &Vec3) -> Line {
    Line {
        point: Point3::from(c.centroid),
        direction: canonical_sign(*dir),
    }
}
