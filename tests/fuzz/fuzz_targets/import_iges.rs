//! Fuzz target: the IGES reader (records, Global section, directory,
//! parameters, B-rep topology, subfigures, surfaces and trims) must return
//! `Ok` or `Err` on any bytes, never panic, overflow the stack or hang.
//!
//! Run: `cargo fuzz run --fuzz-dir tests/fuzz -s none import_iges -- -max_total_time=120`
//! (seed corpus: any .igs/.iges files copied into the corpus directory).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let opts = cmm::cad::ImportOptions::default();
    let _ = cmm::cad::iges::import_iges(&text, "fuzz.igs", "fuzz", &opts);
});
