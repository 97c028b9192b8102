//! Fuzz target: the machine profile (cmm-machine-profile/1) reader and range
//! checks must return `Ok` or `Err` on any bytes, never panic, overflow the
//! stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_profile -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = cmm::machine::MachineProfile::from_json_file(common::input_file(
        "profile.json",
        data,
    ));
});
