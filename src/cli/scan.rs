//! `cmm scan PROGRAM.json... [--out DIR] [--seed N] [--jobs N] [--ideal]
//! [--quiet] [--variants N] [--shard K/N] [--corrections FILE]
//! [--probe-cal FILE] [--machine URDF] [--machine-profile FILE]
//! [--no-compensation]`.
use std::path::PathBuf;

use super::{CliError, Status};
use crate::app::batch::{plan_parts, run_batch, run_part_traced, Part, PartResult};
use crate::app::{load_on, probe_calibration, RunOptions, SimulatedPart};
use crate::formats::serde_name;
use crate::host::calibrate::file::ProbeCalibration;
use crate::host::inspect::learned::CorrectionsFile;
use crate::host::modes::Outcome;
use crate::host::trace::trace_csv;
use crate::output::OutputSet;
use crate::program::MachineFiles;
use crate::report::{Report, Verdict};

/// Arguments of `cmm scan`.
#[derive(Debug, clap::Args)]
pub struct ScanArgs {
    /// Part program files.
    #[arg(required = true)]
    pub programs: Vec<PathBuf>,
    /// Output folder (a subfolder per part when there are several).
    #[arg(long, default_value = "cmm-out")]
    pub out: PathBuf,
    /// Seed of every simulated random draw.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Parts measured in parallel.
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// Switch off every simulated error and all noise.
    #[arg(long)]
    pub ideal: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Random as-machined variants per program (seeds derived from --seed).
    #[arg(long, default_value_t = 1)]
    pub variants: usize,
    /// Run only shard K of N of the parts (`K/N`, 1-based), for CI runners.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Corrections learned across parts: read before, updated after.
    #[arg(long)]
    pub corrections: Option<PathBuf>,
    /// The true part's deviations (an `as_machined` object, the as-machined format)
    /// from this JSON file instead of the programs' own.
    #[arg(long)]
    pub as_machined: Option<PathBuf>,
    /// Write the motion trace of every control cycle to this CSV file
    /// (one part only).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Probe calibration file (cmm-probe-cal/1) from `cmm calibrate-probe`;
    /// overrides the programs' `probe.calibration`.
    #[arg(long)]
    pub probe_cal: Option<PathBuf>,
    /// The machine (URDF); overrides the programs' `machine` (the embedded
    /// bridge CMM when neither is given).
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// The machine profile (cmm-machine-profile/1: dynamics, noise,
    /// geometric error terms); overrides the programs' `machine_profile`.
    #[arg(long)]
    pub machine_profile: Option<PathBuf>,
    /// Measure without correcting the scale readings by the profile's
    /// geometric error terms (the simulated machine keeps its errors):
    /// shows what the compensation is worth.
    #[arg(long)]
    pub no_compensation: bool,
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("'{s}': expected K/N, e.g. 2/4"))?;
    let k: usize = k
        .trim()
        .parse()
        .map_err(|_| format!("'{s}': K is not a number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("'{s}': N is not a number"))?;
    if n == 0 || k == 0 || k > n {
        return Err(format!("'{s}': need 1 <= K <= N"));
    }
    Ok((k, n))
}

/// Most parallel jobs accepted by `--jobs`: far more than any machine has
/// cores, and few enough that starting the threads costs nothing.
pub const MAX_JOBS: usize = 256;

/// Most parts one `cmm scan` accepts (programs times `--variants`), so a
/// mistyped count is refused before the part list is built.
pub const MAX_PARTS: usize = 100_000;

/// Runs `cmm scan`: validates every input first (including that every
/// output can be written), then measures, then writes every output file
/// as one unit.
pub fn run(args: &ScanArgs) -> Result<Status, CliError> {
    check_counts(args)?;
    let files = MachineFiles {
        machine: args.machine.clone(),
        profile: args.machine_profile.clone(),
    };
    let mut programs = args
        .programs
        .iter()
        .map(|p| load_on(p, &files))
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(file) = &args.as_machined {
        crate::app::override_as_machined(&mut programs, file)?;
    }
    let known = match &args.corrections {
        Some(path) => CorrectionsFile::read(path)?,
        None => CorrectionsFile::empty(),
    };
    let parts = plan_parts(
        programs.len(),
        args.variants,
        args.seed,
        args.shard.unwrap_or((1, 1)),
    );
    let base = RunOptions {
        ideal: args.ideal,
        compensation: !args.no_compensation,
        probe_calibration: args
            .probe_cal
            .as_deref()
            .map(ProbeCalibration::read)
            .transpose()?,
        ..RunOptions::default()
    };
    for part in &programs {
        probe_calibration(&part.program, &base)?;
    }
    if args.trace.is_some() && parts.len() != 1 {
        return Err(CliError::Usage(
            "--trace records one part: give one program and no --variants".into(),
        ));
    }
    check_outputs(args)?;
    let mut outputs = OutputSet::default();
    let single = parts.len() == 1;
    let report_dir = |part: &Part| match single {
        true => args.out.clone(),
        false => args.out.join(part_dir(args, part, &programs)),
    };
    let (mut results, updated) = match (&args.trace, parts.first()) {
        (Some(path), Some(part)) => {
            let out = traced_run(&programs, part, &base, &known, (path, &mut outputs))?;
            for (part, result) in parts.iter().zip(&out.0) {
                if let Ok((report, _)) = result {
                    crate::report::add_reports(&mut outputs, &report_dir(part), report);
                }
            }
            out
        }
        _ => {
            let bar = progress_bar(args, parts.len());
            // Each part's reports are written (to temporary names) as it
            // finishes, so the batch holds no report files in memory.
            let staged = std::sync::Mutex::new(OutputSet::default());
            let done = |i: usize, result: &PartResult| {
                bar.inc(1);
                if let (Some(part), Ok((report, _))) = (parts.get(i), result) {
                    // Formatted and written outside the lock: other
                    // workers wait only for the list of files.
                    let mut own = OutputSet::default();
                    crate::report::add_reports(&mut own, &report_dir(part), report);
                    if let Ok(mut set) = staged.lock() {
                        set.absorb(own);
                    }
                }
            };
            let jobs = args.jobs.min(parts.len()).max(1);
            let out = run_batch(&programs, &parts, &base, &known, jobs, &done);
            bar.finish_and_clear();
            outputs.absorb(staged.into_inner().unwrap_or_else(|e| e.into_inner()));
            out
        }
    };
    // One part that could not start: bad input, nothing is written.
    if single && matches!(results.first(), Some(Err(_))) {
        if let Some(Err(e)) = results.pop() {
            return Err(CliError::Run(e));
        }
    }
    if !single {
        super::report_files::add_batch(
            &mut outputs,
            &args.out,
            &batch_rows(args, &parts, &results, &programs),
        );
    }
    if let Some(path) = &args.corrections {
        outputs.add(path, updated.to_json().into_bytes());
    }
    outputs.commit()?;
    // Nobody reading the summary does not change the verdict.
    print_summary(&results).or_else(|e| if e.is_broken_pipe() { Ok(()) } else { Err(e) })?;
    let status = status(&results);
    // The design data (every face's split pieces and indexes) and the
    // reports are left for the process's exit to free: dropping them one
    // allocation at a time takes a measurable share of a short batch.
    std::mem::forget(programs);
    std::mem::forget(results);
    Ok(status)
}

/// `--jobs` and the number of parts within their bounds.
fn check_counts(args: &ScanArgs) -> Result<(), CliError> {
    if args.jobs == 0 || args.jobs > MAX_JOBS {
        return Err(CliError::Value {
            option: "--jobs",
            value: args.jobs.to_string(),
            reason: format!("expected 1 to {MAX_JOBS} parallel jobs"),
        });
    }
    let parts = args.programs.len().saturating_mul(args.variants.max(1));
    if args.variants == 0 || parts > MAX_PARTS {
        return Err(CliError::Value {
            option: "--variants",
            value: args.variants.to_string(),
            reason: format!(
                "expected 1 or more variants, at most {MAX_PARTS} parts in all ({} programs)",
                args.programs.len()
            ),
        });
    }
    Ok(())
}

/// Every file the run will write can be written: checked before measuring.
fn check_outputs(args: &ScanArgs) -> Result<(), CliError> {
    crate::output::check_dir_writable(&args.out)?;
    for path in [&args.corrections, &args.trace].into_iter().flatten() {
        crate::output::check_writable(path, false)?;
    }
    Ok(())
}

/// A bar on stderr when it is a terminal and not `--quiet`; hidden otherwise.
fn progress_bar(args: &ScanArgs, parts: usize) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if args.quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(parts as u64);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} parts {elapsed}")
    {
        bar.set_style(style);
    }
    bar
}

