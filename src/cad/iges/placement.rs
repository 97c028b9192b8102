//! The entities a file shows, each with its placement: top-level entities
//! as they are (scaled to mm), 308 subfigure definitions through their 408
//! instances (nested, with translation, scale and the instance's 124), and
//! the references that decide which surfaces stand free.
use super::entities::{Affine, Model, MAX_CHAIN};
use super::records::Entry;
use crate::cad::error::CadResult;
use crate::math::Vec3;
use std::collections::HashSet;

/// An entity to convert and the map from its parent's definition space to mm.
#[derive(Debug, Clone, PartialEq)]
pub struct Item<'m> {
    /// The entity.
    pub entry: &'m Entry,
    /// Placement (includes the unit scale).
    pub place: Affine,
    /// True for members of a subfigure definition (placed by an instance).
    pub instanced: bool,
}

/// Entities that other entities use as parts (surfaces of faces, faces of
/// shells, shells of solids) and the members of subfigure definitions.
#[derive(Debug, Default)]
pub struct Uses {
    /// DE pointers used as parts.
    pub parts: HashSet<u64>,
    /// DE pointers that are members of a 308 definition.
    pub members: HashSet<u64>,
}

/// Scans the part references (surfaces of faces and boundaries, faces of
/// shells, shells of solids) and the members of subfigure definitions.
pub fn uses(m: &Model) -> Uses {
    let mut u = Uses::default();
    for e in &m.entries {
        let Ok(f) = m.fields(e) else { continue };
        let ptr = |k: usize| f.ptr(k).ok();
        let listed = |count: usize, first: usize, stride: usize| -> Vec<u64> {
            let n = f.count(count).unwrap_or(0).min(f.len());
            (0..n)
                .filter_map(|i| f.ptr(first + stride * i).ok())
                .collect()
        };
        let found: Vec<u64> = match e.kind {
            144 | 142 => ptr(1).into_iter().chain(ptr(2)).collect(),
            143 | 141 => ptr(2).into_iter().chain(ptr(3)).collect(),
            510 => ptr(1).into_iter().collect(),
            514 => listed(1, 2, 2),
            186 => {
                let mut v: Vec<u64> = ptr(1).into_iter().collect();
                v.extend(listed(3, 4, 2));
                v
            }
            308 => {
                u.members.extend(listed(3, 4, 1));
                Vec::new()
            }
            _ => Vec::new(),
        };
        u.parts.extend(found);
    }
    u
}

/// Most entities a file may expand to through subfigure instances.
const MAX_ITEMS: usize = 1_000_000;

/// True when the status field marks the entry physically dependent on a parent.
pub fn dependent(e: &Entry) -> bool {
    matches!(e.status.get(2..4), Some("01") | Some("03"))
}

/// The top-level entities (not subfigure members) with 408 instances
/// expanded, each placed by `unit` (model units to mm).
pub fn items<'m>(m: &'m Model, uses: &Uses, unit: &Affine) -> CadResult<Vec<Item<'m>>> {
    let mut out = Vec::new();
    for e in &m.entries {
        if uses.members.contains(&e.seq) || e.kind == 308 {
            continue;
        }
        expand(m, e, unit, &mut vec![e.seq], &mut out)?;
    }
    Ok(out)
}

fn expand<'m>(
    m: &'m Model,
    e: &'m Entry,
    place: &Affine,
    stack: &mut Vec<u64>,
    out: &mut Vec<Item<'m>>,
) -> CadResult<()> {
    if out.len() >= MAX_ITEMS {
        return Err(m.err(e, "subfigure instances expand to too many entities"));
    }
    // Instances are listed too (and ignored later), so that the list length
    // counts every visit.
    out.push(Item {
        entry: e,
        place: *place,
        instanced: stack.len() > 1,
    });
    if e.kind != 408 {
        return Ok(());
    }
    let f = m.fields(e)?;
    let def = f.target(1)?;
    if def.kind != 308 {
        return Err(f.bad(
            1,
            &format!(
                "points to entity {} (expected a 308 subfigure definition)",
                def.kind
            ),
        ));
    }
    if stack.contains(&def.seq) || stack.len() > MAX_CHAIN {
        stack.push(def.seq);
        return Err(m.cycle(def, stack));
    }
    let opt = |k: usize, default: f64| -> CadResult<f64> {
        if k >= f.len() {
            return Ok(default);
        }
        let v = f.real(k)?;
        Ok(if v == 0.0 && default != 0.0 {
            default
        } else {
            v
        })
    };
    let scale = opt(5, 1.0)?;
    let shift = Vec3::new(opt(2, 0.0)?, opt(3, 0.0)?, opt(4, 0.0)?);
    let local = Affine {
        m: Affine::scaling(scale).m,
        t: shift,
    };
    let inst = place
        .then_inner(&m.transform(e)?)
        .then_inner(&local)
        .then_inner(&m.transform(def)?);
    let g = m.fields(def)?;
    stack.push(e.seq);
    stack.push(def.seq);
    for k in 0..g.count(3)? {
        let member = g.target(4 + k)?;
        expand(m, member, &inst, stack, out)?;
    }
    stack.truncate(stack.len() - 2);
    Ok(())
}
