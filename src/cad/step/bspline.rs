//! B-spline curves and surfaces in every form of ISO 10303-42: with explicit
//! knots (B_SPLINE_*_WITH_KNOTS), UNIFORM_*, QUASI_UNIFORM_*, BEZIER_* and
//! PIECEWISE_BEZIER_* (knots derived as the standard defines them), simple
//! or complex instances, rational (RATIONAL_B_SPLINE_*) or not.
use super::access::{has_record, Args, Ctx};
use super::curves::{point, Space};
use super::parser::Instance;
use crate::cad::error::CadResult;
use crate::cad::nurbs::{new_curve, NurbsCurve};
use crate::formats::workpiece::SurfaceSpec;

/// Largest knot-vector length accepted (guards hostile multiplicities).
const MAX_KNOTS: usize = 1_000_000;

/// How a B-spline's knots are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnotForm {
    /// Multiplicities and knot values in the file.
    Explicit,
    /// Uniform, unclamped: knots `-p, -p + 1, ...`, all simple.
    Uniform,
    /// Uniform with end knots of multiplicity `p + 1`: `0, 1, ..., n - p`.
    QuasiUniform,
    /// One Bezier segment on `[0, 1]`.
    Bezier,
    /// Bezier segments on `[0, 1], [1, 2], ...` (interior multiplicity `p`).
    PiecewiseBezier,
}

/// The record names of each curve and surface knot form (curve, surface).
const FORMS: [(KnotForm, &str, &str); 5] = [
    (
        KnotForm::Explicit,
        "B_SPLINE_CURVE_WITH_KNOTS",
        "B_SPLINE_SURFACE_WITH_KNOTS",
    ),
    (KnotForm::Uniform, "UNIFORM_CURVE", "UNIFORM_SURFACE"),
    (
        KnotForm::QuasiUniform,
        "QUASI_UNIFORM_CURVE",
        "QUASI_UNIFORM_SURFACE",
    ),
    (KnotForm::Bezier, "BEZIER_CURVE", "BEZIER_SURFACE"),
    (
        KnotForm::PiecewiseBezier,
        "PIECEWISE_BEZIER_CURVE",
        "PIECEWISE_BEZIER_SURFACE",
    ),
];

/// The knot form and its record name when `inst` is a B-spline curve
/// (`surface == false`) or surface.
pub fn knot_form(inst: &Instance, surface: bool) -> Option<(KnotForm, &'static str)> {
    FORMS.iter().find_map(|&(form, c, s)| {
        let name = if surface { s } else { c };
        has_record(inst, name).then_some((form, name))
    })
}

/// True when `inst` is a B-spline curve of any form.
pub fn is_bspline_curve(inst: &Instance) -> bool {
    knot_form(inst, false).is_some()
}

/// True when `inst` is a B-spline surface of any form.
pub fn is_bspline_surface(inst: &Instance) -> bool {
    knot_form(inst, true).is_some()
}

/// The knot vector of form `form` for degree `p` and `n` control points
/// (ISO 10303-42, B_SPLINE_CURVE subtypes); `Err` when the counts do not fit.
pub fn derived_knots(form: KnotForm, p: usize, n: usize) -> Result<Vec<f64>, String> {
    if n <= p || n + p + 1 > MAX_KNOTS {
        return Err(format!("{n} control points do not fit degree {p}"));
    }
    let ends = |last: f64, inner: usize, step_mult: usize| {
        let mut k = vec![0.0; p + 1];
        for i in 1..=inner {
            k.extend(std::iter::repeat_n(i as f64, step_mult));
        }
        k.extend(std::iter::repeat_n(last, p + 1));
        k
    };
    match form {
        KnotForm::Uniform => Ok((0..n + p + 1).map(|i| i as f64 - p as f64).collect()),
        KnotForm::QuasiUniform => Ok(ends((n - p) as f64, n - p - 1, 1)),
        KnotForm::Bezier if n == p + 1 => Ok(ends(1.0, 0, 0)),
        KnotForm::Bezier => Err(format!(
            "a Bezier of degree {p} needs {} control points, found {n}",
            p + 1
        )),
        KnotForm::PiecewiseBezier if p > 0 && (n - 1).is_multiple_of(p) => {
            let segments = (n - 1) / p;
            Ok(ends(segments as f64, segments - 1, p))
        }
        KnotForm::PiecewiseBezier => Err(format!(
            "{n} control points do not make whole Bezier segments of degree {p}"
        )),
        KnotForm::Explicit => Err("explicit knots are read from the file".into()),
    }
}

