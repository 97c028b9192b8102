//! Reading JSON input files with exact locations: every syntax or type
//! error names the file, the line and column, and the JSON path
//! (`$.surfaces[2].knots_u[4]`) of the offending value.
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

/// A JSON file that is not valid JSON or does not have the expected shape
/// (unknown key, wrong type, missing field).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: {json_path}: {reason}")]
pub struct JsonSyntaxError {
    /// The file.
    pub file: PathBuf,
    /// JSON path of the offending value.
    pub json_path: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong.
    pub reason: String,
}

/// Parses `text` (the content of `file`) into `T`.
///
/// ```
/// let err = cmm::jsonfile::parse_json::<Vec<u8>>("[1, -2]", "f.json".as_ref()).unwrap_err();
/// assert_eq!(err.json_path, "$[1]");
/// ```
pub fn parse_json<T: DeserializeOwned>(text: &str, file: &Path) -> Result<T, JsonSyntaxError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|err| {
        let json_path = json_path(&err.path().to_string());
        let inner = err.into_inner();
        JsonSyntaxError {
            file: file.to_path_buf(),
            json_path,
            line: inner.line(),
            column: inner.column(),
            reason: strip_position(&inner.to_string()),
        }
    })
}

/// `surfaces[0].degree` -> `$.surfaces[0].degree`; `.` -> `$`.
pub fn json_path(raw: &str) -> String {
    match raw {
        "" | "." => "$".into(),
        p if p.starts_with('[') => format!("${p}"),
        p => format!("$.{p}"),
    }
}

/// serde_json appends " at line L column C"; the position is reported apart.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}
