//! Exact conversion of elementary and swept surfaces to NURBS, and their trims.
pub mod analytic;
pub mod arc;
pub mod revolve;
pub mod swept;
pub mod trim;
