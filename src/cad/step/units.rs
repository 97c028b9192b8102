//! Length and plane-angle units from the GLOBAL_UNIT_ASSIGNED_CONTEXT.
use super::access::{as_real, as_ref, has_record, Ctx};
use super::parser::{Instance, StepFile, Value};
use crate::cad::error::{CadError, CadResult};

/// Deepest chain of CONVERSION_BASED_UNITs followed.
const MAX_UNIT_CHAIN: usize = 8;

/// Shape-model entities whose representation's context defines the units.
const MODEL_ITEMS: [&str; 5] = [
    "MANIFOLD_SOLID_BREP",
    "BREP_WITH_VOIDS",
    "SHELL_BASED_SURFACE_MODEL",
    "FACETED_BREP",
    "ADVANCED_FACE",
];

/// Unit factors of a file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    /// Millimetres per file length unit.
    pub length_mm: f64,
    /// Radians per file plane-angle unit.
    pub angle_rad: f64,
    /// Declared length uncertainty of the geometry context, mm (the
    /// UNCERTAINTY_MEASURE_WITH_UNIT of its GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT).
    pub uncertainty_mm: Option<f64>,
}

/// Finds the units of the geometry; error "missing units" when there is no length unit.
pub fn find_units(step: &StepFile, file: &str) -> CadResult<Units> {
    let ctx = Ctx {
        step,
        file,
        length_mm: 1.0,
        angle_rad: 1.0,
    };
    let contexts = unit_contexts(step);
    let preferred = model_context(step)
        .into_iter()
        .chain(contexts.iter().copied());
    for inst in preferred {
        if let Some(length_mm) = context_unit(&ctx, inst, "LENGTH_UNIT", 1000.0)? {
            let angle_rad = context_unit(&ctx, inst, "PLANE_ANGLE_UNIT", 1.0)?.unwrap_or(1.0);
            return Ok(Units {
                length_mm,
                angle_rad,
                uncertainty_mm: uncertainty(&ctx, inst),
            });
        }
    }
    let pos = contexts.first().map_or(step.data_pos, |i| i.pos);
    Err(CadError::MissingUnits {
        file: file.to_string(),
        line: pos.line,
        column: pos.column,
        reason: "no LENGTH_UNIT in any GLOBAL_UNIT_ASSIGNED_CONTEXT".into(),
    })
}

fn unit_contexts(step: &StepFile) -> Vec<&Instance> {
    step.instances
        .iter()
        .filter(|i| has_record(i, "GLOBAL_UNIT_ASSIGNED_CONTEXT"))
        .collect()
}

/// The context of the first representation whose items hold a shape model.
fn model_context(step: &StepFile) -> Option<&Instance> {
    step.instances.iter().find_map(|inst| {
        let rec = inst.records.first()?;
        let Some(Value::List(items)) = rec.params.get(1) else {
            return None;
        };
        let holds_model = items
            .iter()
            .filter_map(as_ref)
            .filter_map(|id| step.get(id))
            .any(is_model);
        let context = step.get(as_ref(rec.params.get(2)?)?)?;
        (holds_model && has_record(context, "GLOBAL_UNIT_ASSIGNED_CONTEXT")).then_some(context)
    })
}

fn is_model(inst: &Instance) -> bool {
    MODEL_ITEMS.iter().any(|name| has_record(inst, name))
}

/// The factor of the context's unit of `kind`; `si_scale` converts the SI base unit.
fn context_unit(
    ctx: &Ctx,
    context: &Instance,
    kind: &str,
    si_scale: f64,
) -> CadResult<Option<f64>> {
    let args = ctx.args(context.id, "GLOBAL_UNIT_ASSIGNED_CONTEXT")?;
    for id in args.refs(0)? {
        let unit = ctx.inst(id)?;
        if has_record(unit, kind) {
            return unit_factor(ctx, unit, si_scale, 0).map(Some);
        }
    }
    Ok(None)
}

