//! `cmm` command-line entry point: parse, run, map errors to exit codes.
use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = cmm::cli::Cli::parse();
    match cmm::cli::run(cli) {
        Ok(status) => ExitCode::from(status.code()),
        Err(err) => {
            let code = err.exit_code();
            eprintln!("cmm: error: {:#}", anyhow::Error::new(err));
            ExitCode::from(code)
        }
    }
}
