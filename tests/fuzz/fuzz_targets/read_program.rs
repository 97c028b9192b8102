//! Fuzz target: the part program (cmm-program/1) reader, with its workpiece
//! and every check must return `Ok` or `Err` on any bytes, never panic,
//! overflow the stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_program -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = cmm::program::load(&common::input_file("program.json", data));
});
