//! The machine model both sides share: kinematics (URDF), axis limits, the
//! machine profile and the formula of the 21 geometric error terms. The
//! world holds the machine's true terms and its dynamics
//! (`world::dynamics`); the host holds its own error map, given to it as an
//! input.
//!
//! - [`MachineModel`]: a serial chain read from URDF (metres, converted to
//!   mm), forward kinematics, axis metadata; [`MachineModel::default_bridge`].
//! - [`MachineProfile`]: what URDF does not describe (control cycle,
//!   acceleration, servo lag, scale resolution and noise, geometric errors),
//!   JSON with embedded defaults; [`MachineProfile::ideal`] for `--ideal`.

pub mod builtin;
mod chain;
mod error;
pub mod geometric;
mod kinematics;
mod linear;
mod model;
pub mod profile;
mod profile_check;
pub mod urdf;

pub use error::MachineError;
pub use geometric::{ErrorPolynomial, GeometricErrors, LinearAxisErrors, Squareness, Stacking};
pub use linear::LinearAxes;
pub use model::{Axis, AxisKind, AxisLimits, MachineModel};
pub use profile::{LinearAxesProfile, MachineProfile, ProfileError, RotaryAxesProfile};
