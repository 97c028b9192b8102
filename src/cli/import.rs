//! `cmm import FILE --out W.json`: a STEP/IGES part as a `cmm-workpiece/1` file.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::{CliError, Status};
use crate::cad::step::assembly::ProductNode;
use crate::cad::{Diagnostic, DiagnosticKind, Import};

/// Arguments of `cmm import`.
#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// STEP (.step/.stp) or IGES (.iges/.igs) file.
    pub file: PathBuf,
    /// Workpiece file to write (atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Also print the product tree (assembly occurrences, their placements
    /// and face counts) and every face (its name for a program's
    /// `surfaces`, the CAD entity and surface type, box, area, and a point
    /// near its middle with the outward normal) on stdout.
    #[arg(long)]
    pub list: bool,
}

/// Runs `cmm import`: converts, writes the workpiece, then reports every
/// face that was skipped or left untrimmed and a per-type summary on stderr.
pub fn run(args: &ImportArgs) -> Result<Status, CliError> {
    let import = crate::cad::import(&args.file)?;
    let wp = crate::workpiece::Workpiece::from_file(&import.workpiece, &args.file)?;
    let mut text = serde_json::to_string_pretty(&import.workpiece).unwrap_or_default();
    text.push('\n');
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    if args.list {
        for line in tree_lines(&import)
            .into_iter()
            .chain(face_lines(&import, &wp))
        {
            println!("{line}");
        }
    }
    for d in &import.diagnostics {
        eprintln!("{}", diagnostic_line(&args.file, d));
    }
    eprintln!("{}", summary_line(&import));
    if let Some(note) = size_note(&wp) {
        eprintln!("{note}");
    }
    Ok(Status::Pass)
}

/// A part smaller than this across (mm) is likely one whose file states
/// the wrong units: the import says so.
const SMALL_PART_MM: f64 = 1.0;

/// A note on stderr for a part under [`SMALL_PART_MM`] across.
pub fn size_note(wp: &crate::workpiece::Workpiece) -> Option<String> {
    let mut faces = wp.faces.iter().map(|f| f.bounds());
    let first = faces.next()?;
    let (lo, hi) = faces.fold(first, |(l, h), (a, b)| (l.inf(&a), h.sup(&b)));
    let across = (hi - lo).norm();
    (across < SMALL_PART_MM).then(|| {
        format!(
            "note: the part is {across:.4} mm across (its control points' box) in the file's \
             own units; check them if the part is larger"
        )
    })
}

/// `file:line:column: #id TYPE: skipped|untrimmed: reason`.
pub fn diagnostic_line(file: &Path, d: &Diagnostic) -> String {
    let kind = match d.kind {
        DiagnosticKind::Skipped => "skipped",
        DiagnosticKind::Untrimmed => "untrimmed",
    };
    format!(
        "{}:{}:{}: #{} {}: {kind}: {}",
        file.display(),
        d.line,
        d.column,
        d.entity,
        d.entity_type,
        d.message
    )
}

/// `imported N faces (TYPE: n, ...); S skipped, U untrimmed`.
pub fn summary_line(import: &Import) -> String {
    let mut per_type: BTreeMap<&str, usize> = BTreeMap::new();
    for f in &import.faces {
        *per_type.entry(f.surface_type.as_str()).or_insert(0) += 1;
    }
    let types: Vec<String> = per_type.iter().map(|(t, n)| format!("{t}: {n}")).collect();
    let count = |k: DiagnosticKind| import.diagnostics.iter().filter(|d| d.kind == k).count();
    format!(
        "imported {} faces ({}); {} skipped, {} untrimmed",
        import.faces.len(),
        types.join(", "),
        count(DiagnosticKind::Skipped),
        count(DiagnosticKind::Untrimmed)
    )
}

/// One line a face, in workpiece order: `name #entity TYPE: box (x, y, z)
/// .. (x, y, z), area A mm2, at (x, y, z) normal (i, j, k)` (part
/// coordinates, mm; see [`crate::workpiece::FaceSummary`]).
pub fn face_lines(import: &Import, wp: &crate::workpiece::Workpiece) -> Vec<String> {
    let p = |v: &[f64]| format!("({:.3}, {:.3}, {:.3})", v[0], v[1], v[2]);
    (wp.faces.iter().zip(&import.faces))
        .map(|(face, record)| {
            let head = format!("{} #{} {}", face.name, record.entity, record.surface_type);
            match face.summary(crate::workpiece::SUMMARY_GRID) {
                Some(s) => format!(
                    "{head}: box {} .. {}, area {:.3} mm2, at {} normal {}",
                    p(s.lo.coords.as_slice()),
                    p(s.hi.coords.as_slice()),
                    s.area_mm2,
                    p(s.at.coords.as_slice()),
                    p(s.normal.as_slice()),
                ),
                None => format!("{head}: narrower than the sampling grid"),
            }
        })
        .collect()
}

/// The product tree, one node a line, indented two spaces per level:
/// `label (#entity[, occurrence #id]): N faces[, at (x, y, z) rotated A deg about (ax, ay, az)]`;
/// a file without product structure gives one line with its face count.
pub fn tree_lines(import: &Import) -> Vec<String> {
    let mut out = Vec::new();
    if import.products.is_empty() {
        out.push(format!(
            "{}: {} faces (no product structure)",
            import.workpiece.name,
            import.faces.len()
        ));
    }
    for node in &import.products {
        node_lines(node, 0, &mut out);
    }
    out
}

fn node_lines(node: &ProductNode, depth: usize, out: &mut Vec<String>) {
    let occurrence = match node.occurrence {
        0 => String::new(),
        id => format!(", occurrence #{id}"),
    };
    let place = if node.placement.is_identity() {
        String::new()
    } else {
        placement_text(node)
    };
    out.push(format!(
        "{}{} (#{}{occurrence}): {} faces{place}",
        "  ".repeat(depth),
        node.label,
        node.entity,
        node.faces
    ));
    for c in &node.children {
        node_lines(c, depth + 1, out);
    }
}

fn placement_text(node: &ProductNode) -> String {
    let t = node.placement.shift;
    let rot = nalgebra::Rotation3::from_matrix_unchecked(node.placement.linear);
    let (axis, angle) = rot
        .axis_angle()
        .map_or((crate::math::Vec3::z(), 0.0), |(a, ang)| {
            (a.into_inner(), ang)
        });
    format!(
        ", at ({:.6}, {:.6}, {:.6}) rotated {:.6} deg about ({:.6}, {:.6}, {:.6})",
        t.x,
        t.y,
        t.z,
        angle.to_degrees(),
        axis.x,
        axis.y,
        axis.z
    )
}
