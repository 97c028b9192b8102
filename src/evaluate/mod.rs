//! Evaluation: measured points against the design.
//!
//! - [`nominal`]: deviations of measured points from the design (design
//!   data only; the same for a simulated and a real machine).
//! - [`feature`]: a feature's statistics, verdict and fitted element.
//! - [`fitted`]: fitted elements (circle, plane, sphere, cylinder).
//! - [`section_point`]: the design section's point next to a nominal
//!   point (what a section scan's fitted element is compared with).
//! - [`truth`]: after a simulated run, the true deviation of each point
//!   (the only reader of the simulated truth besides the world).
//! - [`evaluate`]: `cmm evaluate`, deviations of points from a CSV.

pub mod feature;
pub mod fitted;
pub mod model;
pub mod nominal;
mod points;
pub mod section_point;
pub mod truth;

pub use points::*;
