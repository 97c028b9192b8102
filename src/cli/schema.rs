//! `cmm schema workpiece|program`: JSON Schemas generated from the types.
use super::{CliError, Status};

/// Which format.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum SchemaKind {
    /// `cmm-workpiece/1`.
    Workpiece,
    /// `cmm-program/1`.
    Program,
}

/// Arguments of `cmm schema`.
#[derive(Debug, clap::Args)]
pub struct SchemaArgs {
    /// The format.
    pub kind: SchemaKind,
}

/// Runs `cmm schema`.
pub fn run(args: &SchemaArgs) -> Result<Status, CliError> {
    let schema = match args.kind {
        SchemaKind::Workpiece => schemars::schema_for!(crate::workpiece::WorkpieceFile),
        SchemaKind::Program => schemars::schema_for!(crate::program::ProgramFile),
    };
    let text = serde_json::to_string_pretty(&schema).unwrap_or_default();
    super::say(&format!("{text}\n"))?;
    Ok(Status::Pass)
}
