//! Tensor-product constructions: surfaces of revolution (which cover the
//! cylinder, cone, sphere and torus), bilinear planes and linear extrusions.
use super::arc::Arc;
use crate::cad::geom::Frame;
use crate::cad::nurbs::{control_points, weights, NurbsCurve};
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Point3, Vec3};

/// A profile curve in local frame coordinates, swept about the frame's z axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Degree.
    pub degree: usize,
    /// Full knot vector.
    pub knots: Vec<f64>,
    /// Control points in local coordinates.
    pub points: Vec<Vec3>,
    /// Weights.
    pub weights: Vec<f64>,
}

impl Profile {
    /// A straight segment from `a` (parameter `t0`) to `b` (`t1`).
    pub fn line(a: Vec3, b: Vec3, t0: f64, t1: f64) -> Profile {
        Profile {
            degree: 1,
            knots: vec![t0, t0, t1, t1],
            points: vec![a, b],
            weights: vec![1.0, 1.0],
        }
    }

    /// The circle arc `(offset + r cos t, 0, r sin t)` over `arc`.
    pub fn arc(arc: &Arc, offset: f64, r: f64) -> Profile {
        let pts = arc.points();
        Profile {
            degree: 2,
            knots: arc.knots(),
            points: pts
                .iter()
                .map(|p| Vec3::new(offset + r * p.c, 0.0, r * p.s))
                .collect(),
            weights: pts.iter().map(|p| p.w).collect(),
        }
    }

    /// A model-space NURBS curve expressed in `frame`'s local coordinates.
    pub fn from_curve(frame: &Frame, c: &NurbsCurve) -> Profile {
        Profile {
            degree: c.knots().degree(),
            knots: c.knots().as_slice().to_vec(),
            points: control_points(c).iter().map(|p| frame.local(*p)).collect(),
            weights: weights(c),
        }
    }
}

/// Revolves `profile` about the frame's z axis over `arc`:
/// `P[i][j] = O + z_j z + c_i X_j + s_i (z x X_j)` with weights `w_i w_j`,
/// where `X_j` is the profile point's component perpendicular to the axis.
pub fn revolve(frame: &Frame, arc: &Arc, profile: &Profile) -> SurfaceSpec {
    let ring = arc.points();
    let mut control_points = Vec::with_capacity(ring.len());
    let mut weights = Vec::with_capacity(ring.len());
    for a in &ring {
        let row: Vec<[f64; 3]> = profile
            .points
            .iter()
            .map(|l| {
                let x = a.c * l.x - a.s * l.y;
                let y = a.c * l.y + a.s * l.x;
                to_array(frame.world(x, y, l.z))
            })
            .collect();
        control_points.push(row);
        weights.push(profile.weights.iter().map(|w| w * a.w).collect());
    }
    SurfaceSpec {
        name: String::new(),
        degree: [2, profile.degree],
        knots_u: arc.knots(),
        knots_v: profile.knots.clone(),
        control_points,
        weights: Some(weights),
        reversed: false,
        trim: None,
    }
}

/// The plane `O + x X + y Y` over `[x0, x1] x [y0, y1]` as a bilinear patch.
pub fn bilinear_plane(frame: &Frame, [x0, x1]: [f64; 2], [y0, y1]: [f64; 2]) -> SurfaceSpec {
    let p = |x: f64, y: f64| to_array(frame.world(x, y, 0.0));
    SurfaceSpec {
        name: String::new(),
        degree: [1, 1],
        knots_u: vec![x0, x0, x1, x1],
        knots_v: vec![y0, y0, y1, y1],
        control_points: vec![vec![p(x0, y0), p(x0, y1)], vec![p(x1, y0), p(x1, y1)]],
        weights: None,
        reversed: false,
        trim: None,
    }
}

/// The linear extrusion `C(u) + v d` for `v` in `[v0, v1]` (d a unit vector).
pub fn extrude(curve: &NurbsCurve, d: Vec3, [v0, v1]: [f64; 2]) -> SurfaceSpec {
    let row = |p: &Point3| vec![to_array(p + d * v0), to_array(p + d * v1)];
    let w = weights(curve);
    let rational = w.iter().any(|w| (w - 1.0).abs() > 0.0);
    SurfaceSpec {
        name: String::new(),
        degree: [curve.knots().degree(), 1],
        knots_u: curve.knots().as_slice().to_vec(),
        knots_v: vec![v0, v0, v1, v1],
        control_points: control_points(curve).iter().map(row).collect(),
        weights: rational.then(|| w.iter().map(|w| vec![*w, *w]).collect()),
        reversed: false,
        trim: None,
    }
}

/// `[x, y, z]` of a point.
pub fn to_array(p: Point3) -> [f64; 3] {
    [p.x, p.y, p.z]
}
