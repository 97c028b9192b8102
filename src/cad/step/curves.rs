//! Points, directions, placements and curves.
use super::access::{has_record, Args, Ctx};
pub use super::bspline::bspline_curve;
use super::bspline::is_bspline_curve;
use crate::cad::error::CadResult;
use crate::cad::geom::EPS_DIRECTION;
use crate::cad::geom::{Curve, Frame};
use crate::cad::nurbs::new_curve;
use crate::math::{Point3, Vec3};

/// Deepest chain of curve wrappers (TRIMMED_CURVE, SURFACE_CURVE) followed.
const MAX_CURVE_CHAIN: usize = 16;

/// Model space (lengths scaled to mm) or a surface's parameter space (unscaled).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Space {
    /// 3-D model coordinates.
    Model,
    /// 2-D parameter coordinates of a pcurve.
    Param,
}

fn scale(ctx: &Ctx, space: Space) -> f64 {
    match space {
        Space::Model => ctx.length_mm,
        Space::Param => 1.0,
    }
}

/// A CARTESIAN_POINT (2-D points get z = 0).
pub fn point(ctx: &Ctx, id: u64, space: Space) -> CadResult<Point3> {
    let args = ctx.args(id, "CARTESIAN_POINT")?;
    let s = scale(ctx, space);
    let c = args.reals(1)?;
    for (k, x) in c.iter().enumerate() {
        let v = x * s;
        if !super::access::in_range(v) {
            return Err(args.out_of_range(&format!("coordinate {}", k + 1), v));
        }
    }
    match c.as_slice() {
        [x, y] => Ok(Point3::new(x * s, y * s, 0.0)),
        [x, y, z] => Ok(Point3::new(x * s, y * s, z * s)),
        _ => Err(args.err("CARTESIAN_POINT needs 2 or 3 coordinates")),
    }
}

/// Parameter `i` as a length in `space` (checked finite and in range).
fn scaled(ctx: &Ctx, args: &Args, i: usize, space: Space) -> CadResult<f64> {
    let v = args.real(i)? * scale(ctx, space);
    if !super::access::in_range(v) {
        return Err(args.out_of_range(&format!("parameter {}", i + 1), v));
    }
    Ok(v)
}

