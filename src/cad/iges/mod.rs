//! IGES 5.3 reader.
//!
//! Faces come from: 186 manifold solid B-reps (514 shells, 510 faces, 508
//! loops, 504 edges, 502 vertices; [`brep`]), 144 trimmed surfaces (142
//! boundaries), 143 bounded surfaces (141 boundaries), and free-standing
//! bounded surfaces (128, 118, 120, 122, 196 sphere, 198 torus) untrimmed.
//! Surfaces ([`surfaces`]): 128 rational B-splines, 118 ruled, 120
//! revolution, 122 tabulated cylinder, 108 bounded plane, 190 plane, 192
//! cylinder, 194 cone, 196 sphere, 198 torus, all converted to exact
//! rational B-splines. Curves ([`curves`]): 100, 102, 104 (ellipses), 106
//! (polylines), 110, 126. 124 transformations apply to every entity (chains
//! followed, cycles are errors); 408 subfigure instances place their 308
//! definitions (nested, with scale); the Global section's unit becomes mm.
//!
//! Trims: analytic and swept surfaces get exact trims from their model-space
//! boundary curves ([`crate::cad::convert::trim`]); B-spline surfaces use
//! parameter-space curves, else the model-space curves projected.
//!
//! Errors: record, section, number and unit errors, and DE pointers that are
//! dangling or cyclic (124 chains, 308/408 nesting, composite curves) fail
//! the import with file, line and column; any other problem with one face
//! skips that face with a diagnostic naming its DE number, type and line.
pub mod brep;
pub mod curves;
pub mod entities;
pub mod faces;
pub mod params;
pub mod placement;
pub mod pspace;
pub mod records;
pub mod ruled;
pub mod surfaces;

use super::error::CadResult;
use super::options::ImportOptions;
use super::step::lexer::Pos;
use super::{DiagnosticKind, Import, Source};
use entities::{is_hard, Affine, Model};
use faces::FaceOut;
use placement::{dependent, items, uses, Item, Uses};
use records::Entry;
use std::collections::HashSet;
use surfaces::{surface, SURFACE_TYPES};

/// Imports the faces of an IGES text (lengths converted to mm).
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
    check_transforms(&model)?;
    let uses = uses(&model);
    let unit = Affine::scaling(model.global.unit_mm);
    let mut run = Run {
        m: &model,
        opts,
        out: Import::new(name),
        n: 0,
        in_solid: in_solids(&model, &uses),
    };
    for item in items(&model, &uses, &unit)? {
        run.item(&item, &uses)?;
    }
    let first = sections.directory.first().map_or(1, |l| l.number);
    run.out.finish(file, first, 1)
}

/// Every entry's 124 chain must resolve: dangling or cyclic chains fail.
fn check_transforms(m: &Model) -> CadResult<()> {
    for e in m.entries.iter().filter(|e| e.transform != 0) {
        if let Err(x) = m.transform(e) {
            if is_hard(&x) {
                return Err(x);
            }
        }
    }
    Ok(())
}

/// Shells and faces that a solid or shell takes care of.
fn in_solids(m: &Model, u: &Uses) -> HashSet<u64> {
    m.entries
        .iter()
        .filter(|e| matches!(e.kind, 510 | 514) && u.parts.contains(&e.seq))
        .map(|e| e.seq)
        .collect()
}

struct Run<'a> {
    m: &'a Model<'a>,
    opts: &'a ImportOptions,
    out: Import,
    n: usize,
    in_solid: HashSet<u64>,
}

impl Run<'_> {
    fn item(&mut self, item: &Item, uses: &Uses) -> CadResult<()> {
        let (m, e) = (self.m, item.entry);
        let free_surface = SURFACE_TYPES.contains(&e.kind)
            && !uses.parts.contains(&e.seq)
            && (item.instanced || !dependent(e));
        match e.kind {
            186 => self.solid(item),
            514 | 510 if self.in_solid.contains(&e.seq) => Ok(()),
            514 => {
                let faces = brep::shell_faces(m, e, true);
                self.faces(item, e, faces)
            }
            510 => {
                let sf = brep::ShellFace {
                    face: e.seq,
                    same_sense: true,
                };
                self.faces(item, e, Ok(vec![sf]))
            }
            144 => {
                let r = faces::face144(m, e, &item.place, self.opts);
                self.push(e, r)
            }
            143 => {
                let r = faces::face143(m, e, &item.place, self.opts);
                self.push(e, r)
            }
            _ if free_surface => {
                let r = surface(m, e, &item.place).and_then(|s| {
                    s.untrimmed()
                        .map(|spec| (spec, None, e.kind))
                        .map_err(|r| m.err(e, r))
                });
                self.push(e, r)
            }
            _ => Ok(()),
        }
    }

    fn solid(&mut self, item: &Item) -> CadResult<()> {
        let e = item.entry;
        let place = match self.m.transform(e) {
            Ok(t) => item.place.then_inner(&t),
            Err(x) => return self.push(e, Err(x)),
        };
        let faces = brep::solid_faces(self.m, e);
        let solid = Item {
            entry: e,
            place,
            instanced: item.instanced,
        };
        self.faces(&solid, e, faces)
    }

    /// Converts the faces of a solid or shell (or one free face).
    fn faces(
        &mut self,
        item: &Item,
        owner: &Entry,
        faces: CadResult<Vec<brep::ShellFace>>,
    ) -> CadResult<()> {
        let faces = match faces {
            Ok(f) => f,
            Err(x) => return self.push(owner, Err(x)),
        };
        let mut cache = brep::EdgeCache::new(item.place, *self.opts);
        for sf in faces {
            let Some(fe) = self.m.get(sf.face) else {
                return Err(self.m.missing(sf.face));
            };
            let r = brep::face510(self.m, sf, &mut cache, self.opts);
            self.push(fe, r)?;
        }
        Ok(())
    }

    /// Records one face (or its failure); dangling and cyclic pointers fail.
    fn push(&mut self, e: &Entry, r: CadResult<FaceOut>) -> CadResult<()> {
        self.n += 1;
        let pos = Pos {
            line: e.line,
            column: 1,
        };
        match r {
            Ok((spec, note, kind)) => {
                let src = Source {
                    entity: e.seq,
                    entity_type: format!("IGES {kind}"),
                    pos,
                };
                self.out.push_face(self.n, "", src, spec, note);
                Ok(())
            }
            Err(x) if is_hard(&x) => Err(x),
            Err(x) => {
                let src = Source {
                    entity: e.seq,
                    entity_type: format!("IGES {}", e.kind),
                    pos,
                };
                self.out.note(&src, DiagnosticKind::Skipped, x.to_string());
                Ok(())
            }
        }
    }
}
