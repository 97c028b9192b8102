//! The host: the measuring software.
//!
//! The host plans and drives measurements the way a real CMM's software
//! would. It sees only the design data, the part program and what the
//! machine reports every control cycle (scale readings, probe deflection
//! readings, status); it never reads the simulated truth (the as-machined
//! part, the machine's true kinematics, the probe's true physics).
//!
//! - [`path`]: ball-centre paths from nominal section points (offset by
//!   `r - Ep`, parametric cubic curve segments) and speed planning on the
//!   control cycle (JP6484108B2, active-scanning speed planning and multi-axis timing).
//! - [`probe_correction`]: condition-dependent correction of the probe's
//!   deflection readings from a calibration (condition-dependent probe correction).
//! - [`compensation`]: the machine's geometric error map applied at the
//!   stylus tip through the probe vector, and its iterative inverse (seed
//!   003).
//! - [`compensated`]: a machine seen through that map (the corrected
//!   scale readings every mode measures and steers with).
//! - [`head`]: the nominal probe-head model (URDF) giving a probe vector per
//!   head orientation.

pub mod calibrate;
pub mod compensated;
pub mod compensation;
pub mod head;
pub mod inspect;
pub mod modes;
pub mod observe;
pub mod path;
pub mod probe_correction;
pub mod trace;
