//! Fuzz target: the point CSV reader must return `Ok` or `Err` on any bytes,
//! never panic, overflow the stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_points_csv -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = cmm::pointfile::read_points_csv(&common::input_file("points.csv", data));
});
