//! `cmm evaluate --workpiece W --points P.csv [--json] [--out F]`.
use std::path::PathBuf;

use super::{emit, CliError, Status};
use crate::evaluate::PointStatus;
use crate::geometry::projection::SearchStatus;
use crate::workpiece::Workpiece;

/// Arguments of `cmm evaluate`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Exit codes:\n  \
    0  every point evaluated and its closest point confirmed (status \"ok\")\n  \
    2  bad usage or bad input (workpiece, point file, a point that is not finite\n     \
       or out of range); nothing is written\n  \
    3  every point evaluated, but the closest point of at least one could not be\n     \
       confirmed: it carries status \"unconfirmed\" (the best point found) and a\n     \
       warning on stderr names it")]
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

/// Runs `cmm evaluate`: exit 0 when every point is confirmed, 3 when some
/// point is unconfirmed (all points are answered either way).
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
    for (k, p) in report.points.iter().enumerate() {
        if let SearchStatus::Unconfirmed {
            reason,
            last_step_mm,
        } = p.search
        {
            let [x, y, z] = p.input;
            eprintln!(
                "warning: point {} ({x}, {y}, {z}): closest point unconfirmed ({reason}, last step {last_step_mm:e} mm)",
                k + 1
            );
        }
    }
    Ok(
        if report.points.iter().all(|p| p.status == PointStatus::Ok) {
            Status::Pass
        } else {
            Status::Incomplete
        },
    )
}
