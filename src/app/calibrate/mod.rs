//! Probe qualification on a simulated reference sphere: the world (the
//! sphere, the machine, the true probe) wired to the host's calibration.

pub mod simulate;
pub mod simulate_head;