fn traced_run(
    programs: &[SimulatedPart],
    part: &Part,
    base: &RunOptions,
    known: &CorrectionsFile,
    (path, outputs): (&std::path::Path, &mut OutputSet),
) -> Result<(Vec<PartResult>, CorrectionsFile), CliError> {
    let (report, learned, rows) = run_part_traced(programs, part, base, (known, &[]), true)?;
    outputs.add(path, trace_csv(&rows).into_bytes());
    let mut updated = known.clone();
    updated.merge(&report.program, &learned);
    Ok((vec![Ok((report, learned))], updated))
}

fn part_dir(args: &ScanArgs, part: &Part, programs: &[SimulatedPart]) -> String {
    let stem = args
        .programs
        .get(part.program)
        .and_then(|f| f.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .or_else(|| programs.get(part.program).map(|p| p.program.name.clone()))
        .unwrap_or_default();
    format!("{:02}-{stem}-v{:03}", part.program, part.variant)
}

fn batch_rows<'r>(
    args: &ScanArgs,
    parts: &[Part],
    results: &'r [PartResult],
    programs: &[SimulatedPart],
) -> Vec<(String, Option<&'r Report>, String)> {
    parts
        .iter()
        .zip(results)
        .map(|(p, r)| {
            let dir = part_dir(args, p, programs);
            match r {
                Ok((report, _)) => (dir, Some(report), String::new()),
                Err(e) => (dir, None, e.to_string()),
            }
        })
        .collect()
}

