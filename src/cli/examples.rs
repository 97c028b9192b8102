//! placeholder
use super::{CliError, Status};
/// Arguments.
#[derive(Debug, clap::Args)]
pub struct ExamplesArgs {}
/// Runs.
pub fn run(_a: &ExamplesArgs) -> Result<Status, CliError> {
    Ok(Status::Pass)
}
