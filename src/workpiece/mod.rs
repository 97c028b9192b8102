//! Workpieces (placeholder).
pub mod format;
/// Workpiece error.
#[derive(Debug, thiserror::Error)]
#[error("workpiece error")]
pub struct WorkpieceError;
