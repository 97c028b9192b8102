//! Fuzz target: the URDF machine description reader (raw XML checks, urdf-rs,
//! kinematic chain) must return `Ok` or `Err` on any bytes, never panic,
//! overflow the stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_urdf -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ =
        cmm::machine::MachineModel::from_urdf_file(common::input_file("machine.urdf", data));
});
