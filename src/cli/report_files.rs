//! The batch summary of a multi-part run, added to the run's output set.
use std::path::Path;

use crate::output::OutputSet;
use crate::report::Report;

/// `batch.json` (one row per part: folder, program, seed, status, times)
/// and `batch-junit.xml` in `dir`, added to `set`.
pub fn add_batch(set: &mut OutputSet, dir: &Path, rows: &[(String, Option<&Report>, String)]) {
    let parts: Vec<serde_json::Value> = rows
        .iter()
        .map(|(folder, report, error)| match report {
            Some(r) => serde_json::json!({ "folder": folder, "program": r.program, "seed": r.seed, "status": r.status,
                                           "machine_time_s": r.machine_time_s, "wall_time_s": r.wall_time_s }),
            None => serde_json::json!({ "folder": folder, "status": "incomplete", "error": error }),
        })
        .collect();
    let doc = serde_json::json!({ "format": "cmm-batch/1", "parts": parts });
    let mut text = serde_json::to_string_pretty(&doc).unwrap_or_default();
    text.push('\n');
    set.add(&dir.join("batch.json"), text.into_bytes());
    let reports: Vec<(String, &Report)> = rows
        .iter()
        .filter_map(|(f, r, _)| r.map(|r| (f.clone(), r)))
        .collect();
    set.add(
        &dir.join("batch-junit.xml"),
        crate::report::junit_batch(&reports).into_bytes(),
    );
}
