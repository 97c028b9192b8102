//! Writing all report files of one part into an output directory.

use std::path::Path;

use super::model::Report;
use super::{csv, html, json, junit};
use crate::output::{OutputSet, WriteError};

/// File names written by [`write_reports`], in writing order.
pub const REPORT_FILES: [&str; 4] = ["report.json", "points.csv", "report.html", "junit.xml"];

/// Writes `report.json`, `points.csv`, `report.html` and `junit.xml` into
/// `dir` (created with its parents if missing) as one unit: all four files
/// are written to temporary files first and renamed only when all are on
/// disk, so on error none of them is left behind.
pub fn write_reports(dir: &Path, report: &Report) -> Result<(), WriteError> {
    let mut set = OutputSet::default();
    add_reports(&mut set, dir, report);
    set.commit()
}

/// Adds the four report files of `report` in `dir` to an output set.
pub fn add_reports(set: &mut OutputSet, dir: &Path, report: &Report) {
    let mut points = csv::PointsCsv::new(report);
    let json = json::to_json_bytes_and_csv(report, &mut points);
    let contents = [
        json,
        points.into_bytes(),
        html::report_html_bytes(report),
        junit::junit_xml(report).into_bytes(),
    ];
    for (name, bytes) in REPORT_FILES.iter().zip(contents) {
        set.add(&dir.join(name), bytes);
    }
}
