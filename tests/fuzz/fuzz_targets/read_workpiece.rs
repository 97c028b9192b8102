//! Fuzz target: the workpiece (cmm-workpiece/1) reader and validation must
//! return `Ok` or `Err` on any bytes, never panic, overflow the stack or
//! hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_workpiece -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = cmm::workpiece::Workpiece::from_path(&common::input_file("workpiece.json", data));
});
