//! `cmm import FILE --out W.json`: a STEP/IGES part as a `cmm-workpiece/1` file.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::{CliError, Status};
use crate::cad::{Diagnostic, DiagnosticKind, Import};

/// Arguments of `cmm import`.
#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// STEP (.step/.stp) or IGES (.iges/.igs) file.
    pub file: PathBuf,
    /// Workpiece file to write (atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `cmm import`: converts, writes the workpiece, then reports every
/// face that was skipped or left untrimmed and a per-type summary on stderr.
pub fn run(args: &ImportArgs) -> Result<Status, CliError> {
    let import = crate::cad::import(&args.file)?;
    crate::workpiece::Workpiece::from_file(&import.workpiece, &args.file)?;
    let mut text = serde_json::to_string_pretty(&import.workpiece).unwrap_or_default();
    text.push('\n');
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    for d in &import.diagnostics {
        eprintln!("{}", diagnostic_line(&args.file, d));
    }
    eprintln!("{}", summary_line(&import));
    Ok(Status::Pass)
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
