//! Surface entities: elementary surfaces, B-spline surfaces (simple and
//! rational complex form), surfaces of revolution and linear extrusion.
use super::access::{has_record, Ctx};
use super::curves::{axis1, bspline_curve, curve, expand_knots, placement, point, vector, Space};
use crate::cad::convert::analytic::Analytic;
use crate::cad::convert::arc::Arc;
use crate::cad::error::CadResult;
use crate::cad::geom::EPS_DIRECTION;
use crate::cad::geom::{Curve, Frame};
use crate::cad::nurbs::{new_curve, NurbsCurve};
use crate::math::{Point3, Vec3};
use crate::workpiece::format::SurfaceSpec;
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

/// Reads the surface `#id`; `Err` for malformed or unsupported surfaces.
pub fn surface(ctx: &Ctx, id: u64) -> CadResult<SurfaceKind> {
    let inst = ctx.inst(id)?;
    if inst.complex || has_record(inst, "B_SPLINE_SURFACE_WITH_KNOTS") {
        return bspline_surface(ctx, id).map(SurfaceKind::Spline);
    }
    let args = ctx.first(id)?;
    let name = inst.records.first().map(|r| r.name.as_str()).unwrap_or("");
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

/// B_SPLINE_SURFACE_WITH_KNOTS, simple or complex (rational) form.
pub fn bspline_surface(ctx: &Ctx, id: u64) -> CadResult<SurfaceSpec> {
    let inst = ctx.inst(id)?;
    let (base, knots, off) = if inst.complex {
        (
            ctx.args(id, "B_SPLINE_SURFACE")?,
            ctx.args(id, "B_SPLINE_SURFACE_WITH_KNOTS")?,
            (0, 0),
        )
    } else {
        let a = ctx.args(id, "B_SPLINE_SURFACE_WITH_KNOTS")?;
        (a, a, (1, 8))
    };
    let degree = [base.count(off.0)?, base.count(off.0 + 1)?];
    let grid = base.ref_grid(off.0 + 2)?;
    let control_points = grid
        .iter()
        .map(|row| {
            row.iter()
                .map(|&p| point(ctx, p, Space::Model).map(|q| [q.x, q.y, q.z]))
                .collect::<CadResult<Vec<_>>>()
        })
        .collect::<CadResult<Vec<_>>>()?;
    let knots_u = expand_knots(&knots, off.1, off.1 + 2)?;
    let knots_v = expand_knots(&knots, off.1 + 1, off.1 + 3)?;
    let weights = match ctx.args(id, "RATIONAL_B_SPLINE_SURFACE") {
        Ok(r) => Some(r.real_grid(0)?),
        Err(_) => None,
    };
    let spec = SurfaceSpec {
        name: String::new(),
        degree,
        knots_u,
        knots_v,
        control_points,
        weights,
        reversed: false,
        trim: None,
    };
    check_spline(&spec).map_err(|reason| base.err(reason))?;
    Ok(spec)
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
    if inst.complex || has_record(inst, "B_SPLINE_CURVE_WITH_KNOTS") {
        return bspline_curve(ctx, id, Space::Param).map(Curve::Nurbs);
    }
    curve(ctx, id, Space::Param)
}
