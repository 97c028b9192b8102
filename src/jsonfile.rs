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
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|err| {
        let json_path = json_path(&err.path().to_string());
        let inner = err.into_inner();
        JsonSyntaxError {
            file: file.to_path_buf(),
            json_path,
            line: inner.line(),
            column: inner.column(),
            reason: strip_position(&inner.to_string()),
        }
    })?;
    // Anything but white space after the value (a second object, a stray
    // brace) is not the file's JSON.
    de.end().map_err(|inner| JsonSyntaxError {
        file: file.to_path_buf(),
        json_path: "$".into(),
        line: inner.line(),
        column: inner.column(),
        reason: strip_position(&inner.to_string()),
    })?;
    Ok(value)
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

/// Largest input file read, bytes (512 MiB): beyond any real workpiece,
/// program or point file, so a wrong path (a disk image, a log) is refused
/// before it is loaded into memory.
pub const MAX_INPUT_BYTES: u64 = 512 * 1024 * 1024;

/// Reads a UTF-8 text input file. Unlike [`std::fs::read_to_string`], a
/// folder, a FIFO or a device is refused before it is opened (a FIFO would
/// block), a file larger than [`MAX_INPUT_BYTES`] is refused, and invalid
/// UTF-8 is reported with its line and column. A UTF-8 byte order mark is
/// dropped.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    let meta = std::fs::metadata(path)?;
    if let Some(problem) = not_a_regular_file(&meta) {
        return Err(std::io::Error::other(problem));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(std::io::Error::other(format!(
            "file is {} bytes, larger than the {MAX_INPUT_BYTES} bytes accepted",
            meta.len()
        )));
    }
    let bytes = std::fs::read(path)?;
    text_from_bytes(bytes)
}

/// UTF-8 text from bytes, the error naming the line and column of the
/// first invalid byte; a leading byte order mark is dropped.
pub fn text_from_bytes(mut bytes: Vec<u8>) -> std::io::Result<String> {
    if bytes.starts_with(b"\xEF\xBB\xBF") {
        bytes.drain(..3);
    }
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let before = bytes.get(..at).unwrap_or_default();
        let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        let column = 1 + String::from_utf8_lossy(before.get(line_start..).unwrap_or_default())
            .chars()
            .count();
        let byte = bytes.get(at).copied().unwrap_or_default();
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("line {line}, column {column}: invalid UTF-8 (byte 0x{byte:02X}); the file must be UTF-8 text"),
        )
    })
}

/// What a file system entry is, for messages ("a folder", "a FIFO").
pub fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a folder";
    }
    if t.is_symlink() {
        return "a symbolic link";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
    }
    if t.is_file() {
        "a file"
    } else {
        "not a regular file"
    }
}

fn not_a_regular_file(meta: &std::fs::Metadata) -> Option<String> {
    (!meta.is_file()).then(|| format!("is {}, expected a regular file", kind_of(meta)))
}

/// Why `path` cannot be read as an input file (`None` if it is a regular
/// file): "does not exist", "is a folder, expected a regular file", ...
pub fn file_problem(path: &Path) -> Option<String> {
    match std::fs::metadata(path) {
        Ok(meta) => not_a_regular_file(&meta),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Some("does not exist".into()),
        Err(e) => Some(format!("cannot be read: {e}")),
    }
}
