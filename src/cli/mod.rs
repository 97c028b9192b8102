//! Command-line interface: one file per subcommand. clap types live here and
//! nowhere else; each subcommand turns its arguments into library calls.
use clap::{Parser, Subcommand};

use crate::output::WriteError;
use crate::pointfile::PointsError;

mod calibrate;
mod calibrate_head;
mod check;
mod completions;
mod evaluate;
mod examples;
mod fit;
mod import;
mod report_files;
mod scan;
mod schema;

/// Dimensional metrology on a simulated CMM: design-value scanning with
/// automatic error correction, deviation evaluation and element fitting.
#[derive(Debug, Parser)]
#[command(name = "cmm", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Calibrate the simulated probe on a reference sphere (cmm-probe-cal/1).
    CalibrateProbe(calibrate::CalibrateArgs),
    /// Validate part programs and their workpieces without measuring.
    Check(check::CheckArgs),
    /// Deviation of measured points from the nominal CAD surfaces.
    Evaluate(evaluate::EvaluateArgs),
    /// Fit a geometric element (line, plane, circle, sphere, cylinder, cone) to points.
    Fit(fit::FitArgs),
    /// Convert a STEP/IGES part into a cmm-workpiece/1 file.
    Import(import::ImportArgs),
    /// Run part programs on the simulated CMM and write deviation reports.
    Scan(scan::ScanArgs),
    /// Print the JSON Schema of a file format.
    Schema(schema::SchemaArgs),
    /// Print a shell completion script (bash, zsh, fish, powershell, elvish).
    Completions(completions::CompletionsArgs),
    /// Print the man page (roff).
    Man(completions::ManArgs),
    /// Regenerate the example workpieces shipped in `workpieces/`.
    #[command(hide = true)]
    ExampleWorkpieces(examples::ExamplesArgs),
}

/// How a successful run ended; maps to the exit codes of the command-line interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Everything measured and in tolerance (exit 0).
    Pass,
    /// Something out of tolerance (exit 1).
    OutOfTolerance,
    /// A measurement could not be completed even after all fallbacks (exit 3).
    Incomplete,
}

impl Status {
    /// The process exit code for this status.
    pub fn code(self) -> u8 {
        match self {
            Status::Pass => 0,
            Status::OutOfTolerance => 1,
            Status::Incomplete => 3,
        }
    }
}

/// Every way a command can fail before producing its result; all of them are
/// bad usage or bad input (exit 2) and leave no output behind.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A workpiece file is invalid.
    #[error(transparent)]
    Workpiece(#[from] crate::workpiece::WorkpieceError),
    /// A CAD file could not be imported.
    #[error(transparent)]
    Cad(#[from] crate::cad::CadError),
    /// A part program is invalid.
    #[error(transparent)]
    Program(#[from] crate::program::ProgramError),
    /// A point file is invalid.
    #[error(transparent)]
    Points(#[from] PointsError),
    /// Fitting failed (degenerate input, no convergence).
    #[error(transparent)]
    Fit(#[from] crate::fit::FitError),
    /// A closest-point query failed.
    #[error(transparent)]
    Projection(#[from] crate::geometry::ProjectionError),
    /// A corrections file is invalid.
    #[error(transparent)]
    Corrections(#[from] crate::host::inspect::learned::CorrectionsError),
    /// A run could not start.
    #[error(transparent)]
    Run(#[from] crate::app::RunError),
    /// The probe calibration failed (or its machine could not be set up).
    #[error(transparent)]
    Calibrate(#[from] crate::app::calibrate::simulate::SimulatedCalError),
    /// A probe description file (`calibrate-probe --probe`) is invalid.
    #[error(transparent)]
    ProbeFile(#[from] crate::host::calibrate::probe_file::ProbeFileError),
    /// A probe calibration file is invalid.
    #[error(transparent)]
    ProbeCal(#[from] crate::host::calibrate::file::ProbeCalError),
    /// A machine description is invalid.
    #[error(transparent)]
    Machine(#[from] crate::machine::MachineError),
    /// A machine profile is invalid.
    #[error(transparent)]
    Profile(#[from] crate::machine::ProfileError),
    /// An output file could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// Standard output could not be written.
    #[error("cannot write to standard output: {0}")]
    Stdout(#[source] std::io::Error),
    /// Arguments that do not go together.
    #[error("{0}")]
    Usage(String),
    /// A command-line value out of its meaningful range.
    #[error("{option} {value}: {reason}")]
    Value {
        /// The option (`--sphere-diameter`).
        option: &'static str,
        /// The value given.
        value: String,
        /// What is wrong and what is accepted.
        reason: String,
    },
    /// The simulated probe calibration failed on the given machine.
    #[error("{machine}: {source}")]
    Calibration {
        /// The machine (URDF file and profile, or the built-in one) and
        /// the probe that were calibrated.
        machine: String,
        /// Why it failed.
        source: Box<crate::app::calibrate::simulate::SimulatedCalError>,
    },
    /// A point file could not be fitted.
    #[error("{file}: {source}")]
    FitPoints {
        /// The point file.
        file: std::path::PathBuf,
        /// Why the fit failed.
        source: crate::fit::FitError,
    },
}

impl CliError {
    /// Exit code: 2 for bad usage or bad input (the command-line interface).
    pub fn exit_code(&self) -> u8 {
        2
    }

    /// Standard output was closed by its reader (`cmm ... | head`): not an
    /// error for the user, the program ends quietly.
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, CliError::Stdout(e) if e.kind() == std::io::ErrorKind::BrokenPipe)
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<Status, CliError> {
    match cli.command {
        Command::CalibrateProbe(args) => calibrate::run(&args),
        Command::Check(args) => check::run(&args),
        Command::Evaluate(args) => evaluate::run(&args),
        Command::Fit(args) => fit::run(&args),
        Command::Import(args) => import::run(&args),
        Command::Scan(args) => scan::run(&args),
        Command::Schema(args) => schema::run(&args),
        Command::Completions(args) => completions::completions(&args),
        Command::Man(args) => completions::man(&args),
        Command::ExampleWorkpieces(args) => examples::run(&args),
    }
}

/// Writes `text` to `out` atomically, or to stdout when `out` is `None`.
fn emit(text: &str, out: Option<&std::path::Path>) -> Result<(), CliError> {
    match out {
        Some(path) => Ok(crate::output::write_atomic(path, text.as_bytes())?),
        None => say(text),
    }
}

/// Writes `text` to standard output (no panic on a closed pipe: the error
/// is returned, and [`CliError::is_broken_pipe`] tells it apart).
pub(crate) fn say(text: &str) -> Result<(), CliError> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(CliError::Stdout)
}
