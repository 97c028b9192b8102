//! # cmm — dimensional metrology on a simulated coordinate measuring machine
//!
//! Data flows one way:
//!
//! ```text
//! part program + workpiece
//!   -> plan      (sections, ball-centre paths, speeds)           geometry, host
//!   -> inspect   (supervisor driving measuring modes on a Machine) host <-> world
//!   -> measured points
//!   -> evaluate  (deviations, fits, tolerances)                  evaluate, fit
//!   -> report writers
//! ```
//!
//! The simulated world (the as-machined part, the machine, the probe physics)
//! and the measuring software (the host) are separate: the host sees only the
//! design data, the part program and per-cycle machine readings.
//!
//! Units: `f64` millimetres everywhere (see [`math`]).

pub mod app;
pub mod cad;
pub mod cli;
pub mod evaluate;
pub mod fit;
pub mod formats;
pub mod geometry;
pub mod host;
pub mod jsonfile;
pub mod machine;
pub mod math;
pub mod output;
pub mod pointfile;
pub mod program;
pub mod report;
pub mod seam;
pub mod workpiece;
pub mod world;
