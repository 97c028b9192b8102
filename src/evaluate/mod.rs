//! Evaluation: measured points against the design.
//!
//! - [`nominal`]: deviations of measured points from the design (design
//!   data only; the same for a simulated and a real machine).
//! - [`feature`]: a feature's statistics, verdict and fitted element.
//! - [`fitted`]: fitted elements (circle, plane, sphere, cylinder).
//! - [`truth`]: after a simulated run, the true deviation of each point
//!   (the only reader of the simulated truth besides the world).
//! - [`evaluate`]: `cmm evaluate`, deviations of points from a CSV.

pub mod feature;
pub mod fitted;
pub mod model;
pub mod nominal;
mod points;
pub mod truth;

pub use points::*;
