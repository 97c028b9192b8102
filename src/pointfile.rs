//! Reading measured points from CSV (the command-line interface): a header line naming
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

/// Most points read from one file (10 million, about 400 MB of CSV): a
/// bound so that a wrong file is refused before it fills the memory.
pub const MAX_POINTS: usize = 10_000_000;

/// Field separators recognised, in order of preference: the one that
/// splits the header into columns naming x, y and z is used.
pub const SEPARATORS: [u8; 3] = [b',', b';', b'\t'];

/// Reads a point CSV file.
pub fn read_points_csv(path: &Path) -> Result<Vec<Point3>, PointsError> {
    let text = crate::jsonfile::read_text(path).map_err(|source| PointsError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_points_csv(&text, path)
}

/// Parses point CSV text; `path` is used only in messages.
///
/// The file is read as CMM software writes it: an optional UTF-8 byte
/// order mark, `#` comment lines and blank lines anywhere, a header naming
/// `x`, `y` and `z` in any case and order (more columns allowed), fields
/// separated by `,`, `;` or tabs and optionally quoted; with `;` or tab
/// separators a decimal comma (`1,5`) is accepted.
///
/// ```
/// let pts = cmm::pointfile::parse_points_csv("id,x,y,z\n7,1,2,3\n", "p.csv".as_ref()).unwrap();
/// assert_eq!(pts[0], cmm::math::Point3::new(1.0, 2.0, 3.0));
/// let pts = cmm::pointfile::parse_points_csv("\u{feff}# probe 1\n\"X\";\"Y\";\"Z\"\n1,5;2;3\n", "p.csv".as_ref()).unwrap();
/// assert_eq!(pts[0], cmm::math::Point3::new(1.5, 2.0, 3.0));
/// ```
pub fn parse_points_csv(text: &str, path: &Path) -> Result<Vec<Point3>, PointsError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let (header_line, header) = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .find(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .ok_or_else(|| PointsError::Header {
            path: path.to_path_buf(),
            line: 1,
            reason: "empty file: expected a header line naming x,y,z".into(),
        })?;
    let (separator, columns) = header_columns(header, header_line, path)?;
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(separator)
        .comment(Some(b'#'))
        .flexible(true)
        .trim(csv::Trim::All)
        .has_headers(true)
        .from_reader(text.as_bytes());
    let width = reader
        .headers()
        .map_err(|e| csv_error(e, header_line, path))?
        .len();
    let mut points = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        let line = reader.position().line() as usize;
        match reader.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => return Err(csv_error(e, line, path)),
        }
        let line = record.position().map_or(line, |p| p.line() as usize);
        if record.iter().all(str::is_empty) {
            continue;
        }
        if points.len() == MAX_POINTS {
            return Err(PointsError::Row {
                path: path.to_path_buf(),
                line,
                reason: format!("more than {MAX_POINTS} points: not a point file?"),
            });
        }
        let row = Row {
            line,
            width,
            separator,
        };
        points.push(row.point(&record, &columns, path)?);
    }
    if points.is_empty() {
        return Err(PointsError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(points)
}

fn csv_error(e: csv::Error, line: usize, path: &Path) -> PointsError {
    let line = e.position().map_or(line, |p| p.line() as usize);
    let reason = match e.kind() {
        csv::ErrorKind::Utf8 { err, .. } => format!("invalid UTF-8 in field {}", err.field() + 1),
        _ => e.to_string(),
    };
    PointsError::Row {
        path: path.to_path_buf(),
        line,
        reason,
    }
}

/// Lower-case header names split at `separator`, quotes removed.
fn header_names(header: &str, separator: u8) -> Vec<String> {
    header
        .split(char::from(separator))
        .map(|c| c.trim().trim_matches('"').trim().to_ascii_lowercase())
        .collect()
}

/// The separator and the columns of x, y and z.
fn header_columns(header: &str, line: usize, path: &Path) -> Result<(u8, [usize; 3]), PointsError> {
    let find = |names: &[String]| -> Option<[usize; 3]> {
        let at = |want: &str| names.iter().position(|n| n == want);
        Some([at("x")?, at("y")?, at("z")?])
    };
    for separator in SEPARATORS {
        if let Some(columns) = find(&header_names(header, separator)) {
            return Ok((separator, columns));
        }
    }
    let names = header_names(header, b',');
    let missing: Vec<&str> = ["x", "y", "z"]
        .into_iter()
        .filter(|w| !names.iter().any(|n| n == w))
        .collect();
    Err(PointsError::Header {
        path: path.to_path_buf(),
        line,
        reason: format!(
            "header has no column '{}' (expected a header naming x,y,z separated by ',', ';' or tabs, found '{header}')",
            missing.join("', '")
        ),
    })
}

/// Where a data record is and how it must look.
struct Row {
    line: usize,
    width: usize,
    separator: u8,
}

impl Row {
    fn point(
        &self,
        fields: &csv::StringRecord,
        columns: &[usize; 3],
        path: &Path,
    ) -> Result<Point3, PointsError> {
        let err = |reason: String| PointsError::Row {
            path: path.to_path_buf(),
            line: self.line,
            reason,
        };
        if fields.len() != self.width {
            return Err(err(format!(
                "expected {} columns like the header, found {}",
                self.width,
                fields.len()
            )));
        }
        let mut xyz = [0.0; 3];
        for (slot, (&col, name)) in xyz.iter_mut().zip(columns.iter().zip(["x", "y", "z"])) {
            let field = fields.get(col).unwrap_or_default();
            let value = self
                .number(field)
                .ok_or_else(|| err(format!("column '{name}' is not a number: '{field}'")))?;
            if !value.is_finite() {
                return Err(err(format!("column '{name}' is not finite: '{field}'")));
            }
            *slot = value;
        }
        Ok(Point3::new(xyz[0], xyz[1], xyz[2]))
    }

    /// A number; with `;` or tab separators also with a decimal comma.
    fn number(&self, field: &str) -> Option<f64> {
        field.parse().ok().or_else(|| {
            (self.separator != b',' && field.matches(',').count() == 1)
                .then(|| field.replace(',', ".").parse().ok())
                .flatten()
        })
    }
}
