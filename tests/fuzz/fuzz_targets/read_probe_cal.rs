//! Fuzz target: the probe calibration (cmm-probe-cal/1) and probe description
//! readers must return `Ok` or `Err` on any bytes, never panic, overflow the
//! stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none read_probe_cal -- -max_total_time=60`
#![no_main]

#[path = "../common/mod.rs"]
mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = common::input_file("probe-cal.json", data);
    let _ = cmm::calibrate::file::ProbeCalibration::read(&path);
    let _ = cmm::calibrate::probe_file::read_probe_file(&path);
});
