//! Fuzz target: the STEP tokenizer, parser and reference checks must return
//! `Ok` or `Err` on any bytes, never panic, overflow the stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none parse_step -- -max_total_time=120`
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = cmm::cad::parse_step_str(&text);
});