fn unit_factor(ctx: &Ctx, unit: &Instance, si_scale: f64, depth: usize) -> CadResult<f64> {
    if depth > MAX_UNIT_CHAIN {
        return Err(ctx.err(unit, "unit conversion chain too long"));
    }
    if has_record(unit, "SI_UNIT") {
        let args = ctx.args(unit.id, "SI_UNIT")?;
        let prefix = match args.get(0)? {
            Value::Enum(p) => {
                si_prefix(p).ok_or_else(|| args.err(format!("unknown SI prefix .{p}.")))?
            }
            _ => 1.0,
        };
        return Ok(prefix * si_scale);
    }
    if has_record(unit, "CONVERSION_BASED_UNIT") {
        let measure = ctx.args(unit.id, "CONVERSION_BASED_UNIT")?.reference(1)?;
        return measure_factor(ctx, measure, si_scale, depth);
    }
    Err(ctx.err(unit, "unit is neither SI_UNIT nor CONVERSION_BASED_UNIT"))
}

/// value x factor(unit) of a *_MEASURE_WITH_UNIT.
fn measure_factor(ctx: &Ctx, id: u64, si_scale: f64, depth: usize) -> CadResult<f64> {
    let inst = ctx.inst(id)?;
    let rec = inst
        .records
        .iter()
        .find(|r| r.params.len() >= 2 && r.name.ends_with("MEASURE_WITH_UNIT"));
    let rec = rec.ok_or_else(|| ctx.err(inst, "expected a MEASURE_WITH_UNIT"))?;
    let value = rec
        .params
        .first()
        .and_then(as_real)
        .ok_or_else(|| ctx.err(inst, "measure value is not a number"))?;
    let unit_id = rec
        .params
        .get(1)
        .and_then(as_ref)
        .ok_or_else(|| ctx.err(inst, "measure unit is not a reference"))?;
    let unit = ctx.inst(unit_id)?;
    Ok(value * unit_factor(ctx, unit, si_scale, depth + 1)?)
}

fn si_prefix(p: &str) -> Option<f64> {
    let factor = match p {
        "EXA" => 1e18,
        "PETA" => 1e15,
        "TERA" => 1e12,
        "GIGA" => 1e9,
        "MEGA" => 1e6,
        "KILO" => 1e3,
        "HECTO" => 1e2,
        "DECA" => 1e1,
        "DECI" => 1e-1,
        "CENTI" => 1e-2,
        "MILLI" => 1e-3,
        "MICRO" => 1e-6,
        "NANO" => 1e-9,
        "PICO" => 1e-12,
        "FEMTO" => 1e-15,
        "ATTO" => 1e-18,
        _ => return None,
    };
    Some(factor)
}

/// Millimetres per length unit of representation `rep`'s context, when it
/// declares one.
pub fn rep_length_mm(ctx: &Ctx, rep: u64) -> Option<f64> {
    let context = rep_context(ctx, rep)?;
    context_unit(ctx, context, "LENGTH_UNIT", 1000.0)
        .ok()
        .flatten()
        .filter(|f| f.is_finite() && *f > 0.0)
}

fn rep_context<'a>(ctx: &Ctx<'a>, rep: u64) -> Option<&'a Instance> {
    let rec = ctx.step.get(rep)?.records.first()?;
    let context = ctx.step.get(as_ref(rec.params.get(2)?)?)?;
    has_record(context, "GLOBAL_UNIT_ASSIGNED_CONTEXT").then_some(context)
}

/// The smallest declared length uncertainty of a context, mm (`None` when
/// it declares none or it cannot be read).
fn uncertainty(ctx: &Ctx, context: &Instance) -> Option<f64> {
    let args = ctx
        .args(context.id, "GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT")
        .ok()?;
    let ids = args.refs(0).ok()?;
    ids.into_iter()
        .filter_map(|id| {
            let inst = ctx.inst(id).ok()?;
            let rec = inst
                .records
                .iter()
                .find(|r| r.name == "UNCERTAINTY_MEASURE_WITH_UNIT")?;
            let unit = ctx.inst(as_ref(rec.params.get(1)?)?).ok()?;
            if !has_record(unit, "LENGTH_UNIT") {
                return None;
            }
            let value = rec.params.first().and_then(as_real)?;
            let factor = unit_factor(ctx, unit, 1000.0, 0).ok()?;
            Some(value * factor)
        })
        .filter(|u| u.is_finite() && *u > 0.0)
        .reduce(f64::min)
}
