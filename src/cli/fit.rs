//! `cmm fit`: placeholder, filled in by the fitting work (issue 7).
use std::path::PathBuf;

use super::{CliError, Status};

/// Arguments of `cmm fit`.
#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// Element kind.
    #[arg(long)]
    pub element: String,
    /// Point CSV file.
    pub points: PathBuf,
    /// JSON output.
    #[arg(long)]
    pub json: bool,
}

/// Runs `cmm fit`.
pub fn run(_args: &FitArgs) -> Result<Status, CliError> {
    Err(crate::fit::FitError::NotImplemented.into())
}
