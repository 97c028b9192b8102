//! The machine's true dynamics: per-axis first-order velocity loops with
//! velocity and acceleration limits, the travel-limit outcome, quantised
//! noisy scale readings, and the probe head's true errors.

mod axis_cycle;
pub mod head_errors;
mod scale;
pub mod servo;

pub use head_errors::HeadErrors;
pub use servo::{AxisDynamics, AxisState, Servo, ServoError};
