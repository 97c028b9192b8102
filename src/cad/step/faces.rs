//! Conversion of one B-rep face to a trimmed NURBS surface.
use super::access::{has_record, type_name, Ctx};
use super::bspline::knot_form;
use super::parser::Instance;
use super::pcurves::pcurve_trim;
use super::projected::projected_trim;
use super::surfaces::{curve_to_nurbs, surface, SurfaceKind};
use super::topology::{EdgeSampler, FaceData};
use crate::cad::convert::analytic::NaturalSurface;
use crate::cad::convert::swept::Swept;
use crate::cad::convert::trim::{analytic_face, Extent, LoopPoints};
use crate::cad::geom::{Curve, Frame};
use crate::cad::nurbs::NurbsCurve;
use crate::cad::options::ImportOptions;
use crate::formats::workpiece::{SurfaceSpec, TrimSpec};
use crate::math::{Point3, Vec3};

/// A converted face.
#[derive(Debug, Clone, PartialEq)]
pub struct Converted {
    /// The surface (name still empty).
    pub spec: SurfaceSpec,
    /// The STEP surface entity type.
    pub surface_type: String,
    /// Why no trim could be given, when `spec.trim` is `None`.
    pub untrimmed: Option<String>,
}

/// Converts `face`; `Err(reason)` when it cannot be converted.
pub fn convert_face(
    ctx: &Ctx,
    sampler: &mut EdgeSampler,
    face: &FaceData,
    opts: &ImportOptions,
) -> Result<Converted, String> {
    let surface_type = ctx
        .inst(face.surface)
        .map(surface_type_name)
        .map_err(|e| e.to_string())?;
    let kind = surface(ctx, face.surface).map_err(|e| e.to_string())?;
    let mut loops = || face_loops(sampler, face);
    let ext = Extent {
        margin_mm: opts.extent_margin_mm,
        axis_tol_mm: opts.point_tolerance_mm,
    };
    let (spec, untrimmed) = match kind {
        SurfaceKind::Analytic(a) => (analytic_face(&a, &loops()?, face.same_sense, ext)?, None),
        SurfaceKind::Spline(mut s) => {
            s.reversed = !face.same_sense;
            let (trim, note) = spline_trim(ctx, sampler, face, &s, opts);
            s.trim = trim;
            (s, note)
        }
        SurfaceKind::Revolution(c, o, axis) => (
            revolution(&c, o, axis, &loops()?, face.same_sense, ext)?,
            None,
        ),
        SurfaceKind::Extrusion(c, d) => (extrusion(&c, d, &loops()?, face.same_sense, ext)?, None),
    };
    Ok(Converted {
        spec,
        surface_type,
        untrimmed,
    })
}

/// PCURVE trim, else projection-based trim; the reasons when neither works.
fn spline_trim(
    ctx: &Ctx,
    sampler: &mut EdgeSampler,
    face: &FaceData,
    spec: &SurfaceSpec,
    opts: &ImportOptions,
) -> (Option<TrimSpec>, Option<String>) {
    let surface = match spec.to_surface() {
        Ok(s) => s,
        Err(e) => return (None, Some(format!("surface cannot be evaluated: {e}"))),
    };
    let pcurve_reason = match pcurve_trim(ctx, sampler, face, &surface, opts) {
        Ok(t) => return (Some(t), None),
        Err(reason) => reason,
    };
    match projected_trim(ctx, face, &surface, opts) {
        Ok(t) => (Some(t), None),
        Err(why) => (None, Some(format!("{pcurve_reason}; projection: {why}"))),
    }
}