/// The base record: `B_SPLINE_CURVE`/`B_SPLINE_SURFACE` of a complex
/// instance (offset 0), else the form's own record (after its name, offset 1).
fn base<'a>(
    ctx: &Ctx<'a>,
    id: u64,
    base_name: &str,
    form_name: &str,
) -> CadResult<(Args<'a>, usize)> {
    let inst = ctx.inst(id)?;
    if inst.complex && has_record(inst, base_name) {
        return Ok((ctx.args(id, base_name)?, 0));
    }
    Ok((ctx.args(id, form_name)?, 1))
}

/// Explicit knots: the form's record holds (multiplicities, knots) after
/// `skip` leading parameters (those of the B_SPLINE_* supertype).
fn explicit_knots(args: &Args, mult_index: usize, knot_index: usize) -> CadResult<Vec<f64>> {
    let mults = args.counts(mult_index)?;
    let knots = args.reals(knot_index)?;
    if mults.len() != knots.len() || mults.iter().sum::<usize>() > MAX_KNOTS {
        return Err(args.err("knot multiplicities and knots differ in length"));
    }
    if knots.iter().any(|k| !k.is_finite()) {
        return Err(args.err("knot values must be finite"));
    }
    Ok(mults
        .iter()
        .zip(&knots)
        .flat_map(|(&m, &k)| std::iter::repeat_n(k, m))
        .collect())
}

/// A B-spline curve of any form.
pub fn bspline_curve(ctx: &Ctx, id: u64, space: Space) -> CadResult<NurbsCurve> {
    let inst = ctx.inst(id)?;
    let (form, form_name) =
        knot_form(inst, false).ok_or_else(|| ctx.err(inst, "not a B-spline curve"))?;
    let (b, off) = base(ctx, id, "B_SPLINE_CURVE", form_name)?;
    let degree = b.count(off)?;
    let points = b
        .refs(off + 1)?
        .into_iter()
        .map(|p| point(ctx, p, space))
        .collect::<CadResult<Vec<_>>>()?;
    let knots = match form {
        KnotForm::Explicit => {
            let k = ctx.args(id, form_name)?;
            let skip = if off == 0 { 0 } else { 6 };
            explicit_knots(&k, skip, skip + 1)?
        }
        _ => derived_knots(form, degree, points.len()).map_err(|r| b.err(r))?,
    };
    let weights = match ctx.args(id, "RATIONAL_B_SPLINE_CURVE") {
        Ok(r) => r.reals(if off == 0 {
            0
        } else {
            r.params.len().saturating_sub(1)
        })?,
        Err(_) => vec![1.0; points.len()],
    };
    new_curve(degree, knots, &points, weights)
        .map_err(|e| b.err(format!("inconsistent B-spline curve: {e}")))
}

/// A B-spline surface of any form, in NURBS form.
pub fn bspline_surface(ctx: &Ctx, id: u64) -> CadResult<SurfaceSpec> {
    let inst = ctx.inst(id)?;
    let (form, form_name) =
        knot_form(inst, true).ok_or_else(|| ctx.err(inst, "not a B-spline surface"))?;
    let (b, off) = base(ctx, id, "B_SPLINE_SURFACE", form_name)?;
    let degree = [b.count(off)?, b.count(off + 1)?];
    let grid = b.ref_grid(off + 2)?;
    let control_points = grid
        .iter()
        .map(|row| {
            row.iter()
                .map(|&p| point(ctx, p, Space::Model).map(|q| [q.x, q.y, q.z]))
                .collect::<CadResult<Vec<_>>>()
        })
        .collect::<CadResult<Vec<_>>>()?;
    let rows = control_points.len();
    let cols = control_points.first().map_or(0, Vec::len);
    let (knots_u, knots_v) = match form {
        KnotForm::Explicit => {
            let k = ctx.args(id, form_name)?;
            let skip = if off == 0 { 0 } else { 8 };
            (
                explicit_knots(&k, skip, skip + 2)?,
                explicit_knots(&k, skip + 1, skip + 3)?,
            )
        }
        _ => (
            derived_knots(form, degree[0], rows).map_err(|r| b.err(format!("u: {r}")))?,
            derived_knots(form, degree[1], cols).map_err(|r| b.err(format!("v: {r}")))?,
        ),
    };
    let weights = match ctx.args(id, "RATIONAL_B_SPLINE_SURFACE") {
        Ok(r) => Some(r.real_grid(if off == 0 {
            0
        } else {
            r.params.len().saturating_sub(1)
        })?),
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
    super::surfaces::check_spline(&spec).map_err(|reason| b.err(reason))?;
    Ok(spec)
}