/// The summary table on stdout; errors of parts go to stderr.
fn print_summary(results: &[PartResult]) -> Result<(), CliError> {
    let mut lines = vec![format!(
        "{:<20} {:<24} {:>10} {:>7} {:>9} {:>9}  attempts",
        "program", "feature", "status", "points", "min mm", "max mm"
    )];
    for r in results {
        match r {
            Ok((report, _)) => report_lines(report, &mut lines),
            Err(e) => {
                use std::io::Write;
                let _ = writeln!(std::io::stderr(), "cmm: error: {e}");
            }
        }
    }
    super::say(&(lines.join("\n") + "\n"))
}

fn report_lines(r: &Report, lines: &mut Vec<String>) {
    if let Some((a, outcome)) = r.alignment.as_ref().and_then(|a| Some((a, a.failed?))) {
        lines.push(format!(
            "{:<20} {:<24} {:>10} {:>7} {:>9} {:>9}  points:{} (features measured at the nominal placement)",
            r.program,
            "alignment",
            serde_name(&Verdict::Incomplete),
            a.points,
            "-",
            "-",
            serde_name(&outcome)
        ));
    }
    for f in &r.features {
        let attempts: Vec<String> = f
            .attempts
            .iter()
            .map(|a| format!("{}:{}", serde_name(&a.mode), serde_name(&a.outcome)))
            .collect();
        lines.push(format!(
            "{:<20} {:<24} {:>10} {:>7} {:>9.4} {:>9.4}  {}",
            r.program,
            f.name,
            serde_name(&f.status),
            f.points.len(),
            f.deviation_mm.min,
            f.deviation_mm.max,
            attempts.join(" -> ")
        ));
    }
    let end = &r.end_move;
    if end.outcome != Outcome::Completed {
        let at = end.collision.as_ref().map_or(String::new(), |c| {
            let [x, y, z] = c.at_mm;
            format!(" ({} at {x:.3}, {y:.3}, {z:.3} mm)", c.probe_part)
        });
        lines.push(format!(
            "{:<20} {:<24} {:>10} {:>7} {:>9} {:>9}  end move stopped: {}{at}",
            r.program,
            "end move",
            "-",
            "-",
            "-",
            "-",
            serde_name(&end.outcome)
        ));
    }
}

fn status(results: &[PartResult]) -> Status {
    let incomplete = results.iter().any(|r| {
        r.as_ref()
            .map_or(true, |(rep, _)| rep.status == Verdict::Incomplete)
    });
    if incomplete {
        Status::Incomplete
    } else if results
        .iter()
        .any(|r| r.as_ref().is_ok_and(|(rep, _)| rep.status == Verdict::Fail))
    {
        Status::OutOfTolerance
    } else {
        Status::Pass
    }
}
