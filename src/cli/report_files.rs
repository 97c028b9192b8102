//! Writing a part's report files and a batch summary into a folder.
use std::path::Path;

use super::CliError;
use crate::output::{write_atomic, WriteError};
use crate::report::Report;

fn ensure_dir(dir: &Path) -> Result<(), CliError> {
    std::fs::create_dir_all(dir).map_err(|source| WriteError {
        path: dir.to_path_buf(),
        source,
    })?;
    Ok(())
}

/// `report.json`, `points.csv`, `report.html` and `junit.xml` of one part.
pub fn write_all(dir: &Path, report: &Report) -> Result<(), CliError> {
    Ok(crate::report::write_reports(dir, report)?)
}

/// `batch.json`: one row per part (folder, program, seed, status, times).
pub fn write_batch(dir: &Path, rows: &[(String, Option<Report>, String)]) -> Result<(), CliError> {
    ensure_dir(dir)?;
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
    write_atomic(&dir.join("batch.json"), text.as_bytes())?;
    let reports: Vec<(String, Report)> = rows
        .iter()
        .filter_map(|(f, r, _)| r.clone().map(|r| (f.clone(), r)))
        .collect();
    write_atomic(
        &dir.join("batch-junit.xml"),
        crate::report::junit_batch(&reports).as_bytes(),
    )?;
    Ok(())
}
