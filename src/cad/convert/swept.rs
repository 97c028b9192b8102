//! Surfaces of revolution and of linear extrusion as [`NaturalSurface`]s,
//! so their faces get trims like the elementary surfaces.
//!
//! Revolution: natural `u` = rotation angle about the axis, `v` = the profile
//! NURBS parameter of the meridian point (found by a closest-point search in
//! the (radius, height) half-plane). Extrusion: `u` = the profile NURBS
//! parameter of the point projected along the direction, `v` = the distance
//! along the (unit) direction.
use super::analytic::{AxisMap, NaturalSurface};
use super::arc::Arc;
use super::revolve::{extrude, revolve, Profile};
use crate::cad::geom::EPS_LENGTH_MM;
use crate::cad::geom::{angle, closest_on, Frame};
use crate::cad::nurbs::NurbsCurve;
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Point3, Vec3};

/// A swept surface with a NURBS profile.
#[derive(Debug, Clone, PartialEq)]
pub enum Swept {
    /// The profile (model space) revolved about the frame's z axis.
    Revolution(Frame, NurbsCurve),
    /// The profile extruded along a unit direction.
    Extrusion(NurbsCurve, Vec3),
}

impl Swept {
    fn profile(&self) -> &NurbsCurve {
        match self {
            Swept::Revolution(_, c) | Swept::Extrusion(c, _) => c,
        }
    }

    /// (radius, height) of `p` in the revolution frame, as a point.
    fn meridian(frame: &Frame, p: Point3) -> Point3 {
        let l = frame.local(p);
        Point3::new(l.x.hypot(l.y), l.z, 0.0)
    }
}

impl NaturalSurface for Swept {
    fn periodic(&self) -> [bool; 2] {
        [matches!(self, Swept::Revolution(..)), false]
    }

    fn metric(&self) -> [f64; 2] {
        match self {
            Swept::Revolution(frame, c) => {
                let r = crate::cad::nurbs::control_points(c)
                    .iter()
                    .map(|p| Swept::meridian(frame, *p).x)
                    .fold(0.0, f64::max);
                [r.max(EPS_LENGTH_MM), 1.0]
            }
            Swept::Extrusion(..) => [1.0, 1.0],
        }
    }

    fn natural(&self, p: Point3, singular_tol: f64) -> (Option<f64>, f64) {
        match self {
            Swept::Revolution(frame, c) => {
                let m = Swept::meridian(frame, p);
                let t = closest_on(
                    &|t| Swept::meridian(frame, c.point(t)),
                    &crate::cad::nurbs::breaks(c),
                    m,
                );
                let (lp, lc) = (frame.local(p), frame.local(c.point(t)));
                let turn = angle(lp.y, lp.x) - angle(lc.y, lc.x);
                ((m.x > singular_tol).then_some(turn), t)
            }
            Swept::Extrusion(c, d) => {
                let flat = |q: Point3| q - d * (q.coords.dot(d));
                let t = closest_on(
                    &|t| flat(c.point(t)),
                    &crate::cad::nurbs::breaks(c),
                    flat(p),
                );
                (Some(t), (p - c.point(t)).dot(d))
            }
        }
    }

    fn clamp_v(&self, lo: f64, hi: f64, _sample: f64) -> (f64, f64) {
        (lo, hi)
    }

    fn extend_v(&self, range: (f64, f64), _high: bool) -> (f64, f64) {
        range
    }

    fn fixed(&self, axis: usize) -> bool {
        match self {
            Swept::Revolution(..) => axis == 1,
            Swept::Extrusion(..) => axis == 0,
        }
    }

    fn maps(&self, u: (f64, f64), v: (f64, f64)) -> [AxisMap; 2] {
        let (lo, hi) = self.profile().domain();
        match self {
            Swept::Revolution(..) => [AxisMap::Angle(Arc::new(u.0, u.1)), AxisMap::Linear(lo, hi)],
            Swept::Extrusion(..) => [AxisMap::Linear(lo, hi), AxisMap::Linear(v.0, v.1)],
        }
    }

    fn to_nurbs(&self, maps: &[AxisMap; 2]) -> SurfaceSpec {
        let [mu, mv] = maps;
        match (self, mu) {
            (Swept::Revolution(frame, c), AxisMap::Angle(arc)) => {
                revolve(frame, arc, &Profile::from_curve(frame, c))
            }
            (Swept::Revolution(frame, c), _) => revolve(
                frame,
                &Arc::new(0.0, std::f64::consts::TAU),
                &Profile::from_curve(frame, c),
            ),
            (Swept::Extrusion(c, d), _) => {
                let (v0, v1) = mv.range();
                extrude(c, *d, [v0, v1])
            }
        }
    }
}
