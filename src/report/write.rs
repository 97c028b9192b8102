//! Writing all report files of one part into an output directory.

use std::path::Path;

use super::model::Report;
use super::{csv, html, json, junit};
use crate::output::{write_atomic, WriteError};

/// File names written by [`write_reports`], in writing order.
pub const REPORT_FILES: [&str; 4] = ["report.json", "points.csv", "report.html", "junit.xml"];

/// Writes `report.json`, `points.csv`, `report.html` and `junit.xml` into
/// `dir` (created with its parents if missing). Each file is written to a
/// temporary file and renamed, so none is ever left half written; on error
/// the files written before it remain.
pub fn write_reports(dir: &Path, report: &Report) -> Result<(), WriteError> {
    std::fs::create_dir_all(dir).map_err(|source| WriteError {
        path: dir.to_path_buf(),
        source,
    })?;
    let contents = [
        json::to_json(report),
        csv::points_csv(report),
        html::report_html(report),
        junit::junit_xml(report),
    ];
    for (name, text) in REPORT_FILES.iter().zip(contents) {
        write_atomic(&dir.join(name), text.as_bytes())?;
    }
    Ok(())
}
