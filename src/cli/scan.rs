//! `cmm scan PROGRAM.json... [--out DIR] [--seed N] [--jobs N] [--ideal] [--quiet]`.
use std::path::{Path, PathBuf};

use super::{CliError, Status};
use crate::inspect::{run_program, RunOptions};
use crate::program::load;
use crate::report::{Report, Verdict};

/// Arguments of `cmm scan`.
#[derive(Debug, clap::Args)]
pub struct ScanArgs {
    /// Part program files.
    #[arg(required = true)]
    pub programs: Vec<PathBuf>,
    /// Output folder (a subfolder per program when there are several).
    #[arg(long, default_value = "cmm-out")]
    pub out: PathBuf,
    /// Seed of every simulated random draw.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Parallel jobs.
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// Switch off every simulated error and all noise.
    #[arg(long)]
    pub ideal: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `cmm scan`: validates every program first, then measures.
pub fn run(args: &ScanArgs) -> Result<Status, CliError> {
    let programs = args
        .programs
        .iter()
        .map(|p| load(p))
        .collect::<Result<Vec<_>, _>>()?;
    let opts = RunOptions {
        seed: args.seed,
        ideal: args.ideal,
        ..RunOptions::default()
    };
    let mut reports = Vec::new();
    for (k, program) in programs.iter().enumerate() {
        let (report, _) = run_program(program, &opts)?;
        let dir = out_dir(&args.out, &args.programs, k, &program.name);
        write_reports(&dir, &report)?;
        reports.push(report);
    }
    print_summary(&reports);
    Ok(status(&reports))
}

fn out_dir(out: &Path, files: &[PathBuf], k: usize, name: &str) -> PathBuf {
    if files.len() == 1 {
        return out.to_path_buf();
    }
    let stem = files
        .get(k)
        .and_then(|f| f.file_stem())
        .map_or_else(|| name.to_string(), |s| s.to_string_lossy().into_owned());
    out.join(format!("{k:02}-{stem}"))
}

fn write_reports(dir: &Path, report: &Report) -> Result<(), CliError> {
    std::fs::create_dir_all(dir).map_err(|source| crate::output::WriteError {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut json = serde_json::to_string_pretty(report).unwrap_or_default();
    json.push('\n');
    crate::output::write_atomic(&dir.join("report.json"), json.as_bytes())?;
    Ok(())
}

fn print_summary(reports: &[Report]) {
    println!(
        "{:<24} {:<28} {:>10} {:>8} {:>10} {:>10}  attempts",
        "program", "feature", "status", "points", "min mm", "max mm"
    );
    for r in reports {
        for f in &r.features {
            let attempts: Vec<String> = f
                .attempts
                .iter()
                .map(|a| {
                    format!(
                        "{}:{}",
                        a.mode,
                        serde_json::to_string(&a.outcome)
                            .unwrap_or_default()
                            .trim_matches('"')
                    )
                })
                .collect();
            println!(
                "{:<24} {:<28} {:>10} {:>8} {:>10.4} {:>10.4}  {}",
                r.program,
                f.name,
                format!("{:?}", f.status).to_lowercase(),
                f.points.len(),
                f.deviation_mm.min,
                f.deviation_mm.max,
                attempts.join(" -> ")
            );
        }
    }
}

fn status(reports: &[Report]) -> Status {
    if reports.iter().any(|r| r.status == Verdict::Incomplete) {
        Status::Incomplete
    } else if reports.iter().any(|r| r.status == Verdict::Fail) {
        Status::OutOfTolerance
    } else {
        Status::Pass
    }
}