/// A DIRECTION (not normalised; 2-D gets z = 0).
pub fn direction(ctx: &Ctx, id: u64) -> CadResult<Vec3> {
    let args = ctx.args(id, "DIRECTION")?;
    match args.reals(1)?.as_slice() {
        [x, y] => Ok(Vec3::new(*x, *y, 0.0)),
        [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(args.err("DIRECTION needs 2 or 3 ratios")),
    }
}

fn optional_direction(ctx: &Ctx, args: &Args, i: usize) -> CadResult<Option<Vec3>> {
    match args.reference(i) {
        Ok(id) => direction(ctx, id).map(Some),
        Err(_) => Ok(None),
    }
}

/// An AXIS2_PLACEMENT_3D or AXIS2_PLACEMENT_2D as a frame.
pub fn placement(ctx: &Ctx, id: u64, space: Space) -> CadResult<Frame> {
    let inst = ctx.inst(id)?;
    if has_record(inst, "AXIS2_PLACEMENT_2D") {
        let args = ctx.args(id, "AXIS2_PLACEMENT_2D")?;
        let origin = point(ctx, args.reference(1)?, space)?;
        let x = optional_direction(ctx, &args, 2)?;
        return Frame::new(origin, Vec3::z(), x).ok_or_else(|| args.err("degenerate placement"));
    }
    let args = ctx.args(id, "AXIS2_PLACEMENT_3D")?;
    let origin = point(ctx, args.reference(1)?, space)?;
    let axis = optional_direction(ctx, &args, 2)?.unwrap_or_else(Vec3::z);
    let x = optional_direction(ctx, &args, 3)?;
    Frame::new(origin, axis, x)
        .ok_or_else(|| args.err("degenerate placement (zero or parallel directions)"))
}

/// An AXIS1_PLACEMENT: point and unit axis.
pub fn axis1(ctx: &Ctx, id: u64) -> CadResult<(Point3, Vec3)> {
    let args = ctx.args(id, "AXIS1_PLACEMENT")?;
    let origin = point(ctx, args.reference(1)?, Space::Model)?;
    let axis = optional_direction(ctx, &args, 2)?.unwrap_or_else(Vec3::z);
    let axis = axis
        .try_normalize(EPS_DIRECTION)
        .ok_or_else(|| args.err("zero axis"))?;
    Ok((origin, axis))
}

/// A VECTOR as direction (unit) times magnitude (mm in model space).
pub fn vector(ctx: &Ctx, id: u64, space: Space) -> CadResult<Vec3> {
    let args = ctx.args(id, "VECTOR")?;
    let dir = direction(ctx, args.reference(1)?)?;
    let unit = dir
        .try_normalize(EPS_DIRECTION)
        .ok_or_else(|| args.err("zero direction"))?;
    Ok(unit * scaled(ctx, &args, 2, space)?)
}

/// Reads any supported curve; wrappers (TRIMMED_CURVE, SURFACE_CURVE,
/// SEAM_CURVE) resolve to their basis curve.
pub fn curve(ctx: &Ctx, id: u64, space: Space) -> CadResult<Curve> {
    curve_at_depth(ctx, id, space, 0)
}

fn curve_at_depth(ctx: &Ctx, id: u64, space: Space, depth: usize) -> CadResult<Curve> {
    let args = ctx.first(id)?;
    if depth > MAX_CURVE_CHAIN {
        return Err(args.err("curve wrappers nested too deeply"));
    }
    if is_bspline_curve(args.inst) {
        return bspline_curve(ctx, id, space).map(Curve::Nurbs);
    }
    let name = args
        .inst
        .records
        .first()
        .map(|r| r.name.as_str())
        .unwrap_or("");
    match name {
        "LINE" => line(ctx, &args, space),
        "CIRCLE" => Ok(Curve::Circle {
            frame: placement(ctx, args.reference(1)?, space)?,
            radius: scaled(ctx, &args, 2, space)?,
        }),
        "ELLIPSE" => ellipse(ctx, &args, space),
        "POLYLINE" => polyline(ctx, &args, space),
        "TRIMMED_CURVE"
        | "SURFACE_CURVE"
        | "SEAM_CURVE"
        | "INTERSECTION_CURVE"
        | "BOUNDED_SURFACE_CURVE" => curve_at_depth(ctx, args.reference(1)?, space, depth + 1),
        other => Err(args.err(format!("unsupported curve type {other}"))),
    }
}

fn line(ctx: &Ctx, args: &Args, space: Space) -> CadResult<Curve> {
    let origin = point(ctx, args.reference(1)?, space)?;
    let dir = vector(ctx, args.reference(2)?, space)?;
    if dir.norm_squared().is_nan() || dir.norm_squared() <= 0.0 {
        return Err(args.err("zero line direction"));
    }
    Ok(Curve::Line { origin, dir })
}

fn ellipse(ctx: &Ctx, args: &Args, space: Space) -> CadResult<Curve> {
    let frame = placement(ctx, args.reference(1)?, space)?;
    Ok(Curve::Ellipse {
        frame,
        a: scaled(ctx, args, 2, space)?,
        b: scaled(ctx, args, 3, space)?,
    })
}

fn polyline(ctx: &Ctx, args: &Args, space: Space) -> CadResult<Curve> {
    let points = args
        .refs(1)?
        .into_iter()
        .map(|id| point(ctx, id, space))
        .collect::<CadResult<Vec<_>>>()?;
    let n = points.len();
    let mut knots = vec![0.0];
    knots.extend((0..n).map(|k| k as f64));
    knots.push(n.saturating_sub(1) as f64);
    new_curve(1, knots, &points, vec![1.0; n])
        .map(Curve::Nurbs)
        .map_err(|e| args.err(format!("POLYLINE needs 2 or more distinct points: {e}")))
}
