//! IGES 5.3 reader: trimmed surfaces (144) on rational B-spline surfaces
//! (128) with parameter-space boundaries (142 -> 102/110/100/126), 124
//! transformations, units from the Global section.
pub mod entities;
pub mod params;
pub mod records;

use super::error::CadResult;
use super::geom::EPS_UV;
use super::options::ImportOptions;
use super::sample::adaptive;
use super::step::lexer::Pos;
use super::{DiagnosticKind, Import, Source};
use crate::geometry::NurbsSurface;
use crate::workpiece::format::{SurfaceSpec, TrimSpec};
use entities::{param_curve, surface128, Model, Piece};
use records::Entry;
use std::collections::HashSet;

type P2 = [f64; 2];

/// Imports all trimmed (144) and free-standing (128) surfaces of an IGES text.
pub fn import_iges(text: &str, file: &str, name: &str, opts: &ImportOptions) -> CadResult<Import> {
    let sections = records::split_sections(text, file)?;
    let global = records::global(&sections.global, file)?;
    let entries = records::directory(&sections.directory, file)?;
    let model = Model {
        file,
        entries,
        params: &sections.parameters,
        global,
    };
    let mut out = Import::new(name);
    let used = trimmed_bases(&model);
    let faces = model
        .entries
        .iter()
        .filter(|e| e.kind == 144 || (e.kind == 128 && !used.contains(&e.seq)));
    for (n, e) in faces.enumerate() {
        let pos = Pos {
            line: e.line,
            column: 1,
        };
        let src = Source {
            entity: e.seq,
            entity_type: format!("IGES {}", e.kind),
            pos,
        };
        match face(&model, e, opts) {
            Ok((spec, note)) => out.push_face(n + 1, "", src, spec, note),
            Err(reason) => out.note(&src, DiagnosticKind::Skipped, reason),
        }
    }
    let first = sections.directory.first().map_or(1, |l| l.number);
    out.finish(file, first, 1)
}

/// DE pointers of the 128 surfaces that 144 entities trim.
fn trimmed_bases(m: &Model) -> HashSet<u64> {
    m.entries
        .iter()
        .filter(|e| e.kind == 144)
        .filter_map(|e| m.fields(e).ok()?.ptr(1).ok())
        .collect()
}

/// Converts a 144 (or a bare 128); the note explains a missing trim.
fn face(
    m: &Model,
    e: &Entry,
    opts: &ImportOptions,
) -> Result<(SurfaceSpec, Option<String>), String> {
    if e.kind == 128 {
        return surface128(m, e)
            .map(|(s, _)| (s, None))
            .map_err(|x| x.to_string());
    }
    let f = m.fields(e).map_err(|x| x.to_string())?;
    let base = m
        .entry(f.ptr(1).map_err(|x| x.to_string())?)
        .map_err(|x| x.to_string())?;
    if base.kind != 128 {
        return Err(format!(
            "trimmed surface on unsupported surface type {}",
            base.kind
        ));
    }
    let (mut spec, [u0, u1, v0, v1]) = surface128(m, base).map_err(|x| x.to_string())?;
    let trim = spec
        .to_surface()
        .map_err(|e| format!("surface cannot be evaluated: {e}"))
        .and_then(|s| trim144(m, &f, &s, [u0, u1, v0, v1], opts));
    let note = trim.as_ref().err().cloned();
    spec.trim = trim.ok();
    Ok((spec, note))
}

fn trim144(
    m: &Model,
    f: &entities::Fields,
    spec: &NurbsSurface,
    [u0, u1, v0, v1]: [f64; 4],
    opts: &ImportOptions,
) -> Result<TrimSpec, String> {
    let s = |x: CadResult<i64>| x.map_err(|e| e.to_string());
    let (n1, n2) = (s(f.int(2))?, s(f.int(3))?);
    let outer = if n1 == 0 {
        vec![[u0, v0], [u1, v0], [u1, v1], [u0, v1]]
    } else {
        boundary(m, f.ptr(4).map_err(|e| e.to_string())?, spec, opts)?
    };
    let holes = (0..usize::try_from(n2).unwrap_or(0))
        .map(|k| boundary(m, f.ptr(5 + k).map_err(|e| e.to_string())?, spec, opts))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(TrimSpec { outer, holes })
}

/// The parameter-space polyline of a 142 curve on surface.
fn boundary(
    m: &Model,
    de: u64,
    spec: &NurbsSurface,
    opts: &ImportOptions,
) -> Result<Vec<P2>, String> {
    let e = m.entry(de).map_err(|x| x.to_string())?;
    if e.kind != 142 {
        return Err(format!(
            "boundary DE {de} is entity {} (expected 142)",
            e.kind
        ));
    }
    let f = m.fields(e).map_err(|x| x.to_string())?;
    let bptr = f.ptr(3).map_err(|x| x.to_string())?;
    if bptr == 0 {
        return Err(format!(
            "curve on surface DE {de} has no parameter-space curve"
        ));
    }
    let pieces = param_curve(m, bptr, 0).map_err(|x| x.to_string())?;
    let mut out: Vec<P2> = Vec::new();
    for p in &pieces {
        let pts = sample_piece(p, spec, opts);
        let skip = usize::from(out.last().is_some_and(|l| {
            pts.first()
                .is_some_and(|f| (l[0] - f[0]).hypot(l[1] - f[1]) < EPS_UV)
        }));
        out.extend(pts.into_iter().skip(skip));
    }
    if out.len() > 1
        && out
            .first()
            .zip(out.last())
            .is_some_and(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) < EPS_UV)
    {
        out.pop();
    }
    Ok(out)
}

fn sample_piece(p: &Piece, spec: &NurbsSurface, opts: &ImportOptions) -> Vec<P2> {
    match p {
        Piece::Segment(a, b) => vec![[a.x, a.y], [b.x, b.y]],
        Piece::Arc(c, t0, t1) => {
            let f = |t: f64| {
                let q = c.eval(t);
                spec.point(q.x, q.y)
            };
            let initial = crate::cad::step::topology::initial_segments(c, *t0, *t1);
            adaptive(
                &f,
                *t0,
                *t1,
                initial,
                opts.chord_tolerance_mm,
                opts.max_edge_samples,
            )
            .into_iter()
            .map(|(t, _)| {
                let q = c.eval(t);
                [q.x, q.y]
            })
            .collect()
        }
    }
}
