//! Surface entities: elementary surfaces, B-spline surfaces (simple and
//! rational complex form), surfaces of revolution and linear extrusion.
use super::access::Ctx;
pub use super::bspline::bspline_surface;
use super::bspline::{bspline_curve, is_bspline_curve, is_bspline_surface};
use super::curves::{axis1, curve, placement, vector, Space};
use crate::cad::convert::analytic::Analytic;
use crate::cad::convert::arc::Arc;
use crate::cad::error::CadResult;
use crate::cad::geom::EPS_DIRECTION;
use crate::cad::geom::{Curve, Frame};
use crate::cad::nurbs::{new_curve, NurbsCurve};
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Point3, Vec3};
use std::f64::consts::TAU;

/// A surface as read from the file.
#[derive(Debug, Clone, PartialEq)]
pub enum SurfaceKind {
    /// Plane, cylinder, cone, sphere, torus.
    Analytic(Analytic),
    /// A B-spline surface, already in NURBS form.
    Spline(SurfaceSpec),
    /// SURFACE_OF_REVOLUTION: profile curve, axis point and unit axis.
    Revolution(Curve, Point3, Vec3),
    /// SURFACE_OF_LINEAR_EXTRUSION: profile curve and unit direction.
    Extrusion(Curve, Vec3),
}

/// Deepest chain of surface wrappers (offset, trimmed, curve-bounded) followed.
const MAX_SURFACE_CHAIN: usize = 16;

/// Reads the surface `#id`; `Err` for malformed or unsupported surfaces.
///
/// RECTANGULAR_TRIMMED_SURFACE and CURVE_BOUNDED_SURFACE resolve to their
/// basis surface (the face's own loops bound it); OFFSET_SURFACE is exact
/// for elementary basis surfaces (see [`offset`]).
pub fn surface(ctx: &Ctx, id: u64) -> CadResult<SurfaceKind> {
    surface_at(ctx, id, 0)
}

fn surface_at(ctx: &Ctx, id: u64, depth: usize) -> CadResult<SurfaceKind> {
    let inst = ctx.inst(id)?;
    if is_bspline_surface(inst) {
        return bspline_surface(ctx, id).map(SurfaceKind::Spline);
    }
    let args = ctx.first(id)?;
    let name = inst.records.first().map(|r| r.name.as_str()).unwrap_or("");
    if depth > MAX_SURFACE_CHAIN {
        return Err(args.err("surface wrappers nested too deeply"));
    }
    match name {
        "RECTANGULAR_TRIMMED_SURFACE" | "CURVE_BOUNDED_SURFACE" => {
            return surface_at(ctx, args.reference(1)?, depth + 1);
        }
        "OFFSET_SURFACE" => {
            let basis = surface_at(ctx, args.reference(1)?, depth + 1)?;
            return offset(basis, args.length(2)?).map_err(|r| args.err(r));
        }
        _ => {}
    }
    let frame = || placement(ctx, args.reference(1)?, Space::Model);
    let a = match name {
        "PLANE" => Analytic::Plane(frame()?),
        "CYLINDRICAL_SURFACE" => Analytic::Cylinder(frame()?, args.length(2)?),
        "CONICAL_SURFACE" => {
            Analytic::Cone(frame()?, args.length(2)?, args.real(3)? * ctx.angle_rad)
        }
        "SPHERICAL_SURFACE" => Analytic::Sphere(frame()?, args.length(2)?),
        "TOROIDAL_SURFACE" | "DEGENERATE_TOROIDAL_SURFACE" => {
            Analytic::Torus(frame()?, args.length(2)?, args.length(3)?)
        }
        "SURFACE_OF_REVOLUTION" => {
            let (o, axis) = axis1(ctx, args.reference(2)?)?;
            return Ok(SurfaceKind::Revolution(
                curve(ctx, args.reference(1)?, Space::Model)?,
                o,
                axis,
            ));
        }
        "SURFACE_OF_LINEAR_EXTRUSION" => {
            let v = vector(ctx, args.reference(2)?, Space::Model)?;
            let dir = v
                .try_normalize(EPS_DIRECTION)
                .ok_or_else(|| args.err("zero extrusion vector"))?;
            return Ok(SurfaceKind::Extrusion(
                curve(ctx, args.reference(1)?, Space::Model)?,
                dir,
            ));
        }
        other => return Err(args.err(format!("unsupported surface type {other}"))),
    };
    Ok(SurfaceKind::Analytic(a))
}

