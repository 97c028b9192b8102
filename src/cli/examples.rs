//! `cmm example-workpieces --out DIR` (hidden): regenerates `workpieces/`.
use std::path::PathBuf;

use super::{CliError, Status};

/// Arguments.
#[derive(Debug, clap::Args)]
pub struct ExamplesArgs {
    /// Output folder.
    #[arg(long, default_value = "workpieces")]
    pub out: PathBuf,
}

/// Writes every example workpiece as `<stem>.json`.
pub fn run(args: &ExamplesArgs) -> Result<Status, CliError> {
    for (stem, wp) in crate::workpiece::examples::all() {
        let text = crate::workpiece::examples::to_json(&wp);
        crate::output::write_atomic(&args.out.join(format!("{stem}.json")), text.as_bytes())?;
    }
    let points = crate::workpiece::examples::blade_points_csv();
    crate::output::write_atomic(&args.out.join("blade-points.csv"), points.as_bytes())?;
    Ok(Status::Pass)
}
