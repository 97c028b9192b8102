//! Exact NURBS forms of planes, cylinders, cones, spheres and tori, and the
//! analytic mapping of 3-D points to their "natural" parameters.
//!
//! Natural parameters: plane `(x, y)` in the placement; cylinder and cone
//! `(angle, axial height)`; sphere `(longitude, latitude)`; torus
//! `(major angle, minor angle)`. Angles are mapped to NURBS parameters with
//! [`Arc::param`]; lengths are used as NURBS parameters unchanged.
use super::arc::Arc;
use super::revolve::{bilinear_plane, revolve, Profile};
use crate::cad::geom::{angle, Frame};
use crate::cad::geom::{EPS_LENGTH_MM, EPS_PARAM};
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Point3, Vec3};
use std::f64::consts::FRAC_PI_2;

/// A surface whose points map analytically to "natural" parameters, from
/// which its NURBS form and face trims are built (see [`super::trim`]).
pub trait NaturalSurface {
    /// Which natural parameters are angles (periodic).
    fn periodic(&self) -> [bool; 2];
    /// Length per natural unit of each parameter, for margins (mm).
    fn metric(&self) -> [f64; 2];
    /// Natural parameters of `p`; `None` for the first one where it is
    /// undefined (on the axis).
    fn natural(&self, p: Point3, singular_tol: f64) -> (Option<f64>, f64);
    /// Restricts the second range to where it is valid (`sample` is a
    /// typical value of the face).
    fn clamp_v(&self, lo: f64, hi: f64, sample: f64) -> (f64, f64);
    /// Extends the second range to a pole or apex on the face's side.
    fn extend_v(&self, range: (f64, f64), high: bool) -> (f64, f64);
    /// True when parameter `axis` always spans a fixed range (a profile
    /// curve's domain), whatever the face's extent.
    fn fixed(&self, _axis: usize) -> bool {
        false
    }
    /// The natural-to-NURBS parameter maps for the given natural ranges.
    fn maps(&self, u: (f64, f64), v: (f64, f64)) -> [AxisMap; 2];
    /// The NURBS surface over the maps' ranges (name left empty).
    fn to_nurbs(&self, maps: &[AxisMap; 2]) -> SurfaceSpec;
}

/// An elementary surface in its placement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Analytic {
    /// PLANE; normal = frame z.
    Plane(Frame),
    /// CYLINDRICAL_SURFACE of radius `r`.
    Cylinder(Frame, f64),
    /// CONICAL_SURFACE: radius `r` at height 0, semi-angle (rad).
    Cone(Frame, f64, f64),
    /// SPHERICAL_SURFACE of radius `r`.
    Sphere(Frame, f64),
    /// TOROIDAL_SURFACE: major and minor radius.
    Torus(Frame, f64, f64),
}

/// How one natural parameter maps to the NURBS parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxisMap {
    /// NURBS parameter = natural parameter (a length).
    Linear(f64, f64),
    /// Angle mapped through a rational arc.
    Angle(Arc),
}

impl AxisMap {
    /// The NURBS parameter of natural value `x`.
    pub fn map(&self, x: f64) -> f64 {
        match self {
            AxisMap::Linear(lo, hi) => x.max(*lo).min(*hi),
            AxisMap::Angle(arc) => arc.param(x),
        }
    }

    /// The natural range.
    pub fn range(&self) -> (f64, f64) {
        match self {
            AxisMap::Linear(lo, hi) => (*lo, *hi),
            AxisMap::Angle(a) => (a.start, a.start + a.sweep),
        }
    }
}

impl Analytic {
    /// The placement.
    pub fn frame(&self) -> Frame {
        match self {
            Analytic::Plane(f) | Analytic::Cylinder(f, _) | Analytic::Cone(f, _, _) => *f,
            Analytic::Sphere(f, _) | Analytic::Torus(f, _, _) => *f,
        }
    }
}

impl NaturalSurface for Analytic {
    /// Which natural parameters are angles (periodic).
    fn periodic(&self) -> [bool; 2] {
        match self {
            Analytic::Plane(_) => [false, false],
            Analytic::Torus(..) => [true, true],
            _ => [true, false],
        }
    }

    /// Length per radian of each natural parameter (1 for lengths), for margins.
    fn metric(&self) -> [f64; 2] {
        match *self {
            Analytic::Plane(_) => [1.0, 1.0],
            Analytic::Cylinder(_, r) | Analytic::Cone(_, r, _) => [r.abs().max(EPS_LENGTH_MM), 1.0],
            Analytic::Sphere(_, r) => [r.abs().max(EPS_LENGTH_MM); 2],
            Analytic::Torus(_, big, small) => [
                (big + small).abs().max(EPS_LENGTH_MM),
                small.abs().max(EPS_LENGTH_MM),
            ],
        }
    }

