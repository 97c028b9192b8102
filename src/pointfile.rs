//! Reading measured points from CSV (DESIGN.md 5): a header line naming
//! `x,y,z` (more columns allowed, in any order), then one point per line.
//!
//! Every error names the file, the 1-based line and the reason.
use std::path::{Path, PathBuf};

use crate::math::Point3;

/// Why a point file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PointsError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file has no header line, or the header lacks a column.
    #[error("{path}:{line}: {reason}")]
    Header {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with the header.
        reason: String,
    },
    /// A data line is malformed.
    #[error("{path}:{line}: {reason}")]
    Row {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with the line.
        reason: String,
    },
    /// The file has a header but no points.
    #[error("{path}: no points after the header")]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// Reads a point CSV file.
pub fn read_points_csv(path: &Path) -> Result<Vec<Point3>, PointsError> {
    let text = std::fs::read_to_string(path).map_err(|source| PointsError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_points_csv(&text, path)
}

/// Parses point CSV text; `path` is used only in messages.
///
/// ```
/// let pts = cmm::pointfile::parse_points_csv("id,x,y,z\n7,1,2,3\n", "p.csv".as_ref()).unwrap();
/// assert_eq!(pts[0], cmm::math::Point3::new(1.0, 2.0, 3.0));
/// ```
pub fn parse_points_csv(text: &str, path: &Path) -> Result<Vec<Point3>, PointsError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = lines.next().ok_or_else(|| PointsError::Header {
        path: path.to_path_buf(),
        line: 1,
        reason: "empty file: expected a header line naming x,y,z".into(),
    })?;
    let columns = header_columns(header, header_line, path)?;
    let width = header.split(',').count();
    let points = lines
        .map(|(line, row)| parse_row(row, line, width, &columns, path))
        .collect::<Result<Vec<_>, _>>()?;
    if points.is_empty() {
        return Err(PointsError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(points)
}

fn header_columns(header: &str, line: usize, path: &Path) -> Result<[usize; 3], PointsError> {
    let names: Vec<String> = header
        .split(',')
        .map(|c| c.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    let find = |want: &str| {
        names
            .iter()
            .position(|n| n == want)
            .ok_or_else(|| PointsError::Header {
                path: path.to_path_buf(),
                line,
                reason: format!("header has no column '{want}' (expected a header naming x,y,z, found '{header}')"),
            })
    };
    Ok([find("x")?, find("y")?, find("z")?])
}

fn parse_row(
    row: &str,
    line: usize,
    width: usize,
    columns: &[usize; 3],
    path: &Path,
) -> Result<Point3, PointsError> {
    let fields: Vec<&str> = row.split(',').map(str::trim).collect();
    let err = |reason: String| PointsError::Row {
        path: path.to_path_buf(),
        line,
        reason,
    };
    if fields.len() != width {
        return Err(err(format!(
            "expected {width} columns like the header, found {}",
            fields.len()
        )));
    }
    let mut xyz = [0.0; 3];
    for (slot, (&col, name)) in xyz.iter_mut().zip(columns.iter().zip(["x", "y", "z"])) {
        let field = fields.get(col).copied().unwrap_or_default();
        let value: f64 = field
            .parse()
            .map_err(|_| err(format!("column '{name}' is not a number: '{field}'")))?;
        if !value.is_finite() {
            return Err(err(format!("column '{name}' is not finite: '{field}'")));
        }
        *slot = value;
    }
    Ok(Point3::new(xyz[0], xyz[1], xyz[2]))
}
