//! The faces of a shape representation: its items walked down through
//! solids, shells and oriented faces/shells; MAPPED_ITEMs are returned for
//! the caller to place.
use super::access::{as_ref, Ctx};
use super::parser::Value;
use crate::cad::error::CadResult;
use std::collections::HashSet;

/// Face entity types read as B-rep faces.
pub const FACE_TYPES: [&str; 2] = ["ADVANCED_FACE", "FACE_SURFACE"];

/// Deepest nesting of shells and oriented wrappers followed.
const MAX_SHAPE_DEPTH: usize = 16;

/// What a representation holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ItemWalk {
    /// Faces and whether an ORIENTED_FACE / ORIENTED_*_SHELL flipped them.
    pub faces: Vec<(u64, bool)>,
    /// MAPPED_ITEM ids among the items.
    pub mapped: Vec<u64>,
}

/// Walks the items of representation `rep`.
pub fn rep_items(ctx: &Ctx, rep: u64) -> CadResult<ItemWalk> {
    let items = ctx.first(rep)?.refs(1)?;
    let mut out = ItemWalk::default();
    let mut seen = HashSet::new();
    for item in items {
        walk(ctx, item, false, 0, &mut out, &mut seen)?;
    }
    Ok(out)
}

fn walk(
    ctx: &Ctx,
    id: u64,
    flip: bool,
    depth: usize,
    out: &mut ItemWalk,
    seen: &mut HashSet<u64>,
) -> CadResult<()> {
    let inst = ctx.inst(id)?;
    if depth > MAX_SHAPE_DEPTH {
        return Err(ctx.err(inst, "shells nested too deeply"));
    }
    let Some(rec) = inst.records.first() else {
        return Ok(());
    };
    let name = rec.name.as_str();
    if FACE_TYPES
        .iter()
        .any(|t| super::access::has_record(inst, t))
    {
        if seen.insert(id) {
            out.faces.push((id, flip));
        }
        return Ok(());
    }
    let refs_at = |i: usize| -> Vec<u64> {
        match rec.params.get(i) {
            Some(Value::List(items)) => items.iter().filter_map(as_ref).collect(),
            Some(v) => as_ref(v).into_iter().collect(),
            None => Vec::new(),
        }
    };
    let orientation = || matches!(rec.params.get(3), Some(Value::Enum(e)) if e == "F");
    let next: Vec<(u64, bool)> = match name {
        "MAPPED_ITEM" => {
            out.mapped.push(id);
            Vec::new()
        }
        "ORIENTED_FACE" | "ORIENTED_CLOSED_SHELL" | "ORIENTED_OPEN_SHELL" => refs_at(2)
            .into_iter()
            .map(|r| (r, flip != orientation()))
            .collect(),
        "CLOSED_SHELL"
        | "OPEN_SHELL"
        | "CONNECTED_FACE_SET"
        | "SHELL_BASED_SURFACE_MODEL"
        | "MANIFOLD_SOLID_BREP"
        | "FACETED_BREP"
        | "FACE_BASED_SURFACE_MODEL" => refs_at(1).into_iter().map(|r| (r, flip)).collect(),
        "BREP_WITH_VOIDS" => refs_at(1)
            .into_iter()
            .chain(refs_at(2))
            .map(|r| (r, flip))
            .collect(),
        _ => Vec::new(),
    };
    for (r, f) in next {
        walk(ctx, r, f, depth + 1, out, seen)?;
    }
    Ok(())
}