    /// Natural parameters of `p`; `None` for the first one on the axis
    /// (cone apex, sphere poles), where the angle is undefined.
    fn natural(&self, p: Point3, singular_tol: f64) -> (Option<f64>, f64) {
        let l: Vec3 = self.frame().local(p);
        let rho = l.x.hypot(l.y);
        let theta = (rho > singular_tol).then(|| angle(l.y, l.x));
        match *self {
            Analytic::Plane(_) => (Some(l.x), l.y),
            Analytic::Cylinder(..) | Analytic::Cone(..) => (theta, l.z),
            Analytic::Sphere(..) => (theta, l.z.atan2(rho)),
            Analytic::Torus(_, big, _) => (theta, l.z.atan2(rho - big)),
        }
    }

    /// Clamps a natural range of the second parameter to where it is valid
    /// (sphere latitude within the poles; a cone on one side of its apex).
    fn clamp_v(&self, lo: f64, hi: f64, sample: f64) -> (f64, f64) {
        match *self {
            Analytic::Sphere(..) => (lo.max(-FRAC_PI_2), hi.min(FRAC_PI_2)),
            Analytic::Cone(_, r, semi) if semi.tan().abs() > EPS_PARAM => {
                let apex = -r / semi.tan();
                if sample >= apex {
                    (lo.max(apex), hi)
                } else {
                    (lo, hi.min(apex))
                }
            }
            _ => (lo, hi),
        }
    }

    /// Extends the second natural range to the pole (sphere) or apex (cone)
    /// on the face's side, for faces bounded by a single loop round the axis.
    fn extend_v(&self, (lo, hi): (f64, f64), high: bool) -> (f64, f64) {
        match *self {
            Analytic::Sphere(..) if high => (lo, FRAC_PI_2),
            Analytic::Sphere(..) => (-FRAC_PI_2, hi),
            Analytic::Cone(_, r, semi) if semi.tan().abs() > EPS_PARAM => {
                let apex = -r / semi.tan();
                match (high, apex > hi, apex < lo) {
                    (true, true, _) => (lo, apex),
                    (false, _, true) => (apex, hi),
                    _ => (lo, hi),
                }
            }
            _ => (lo, hi),
        }
    }

    /// The axis maps for natural ranges `u` and `v`.
    fn maps(&self, u: (f64, f64), v: (f64, f64)) -> [AxisMap; 2] {
        let [pu, pv] = self.periodic();
        let m = |periodic: bool, (lo, hi): (f64, f64)| {
            if periodic {
                AxisMap::Angle(Arc::new(lo, hi))
            } else {
                AxisMap::Linear(lo, hi)
            }
        };
        let v_map = match self {
            Analytic::Sphere(..) => AxisMap::Angle(Arc::new(v.0, v.1)),
            _ => m(pv, v),
        };
        [m(pu, u), v_map]
    }

    /// The exact NURBS surface over the given axis maps (name left empty).
    fn to_nurbs(&self, maps: &[AxisMap; 2]) -> SurfaceSpec {
        let frame = self.frame();
        let [mu, mv] = maps;
        let AxisMap::Angle(arc) = mu else {
            let ((x0, x1), (y0, y1)) = (mu.range(), mv.range());
            return bilinear_plane(&frame, [x0, x1], [y0, y1]);
        };
        revolve(&frame, arc, &self.profile(mv))
    }
}

impl Analytic {
    /// The profile in the frame's xz half-plane (local coordinates).
    fn profile(&self, mv: &AxisMap) -> Profile {
        let (h0, h1) = mv.range();
        let straight = |r0: f64, r1: f64| {
            Profile::line(Vec3::new(r0, 0.0, h0), Vec3::new(r1, 0.0, h1), h0, h1)
        };
        match (*self, mv) {
            (Analytic::Sphere(_, r), AxisMap::Angle(a)) => Profile::arc(a, 0.0, r),
            (Analytic::Torus(_, big, small), AxisMap::Angle(a)) => Profile::arc(a, big, small),
            (Analytic::Cone(_, r, semi), _) => straight(r + h0 * semi.tan(), r + h1 * semi.tan()),
            (Analytic::Cylinder(_, r), _) => straight(r, r),
            _ => straight(0.0, 0.0),
        }
    }
}
