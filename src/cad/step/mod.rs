//! STEP (ISO 10303-21; AP203/AP214/AP242) reader: exchange-structure parser,
//! reference checks, units and B-rep face extraction.
pub mod access;
pub mod curves;
pub mod faces;
pub mod graph;
pub mod lexer;
pub mod parser;
pub mod pcurves;
pub mod projected;
pub mod strings;
pub mod surfaces;
pub mod topology;
pub mod units;

use super::error::CadResult;
use super::options::ImportOptions;
use super::{DiagnosticKind, Import, Source};
use access::{has_record, type_name, Ctx};
use parser::StepFile;
use topology::EdgeSampler;

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

/// Face entity types read as B-rep faces.
const FACE_TYPES: [&str; 2] = ["ADVANCED_FACE", "FACE_SURFACE"];

/// Imports all faces of a STEP text.
pub fn import_step(text: &str, file: &str, name: &str, opts: &ImportOptions) -> CadResult<Import> {
    let step = parse_step(text, file)?;
    let u = units::find_units(&step, file)?;
    let ctx = Ctx {
        step: &step,
        file,
        length_mm: u.length_mm,
        angle_rad: u.angle_rad,
    };
    let mut out = Import::new(name);
    let mut sampler = EdgeSampler::new(ctx, *opts);
    let faces = step.instances.iter().filter_map(|i| {
        FACE_TYPES
            .iter()
            .find(|t| has_record(i, t))
            .map(|t| (i, *t))
    });
    for (n, (inst, kind)) in faces.enumerate() {
        let result = topology::face(&ctx, inst.id, kind)
            .map_err(|e| e.to_string())
            .and_then(|f| faces::convert_face(&ctx, &mut sampler, &f, opts).map(|c| (f, c)));
        let src = |entity_type: String| Source {
            entity: inst.id,
            entity_type,
            pos: inst.pos,
        };
        match result {
            Ok((f, c)) => out.push_face(n + 1, &f.name, src(c.surface_type), c.spec, c.untrimmed),
            Err(reason) => out.note(&src(type_name(inst)), DiagnosticKind::Skipped, reason),
        }
    }
    out.finish(file, step.data_pos.line, step.data_pos.column)
}
