//! Workpieces (placeholder).
/// Workpiece error.
#[derive(Debug, thiserror::Error)]
#[error("workpiece error")]
pub struct WorkpieceError;
