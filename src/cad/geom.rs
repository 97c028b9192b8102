//! Frames and the curve types edges are built from.
use super::nurbs::{breaks, NurbsCurve};
use crate::math::{Point3, Vec3};
use std::f64::consts::TAU;

/// Smallest length treated as non-zero (radii, margins per radian), mm.
pub const EPS_LENGTH_MM: f64 = 1e-9;
/// Smallest angle or parameter step treated as non-zero (sweeps, tangents).
pub const EPS_PARAM: f64 = 1e-12;
/// Smallest direction-vector norm accepted before normalising (dimensionless).
pub const EPS_DIRECTION: f64 = 1e-12;
/// Parameter-space distance below which two trim points coincide.
pub const EPS_UV: f64 = 1e-12;

/// Iterations of the golden-section refinement of a closest curve parameter.
const GOLDEN_ITERATIONS: usize = 80;
/// Samples per knot span for the coarse closest-parameter search.
const SEARCH_SAMPLES_PER_SPAN: usize = 16;

/// A right-handed orthonormal frame (AXIS2_PLACEMENT_3D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Origin, mm.
    pub origin: Point3,
    /// Reference direction.
    pub x: Vec3,
    /// `z x x`.
    pub y: Vec3,
    /// Axis.
    pub z: Vec3,
}

impl Frame {
    /// Builds a frame from an axis and an approximate reference direction;
    /// `None` when degenerate.
    pub fn new(origin: Point3, axis: Vec3, reference: Option<Vec3>) -> Option<Frame> {
        let z = axis.try_normalize(EPS_DIRECTION)?;
        let guess = reference.unwrap_or_else(|| {
            if z.x.abs() < 0.9 {
                Vec3::x()
            } else {
                Vec3::y()
            }
        });
        let x = (guess - z * guess.dot(&z))
            .try_normalize(EPS_DIRECTION)
            .or_else(|| z.cross(&Vec3::x()).try_normalize(EPS_DIRECTION))?;
        Some(Frame {
            origin,
            x,
            y: z.cross(&x),
            z,
        })
    }

    /// Local coordinates of `p`.
    pub fn local(&self, p: Point3) -> Vec3 {
        let d = p - self.origin;
        Vec3::new(d.dot(&self.x), d.dot(&self.y), d.dot(&self.z))
    }

    /// World point of local coordinates.
    pub fn world(&self, x: f64, y: f64, z: f64) -> Point3 {
        self.origin + self.x * x + self.y * y + self.z * z
    }
}

/// A 3-D (or 2-D parameter-space) curve.
#[derive(Debug, Clone, PartialEq)]
pub enum Curve {
    /// `origin + t * dir`, STEP's own parameterisation (dir = the VECTOR,
    /// magnitude included).
    Line {
        /// A point on the line.
        origin: Point3,
        /// Direction times magnitude (non-zero).
        dir: Vec3,
    },
    /// Circle in the frame's xy plane, parameter = angle (rad).
    Circle {
        /// Centre and plane.
        frame: Frame,
        /// Radius, mm.
        radius: f64,
    },
    /// Ellipse in the frame's xy plane, parameter = eccentric angle (rad).
    Ellipse {
        /// Centre and plane.
        frame: Frame,
        /// Semi-axis along x, mm.
        a: f64,
        /// Semi-axis along y, mm.
        b: f64,
    },
    /// Rational B-spline.
    Nurbs(NurbsCurve),
}

impl Curve {
    /// The point at parameter `t`.
    pub fn eval(&self, t: f64) -> Point3 {
        match self {
            Curve::Line { origin, dir } => origin + dir * t,
            Curve::Circle { frame, radius } => frame.world(radius * t.cos(), radius * t.sin(), 0.0),
            Curve::Ellipse { frame, a, b } => frame.world(a * t.cos(), b * t.sin(), 0.0),
            Curve::Nurbs(n) => n.point(t),
        }
    }

    /// The period for closed conics.
    pub fn period(&self) -> Option<f64> {
        matches!(self, Curve::Circle { .. } | Curve::Ellipse { .. }).then_some(TAU)
    }

    /// The parameter of the point of the curve closest to `p`.
    pub fn param_of(&self, p: Point3) -> f64 {
        match self {
            Curve::Line { origin, dir } => {
                (p - origin).dot(dir) / dir.norm_squared().max(f64::MIN_POSITIVE)
            }
            Curve::Circle { frame, .. } => angle(frame.local(p).y, frame.local(p).x),
            Curve::Ellipse { frame, a, b } => angle(frame.local(p).y / b, frame.local(p).x / a),
            Curve::Nurbs(n) => closest_param(n, p),
        }
    }
}

/// `atan2` mapped into `[0, 2 pi)`.
pub fn angle(y: f64, x: f64) -> f64 {
    let a = y.atan2(x);
    if a < 0.0 {
        a + TAU
    } else {
        a
    }
}

fn closest_param(n: &NurbsCurve, p: Point3) -> f64 {
    closest_on(&|t| n.point(t), &breaks(n), p)
}

/// The parameter in `[breaks.first, breaks.last]` where `f` comes closest to
/// `p`: coarse samples per interval, then golden-section refinement.
pub fn closest_on(f: &dyn Fn(f64) -> Point3, breaks: &[f64], p: Point3) -> f64 {
    let mut best = (f64::INFINITY, 0.0, 0.0, 0.0);
    for w in breaks.windows(2) {
        let [a, b] = [
            w.first().copied().unwrap_or(0.0),
            w.get(1).copied().unwrap_or(0.0),
        ];
        let h = (b - a) / SEARCH_SAMPLES_PER_SPAN as f64;
        for k in 0..=SEARCH_SAMPLES_PER_SPAN {
            let t = a + h * k as f64;
            let d = (f(t) - p).norm_squared();
            if d < best.0 {
                best = (d, t, (t - h).max(a), (t + h).min(b));
            }
        }
    }
    golden(|t| (f(t) - p).norm_squared(), best.2, best.3)
}

/// Minimises a unimodal `f` on `[a, b]` by golden-section search.
fn golden(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..GOLDEN_ITERATIONS {
        let c = b - r * (b - a);
        let d = a + r * (b - a);
        if f(c) < f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}
