//! STEP (ISO 10303-21; AP203/AP214/AP242) reader: exchange-structure parser,
//! reference checks, units and B-rep face extraction.
pub mod access;
pub mod assembly;
pub mod bspline;
pub mod curves;
pub mod faces;
pub mod graph;
pub mod lexer;
pub mod parser;
pub mod pcurves;
pub mod placement;
pub mod projected;
pub mod shapes;
pub mod strings;
pub mod surfaces;
pub mod topology;
pub mod units;

use super::error::CadResult;
use super::options::ImportOptions;
use super::{DiagnosticKind, Import, Source};
use access::{has_record, type_name, Ctx};
use assembly::FaceInstance;
use faces::Converted;
use parser::StepFile;
use placement::Transform;
use shapes::FACE_TYPES;
use std::collections::HashMap;
use topology::{EdgeSampler, FaceData};

/// Parses STEP text: syntax, then reference resolution (unknown and cyclic
/// references are errors). Never panics on any input.
pub fn parse_step_str(text: &str) -> CadResult<StepFile> {
    parse_step(text, "<string>")
}

/// Like [`parse_step_str`], naming `file` in errors.
pub fn parse_step(text: &str, file: &str) -> CadResult<StepFile> {
    let step = parser::parse_syntax(text, file)?;
    graph::check_references(&step, file)?;
    Ok(step)
}

/// Imports all faces of a STEP text: every face instance of the product
/// structure (placed into the top frame and named after its product
/// instance), or every face once when the file has no product structure.
pub fn import_step(text: &str, file: &str, name: &str, opts: &ImportOptions) -> CadResult<Import> {
    let step = parse_step(text, file)?;
    let u = units::find_units(&step, file)?;
    let ctx = Ctx {
        step: &step,
        file,
        length_mm: u.length_mm,
        angle_rad: u.angle_rad,
    };
    let opts = &opts.with_file_uncertainty(u.uncertainty_mm);
    let tree = assembly::structure(&ctx)?;
    let ordinals = face_ordinals(&step);
    let instances = if tree.faces.is_empty() {
        every_face_once(&step, ctx.length_mm)
    } else {
        tree.faces
    };
    let mut out = Import::new(name);
    out.products = tree.roots;
    let mut conv = Converter {
        ctx,
        opts: *opts,
        samplers: Vec::new(),
        done: HashMap::new(),
    };
    for fi in &instances {
        let n = ordinals.get(&fi.face).copied().unwrap_or(0);
        let (first, result) = conv.convert(fi.face, fi.length_mm)?;
        let inst = ctx.inst(fi.face)?;
        let src = |entity_type: String| Source {
            entity: inst.id,
            entity_type,
            pos: inst.pos,
        };
        match result {
            Ok((f, c)) => {
                let mut spec = c.spec.clone();
                fi.transform.apply_to(&mut spec);
                spec.reversed ^= fi.flipped;
                let own = if f.name.trim().is_empty() {
                    format!("face{n}")
                } else {
                    f.name.clone()
                };
                let label = match fi.prefix.is_empty() {
                    true => own,
                    false => format!("{}/{own}", fi.prefix),
                };
                let note = c.untrimmed.clone().filter(|_| first);
                out.push_face(n, &label, src(c.surface_type.clone()), spec, note);
            }
            Err(reason) if first => out.note(
                &src(type_name(inst)),
                DiagnosticKind::Skipped,
                reason.clone(),
            ),
            Err(_) => {}
        }
    }
    out.finish(file, step.data_pos.line, step.data_pos.column)
}

/// 1-based file-order number of each face entity (for `face<N>` names).
fn face_ordinals(step: &StepFile) -> HashMap<u64, usize> {
    step.instances
        .iter()
        .filter(|i| FACE_TYPES.iter().any(|t| has_record(i, t)))
        .enumerate()
        .map(|(k, i)| (i.id, k + 1))
        .collect()
}

/// Every face of the file once, in file order, unplaced.
fn every_face_once(step: &StepFile, length_mm: f64) -> Vec<FaceInstance> {
    step.instances
        .iter()
        .filter(|i| FACE_TYPES.iter().any(|t| has_record(i, t)))
        .map(|i| FaceInstance {
            face: i.id,
            transform: Transform::identity(),
            flipped: false,
            length_mm,
            prefix: String::new(),
        })
        .collect()
}

type Outcome = Result<(FaceData, Converted), String>;

/// Converts each face once per length unit; instances share the result.
struct Converter<'a> {
    ctx: Ctx<'a>,
    opts: ImportOptions,
    samplers: Vec<(u64, EdgeSampler<'a>)>,
    done: HashMap<(u64, u64), Outcome>,
}

impl<'a> Converter<'a> {
    /// The face's conversion and whether this is its first use.
    fn convert(&mut self, face: u64, length_mm: f64) -> CadResult<(bool, &Outcome)> {
        let key = (face, length_mm.to_bits());
        let first = !self.done.contains_key(&key);
        if first {
            let ctx = Ctx {
                length_mm,
                ..self.ctx
            };
            let k = match self.samplers.iter().position(|s| s.0 == key.1) {
                Some(k) => k,
                None => {
                    self.samplers
                        .push((key.1, EdgeSampler::new(ctx, self.opts)));
                    self.samplers.len() - 1
                }
            };
            let Some((_, sampler)) = self.samplers.get_mut(k) else {
                return Err(ctx.err(ctx.inst(face)?, "no edge sampler"));
            };
            let kind = type_name(ctx.inst(face)?);
            let kind = FACE_TYPES
                .iter()
                .find(|t| kind == **t)
                .copied()
                .unwrap_or("ADVANCED_FACE");
            let opts = self.opts;
            let result = topology::face(&ctx, face, kind)
                .map_err(|e| e.to_string())
                .and_then(|f| faces::convert_face(&ctx, sampler, &f, &opts).map(|c| (f, c)));
            self.done.insert(key, result);
        }
        match self.done.get(&key) {
            Some(r) => Ok((first, r)),
            None => Err(self.ctx.err(self.ctx.inst(face)?, "face conversion lost")),
        }
    }
}
