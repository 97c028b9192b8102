//! Placements of assembly occurrences and mapped items: affine maps built
//! from pairs of AXIS2_PLACEMENT_3D (ITEM_DEFINED_TRANSFORMATION,
//! REPRESENTATION_MAP + MAPPED_ITEM) or from a
//! CARTESIAN_TRANSFORMATION_OPERATOR_3D, and applied to converted faces.
use super::access::{has_record, Ctx};
use super::curves::{direction, placement, point, Space};
use crate::cad::error::CadResult;
use crate::cad::geom::{Frame, EPS_DIRECTION};
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Mat3, Point3, Vec3};

/// An affine map `p -> linear * p + shift` (mm); rigid for placements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Rotation (times scale, possibly a mirror for transformation operators).
    pub linear: Mat3,
    /// Translation, mm.
    pub shift: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::identity()
    }
}

impl Transform {
    /// The identity.
    pub fn identity() -> Transform {
        Transform {
            linear: Mat3::identity(),
            shift: Vec3::zeros(),
        }
    }

    /// The map from a frame's local coordinates to world coordinates.
    pub fn of_frame(f: &Frame) -> Transform {
        Transform {
            linear: Mat3::from_columns(&[f.x, f.y, f.z]),
            shift: f.origin.coords,
        }
    }

    /// The rigid map that carries frame `from` onto frame `to`
    /// (`to * from^-1`).
    pub fn between(from: &Frame, to: &Frame) -> Transform {
        let inv_rot = Mat3::from_columns(&[from.x, from.y, from.z]).transpose();
        let inverse = Transform {
            linear: inv_rot,
            shift: -(inv_rot * from.origin.coords),
        };
        Transform::of_frame(to).after(&inverse)
    }

    /// `self` applied after `inner` (`self(inner(p))`).
    pub fn after(&self, inner: &Transform) -> Transform {
        Transform {
            linear: self.linear * inner.linear,
            shift: self.linear * inner.shift + self.shift,
        }
    }

    /// The image of a point.
    pub fn apply(&self, p: Point3) -> Point3 {
        Point3::from(self.linear * p.coords + self.shift)
    }

    /// True when the map is the identity to round-off.
    pub fn is_identity(&self) -> bool {
        (self.linear - Mat3::identity()).abs().max() <= 1e-15 && self.shift.abs().max() == 0.0
    }

    /// True when the map reverses orientation (a mirror).
    pub fn mirrors(&self) -> bool {
        self.linear.determinant() < 0.0
    }

    /// Moves a converted surface: NURBS are affinely invariant, so mapping
    /// the control points is exact and the trim in (u, v) is unchanged; a
    /// mirror flips the normal `Su x Sv`, so `reversed` is toggled to keep it
    /// pointing out of the material.
    pub fn apply_to(&self, spec: &mut SurfaceSpec) {
        for row in spec.control_points.iter_mut() {
            for c in row.iter_mut() {
                let q = self.apply(Point3::new(c[0], c[1], c[2]));
                *c = [q.x, q.y, q.z];
            }
        }
        if self.mirrors() {
            spec.reversed = !spec.reversed;
        }
    }
}

/// The map of an ITEM_DEFINED_TRANSFORMATION (item 1 carried onto item 2),
/// a CARTESIAN_TRANSFORMATION_OPERATOR_3D, or a bare placement (its frame).
/// `from_mm` and `to_mm` are the length units of the two sides.
pub fn transformation(ctx: &Ctx, id: u64, from_mm: f64, to_mm: f64) -> CadResult<Transform> {
    let inst = ctx.inst(id)?;
    if has_record(inst, "ITEM_DEFINED_TRANSFORMATION") {
        let args = ctx.args(id, "ITEM_DEFINED_TRANSFORMATION")?;
        let from = frame_in(ctx, args.reference(2)?, from_mm)?;
        let to = frame_in(ctx, args.reference(3)?, to_mm)?;
        return Ok(Transform::between(&from, &to));
    }
    if has_record(inst, "CARTESIAN_TRANSFORMATION_OPERATOR_3D")
        || has_record(inst, "CARTESIAN_TRANSFORMATION_OPERATOR")
    {
        return operator(ctx, id, to_mm);
    }
    Ok(Transform::of_frame(&frame_in(ctx, id, to_mm)?))
}

/// A placement read with the length unit `length_mm`.
pub fn frame_in(ctx: &Ctx, id: u64, length_mm: f64) -> CadResult<Frame> {
    let scaled = Ctx { length_mm, ..*ctx };
    placement(&scaled, id, Space::Model)
}

/// CARTESIAN_TRANSFORMATION_OPERATOR(_3D): axis1, axis2, local_origin,
/// scale, axis3 (ISO 10303-42 base_axis with the defaults for `$`).
fn operator(ctx: &Ctx, id: u64, length_mm: f64) -> CadResult<Transform> {
    let args = ctx.args(id, "CARTESIAN_TRANSFORMATION_OPERATOR")?;
    let dir = |i: usize| match args.reference(i) {
        Ok(r) => direction(ctx, r).map(Some),
        Err(_) => Ok(None),
    };
    let (a1, a2) = (dir(3)?, dir(4)?);
    let a3 = match ctx.args(id, "CARTESIAN_TRANSFORMATION_OPERATOR_3D") {
        Ok(a) => match a.reference(0) {
            Ok(r) => Some(direction(ctx, r)?),
            Err(_) => None,
        },
        Err(_) => None,
    };
    let scaled = Ctx { length_mm, ..*ctx };
    let origin = point(&scaled, args.reference(5)?, Space::Model)?;
    let scale = args.real(6).unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(args.err(format!("transformation scale {scale} is not positive")));
    }
    let [u, v, w] =
        base_axis(a1, a2, a3).ok_or_else(|| args.err("degenerate transformation axes"))?;
    Ok(Transform {
        linear: Mat3::from_columns(&[u, v, w]) * scale,
        shift: origin.coords,
    })
}

/// ISO 10303-42 `base_axis` for three dimensions: an orthonormal triple from
/// optional axis1, axis2, axis3 (axis3 defaults to z, axis1 to x), keeping
/// the handedness the file gives (a mirror stays a mirror).
fn base_axis(a1: Option<Vec3>, a2: Option<Vec3>, a3: Option<Vec3>) -> Option<[Vec3; 3]> {
    let w = a3.unwrap_or_else(Vec3::z).try_normalize(EPS_DIRECTION)?;
    let guess = a1.unwrap_or_else(|| {
        if w.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        }
    });
    let u = (guess - w * guess.dot(&w)).try_normalize(EPS_DIRECTION)?;
    let right = w.cross(&u);
    let v = match a2 {
        Some(a2) if a2.dot(&right) < 0.0 => -right,
        _ => right,
    };
    Some([u, v, w])
}
