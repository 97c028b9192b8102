//! The world-side machine: true kinematics (URDF), dynamics (servo loop),
//! scales and the 21 geometric error terms.
//!
//! - [`MachineModel`]: a serial chain read from URDF (metres, converted to
//!   mm), forward kinematics, axis metadata; [`MachineModel::default_bridge`].
//! - [`MachineProfile`]: what URDF does not describe (control cycle,
//!   acceleration, servo lag, scale resolution and noise, geometric errors),
//!   JSON with embedded defaults; [`MachineProfile::ideal`] for `--ideal`.
//! - [`Servo`]: per-axis first-order velocity loop with velocity and
//!   acceleration limits, travel-limit outcome, quantised noisy scale readings.

mod axis_cycle;
pub mod builtin;
mod chain;
mod error;
pub mod geometric;
pub mod head_errors;
mod kinematics;
mod linear;
mod model;
pub mod profile;
mod profile_check;
mod scale;
pub mod servo;
pub mod urdf;

pub use error::MachineError;
pub use geometric::{ErrorPolynomial, GeometricErrors, LinearAxisErrors, Squareness, Stacking};
pub use head_errors::HeadErrors;
pub use linear::LinearAxes;
pub use model::{Axis, AxisKind, AxisLimits, MachineModel};
pub use profile::{LinearAxesProfile, MachineProfile, ProfileError, RotaryAxesProfile};
pub use servo::{AxisDynamics, AxisState, Servo, ServoError};
