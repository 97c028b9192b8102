//! `cmm` command-line entry point: parse, run, map errors to exit codes.
use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    cmm::output::install_interrupt_cleanup();
    let cli = cmm::cli::Cli::parse();
    match cmm::cli::run(cli) {
        Ok(status) => ExitCode::from(status.code()),
        // A closed pipe (`cmm ... | head`): the reader wants no more.
        Err(err) if err.is_broken_pipe() => ExitCode::SUCCESS,
        Err(err) => {
            let code = err.exit_code();
            let _ = writeln!(std::io::stderr(), "cmm: error: {}", message(&err));
            ExitCode::from(code)
        }
    }
}

/// The error and its causes, each cause once: most errors already quote
/// their source in their own message.
fn message(err: &(dyn std::error::Error + 'static)) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(cause) = source {
        let said = cause.to_string();
        if !text.contains(&said) {
            text = format!("{text}: {said}");
        }
        source = cause.source();
    }
    text
}
