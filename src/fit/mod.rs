//! Geometric element fitting (least squares and minimum zone). Placeholder:
//! filled in by the fitting work (issue 7).

/// Why a fit could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Not implemented yet.
    #[error("fitting is not implemented yet")]
    NotImplemented,
}
