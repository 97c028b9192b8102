//! Geometry kernel (placeholder while the kernel is written).
/// Closest-point query failure.
#[derive(Debug, thiserror::Error)]
#[error("projection failed")]
pub struct ProjectionError;
