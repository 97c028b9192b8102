//! `cmm completions SHELL` and `cmm man`: shell completion scripts and the
//! man page, generated from the same clap definitions that parse the
//! command line.
use clap::CommandFactory;

use super::{emit, Cli, CliError, Status};

/// Arguments of `cmm completions`.
#[derive(Debug, clap::Args)]
pub struct CompletionsArgs {
    /// The shell to write a completion script for.
    pub shell: clap_complete::Shell,
}

/// Arguments of `cmm man`.
#[derive(Debug, clap::Args)]
pub struct ManArgs {}

/// Prints the completion script for `args.shell` on stdout.
pub fn completions(args: &CompletionsArgs) -> Result<Status, CliError> {
    let mut cmd = Cli::command();
    let mut out = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "cmm", &mut out);
    emit(&String::from_utf8_lossy(&out), None)?;
    Ok(Status::Pass)
}

/// Prints the man page (roff) on stdout.
pub fn man(_args: &ManArgs) -> Result<Status, CliError> {
    let mut out = Vec::new();
    // Rendering into memory cannot fail but for a formatter bug; an empty
    // page is then printed rather than a panic.
    let _ = clap_mangen::Man::new(Cli::command()).render(&mut out);
    emit(&String::from_utf8_lossy(&out), None)?;
    Ok(Status::Pass)
}