/// The surface at signed distance `d` (mm) along the basis surface's normal
/// (ISO 10303-42: outward for cylinders, cones, spheres and tori, the
/// placement axis for planes). Offsets of elementary surfaces are again
/// elementary: a plane moves along its normal, radii grow by `d` (a cone's
/// reference radius by `d / cos(semi-angle)`). Other basis surfaces have no
/// exact NURBS offset and are refused.
pub fn offset(basis: SurfaceKind, d: f64) -> Result<SurfaceKind, String> {
    let SurfaceKind::Analytic(a) = basis else {
        return Err("OFFSET_SURFACE of a non-elementary surface has no exact NURBS form".into());
    };
    let grown = |r: f64| {
        let g = r + d;
        if g > 0.0 && g.is_finite() {
            Ok(g)
        } else {
            Err(format!("offset {d} mm collapses radius {r} mm"))
        }
    };
    let out = match a {
        Analytic::Plane(f) => Analytic::Plane(Frame {
            origin: f.origin + f.z * d,
            ..f
        }),
        Analytic::Cylinder(f, r) => Analytic::Cylinder(f, grown(r)?),
        Analytic::Sphere(f, r) => Analytic::Sphere(f, grown(r)?),
        Analytic::Torus(f, big, small) => Analytic::Torus(f, big, grown(small)?),
        Analytic::Cone(f, r, semi) => {
            let c = semi.cos();
            if c.abs() < EPS_DIRECTION {
                return Err("offset of a flat cone".into());
            }
            Analytic::Cone(f, r + d / c, semi)
        }
    };
    Ok(SurfaceKind::Analytic(out))
}

/// Shape checks of a NURBS surface (counts, knot order, positive weights).
pub fn check_spline(s: &SurfaceSpec) -> Result<(), String> {
    let [p, q] = s.degree;
    let rows = s.control_points.len();
    let cols = s.control_points.first().map_or(0, Vec::len);
    let ok_counts =
        rows > p && cols > q && s.knots_u.len() == rows + p + 1 && s.knots_v.len() == cols + q + 1;
    let ok_rows = s.control_points.iter().all(|r| r.len() == cols);
    let ok_knots = [&s.knots_u, &s.knots_v]
        .iter()
        .all(|k| k.windows(2).all(|w| matches!(w, [a, b] if a <= b)));
    let ok_weights = s.weights.as_ref().is_none_or(|w| {
        w.len() == rows
            && w.iter()
                .all(|r| r.len() == cols && r.iter().all(|x| *x > 0.0))
    });
    if ok_counts && ok_rows && ok_knots && ok_weights {
        return Ok(());
    }
    Err(format!(
        "inconsistent B-spline surface: degree {p}x{q}, {rows}x{cols} control points, {}+{} knots",
        s.knots_u.len(),
        s.knots_v.len()
    ))
}

/// A curve as a NURBS curve; lines are bounded to `[t0, t1]`, conics are full.
pub fn curve_to_nurbs(c: &Curve, line_range: (f64, f64)) -> Result<NurbsCurve, String> {
    let (t0, t1) = line_range;
    let curve = match c {
        Curve::Nurbs(n) => return Ok(n.clone()),
        Curve::Line { origin, dir } => new_curve(
            1,
            vec![t0, t0, t1, t1],
            &[origin + dir * t0, origin + dir * t1],
            vec![1.0; 2],
        ),
        Curve::Circle { frame, radius } => conic(frame, *radius, *radius),
        Curve::Ellipse { frame, a, b } => conic(frame, *a, *b),
    };
    curve.map_err(|e| format!("profile curve: {e}"))
}

fn conic(frame: &Frame, a: f64, b: f64) -> Result<NurbsCurve, crate::geometry::NurbsError> {
    let arc = Arc::new(0.0, TAU);
    let pts = arc.points();
    let points: Vec<_> = pts
        .iter()
        .map(|p| frame.world(a * p.c, b * p.s, 0.0))
        .collect();
    new_curve(2, arc.knots(), &points, pts.iter().map(|p| p.w).collect())
}

/// Reads a pcurve's 2-D curve (parameter space, unscaled).
pub fn param_curve(ctx: &Ctx, id: u64) -> CadResult<Curve> {
    let inst = ctx.inst(id)?;
    if is_bspline_curve(inst) {
        return bspline_curve(ctx, id, Space::Param).map(Curve::Nurbs);
    }
    curve(ctx, id, Space::Param)
}
