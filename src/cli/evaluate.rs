//! `cmm evaluate --workpiece W --points P.csv [--json] [--out F]`.
use std::path::PathBuf;

use super::{emit, CliError, Status};
use crate::workpiece::Workpiece;

/// Arguments of `cmm evaluate`.
#[derive(Debug, clap::Args)]
pub struct EvaluateArgs {
    /// Workpiece file: cmm-workpiece/1 JSON, or STEP (.step/.stp) / IGES (.iges/.igs).
    #[arg(long)]
    pub workpiece: PathBuf,
    /// Point CSV file: a header naming x,y,z, then one point per line.
    #[arg(long)]
    pub points: PathBuf,
    /// Write `cmm-evaluate/1` JSON instead of CSV.
    #[arg(long)]
    pub json: bool,
    /// Write to this file (atomically) instead of stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `cmm evaluate`.
pub fn run(args: &EvaluateArgs) -> Result<Status, CliError> {
    let wp = Workpiece::from_path(&args.workpiece)?;
    let points = crate::pointfile::read_points_csv(&args.points)?;
    let report = crate::evaluate::evaluate(&wp, &points)?;
    let text = if args.json {
        let mut s = serde_json::to_string_pretty(&report).unwrap_or_default();
        s.push('\n');
        s
    } else {
        report.to_csv()
    };
    emit(&text, args.out.as_deref())?;
    Ok(Status::Pass)
}