/// The surface's type; complex B-spline instances are named
/// `RATIONAL_B_SPLINE_SURFACE`, else after their knot form
/// (`B_SPLINE_SURFACE_WITH_KNOTS`, `QUASI_UNIFORM_SURFACE`, ...).
pub fn surface_type_name(inst: &Instance) -> String {
    if !inst.complex {
        return type_name(inst);
    }
    if has_record(inst, "RATIONAL_B_SPLINE_SURFACE") {
        return "RATIONAL_B_SPLINE_SURFACE".into();
    }
    match knot_form(inst, true) {
        Some((_, name)) => name.to_string(),
        None => type_name(inst),
    }
}

fn face_loops(sampler: &mut EdgeSampler, face: &FaceData) -> Result<Vec<LoopPoints>, String> {
    face.bounds
        .iter()
        .map(|b| {
            sampler
                .bound_points(b)
                .map(|points| LoopPoints {
                    points,
                    outer: b.outer,
                })
                .map_err(|e| e.to_string())
        })
        .collect()
}

fn all_points(loops: &[LoopPoints]) -> impl Iterator<Item = &Point3> {
    loops.iter().flat_map(|l| l.points.iter())
}

/// Range of the line parameter `t` of `o + t d` over the loops' points
/// projected onto the line, widened by `margin` mm.
fn projected_range(
    loops: &[LoopPoints],
    o: Point3,
    d: Vec3,
    margin: f64,
) -> Result<(f64, f64), String> {
    let len2 = d.norm_squared();
    if len2.is_nan() || len2 <= 0.0 {
        return Err("zero direction".into());
    }
    let vals = all_points(loops).map(|p| (p - o).dot(&d) / len2);
    let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if lo > hi {
        return Err("face has no boundary points to bound the surface".into());
    }
    let m = margin / len2.sqrt();
    Ok((lo - m, hi + m))
}

/// Bounds an unbounded LINE profile: a loose range from the points' extent,
/// then the exact one from the surface's own natural parameters.
fn line_range(
    c: &Curve,
    loops: &[LoopPoints],
    make: &dyn Fn(NurbsCurve) -> Swept,
    axis: usize,
    margin: f64,
) -> Result<NurbsCurve, String> {
    let Curve::Line { origin, dir } = c else {
        return curve_to_nurbs(c, (0.0, 0.0));
    };
    let (lo, hi) = extent(loops);
    let loose = projected_range(loops, *origin, *dir, (hi - lo).norm() + margin)?;
    let provisional = make(curve_to_nurbs(c, loose)?);
    let ts: Vec<f64> = all_points(loops)
        .map(|p| pick(provisional.natural(*p, 0.0), axis))
        .collect();
    let (t0, t1) = ts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(*t), b.max(*t))
        });
    let m = margin / dir.norm();
    curve_to_nurbs(c, (t0 - m, t1 + m))
}

fn pick((u, v): (Option<f64>, f64), axis: usize) -> f64 {
    if axis == 0 {
        u.unwrap_or(0.0)
    } else {
        v
    }
}

fn extent(loops: &[LoopPoints]) -> (Point3, Point3) {
    let first = all_points(loops)
        .next()
        .copied()
        .unwrap_or_else(Point3::origin);
    all_points(loops).fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

fn revolution(
    c: &Curve,
    o: Point3,
    axis: Vec3,
    loops: &[LoopPoints],
    same_sense: bool,
    ext: Extent,
) -> Result<SurfaceSpec, String> {
    let frame = Frame::new(o, axis, None).ok_or("degenerate revolution axis")?;
    let make = |n: NurbsCurve| Swept::Revolution(frame, n);
    let profile = line_range(c, loops, &make, 1, ext.margin_mm)?;
    analytic_face(&make(profile), loops, same_sense, ext)
}

fn extrusion(
    c: &Curve,
    d: Vec3,
    loops: &[LoopPoints],
    same_sense: bool,
    ext: Extent,
) -> Result<SurfaceSpec, String> {
    let make = |n: NurbsCurve| Swept::Extrusion(n, d);
    let profile = line_range(c, loops, &make, 0, ext.margin_mm)?;
    analytic_face(&make(profile), loops, same_sense, ext)
}
