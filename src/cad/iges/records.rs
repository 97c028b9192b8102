//! IGES 5.3 fixed-format file structure: 80-column records in the S, G, D,
//! P and T sections, the Global section and the Directory-entry pairs.
use super::params::{tokenize, Token, Tokens};
use crate::cad::error::{CadError, CadResult};

/// Width of the data field of S, G and D records.
const DATA_COLS: usize = 72;
/// Width of the parameter field of P records.
const PARAM_COLS: usize = 64;

/// One physical record: its data field and the physical line number.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// 1-based line number in the file.
    pub number: usize,
    /// The data columns (1..=72, or 1..=64 for P records).
    pub data: String,
}

/// The sections of an IGES file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sections {
    /// Global section records.
    pub global: Vec<Line>,
    /// Directory-entry records.
    pub directory: Vec<Line>,
    /// Parameter-data records.
    pub parameters: Vec<Line>,
}

/// A syntax error at a line and column.
pub fn syntax(file: &str, line: usize, column: usize, reason: impl Into<String>) -> CadError {
    CadError::Syntax {
        file: file.to_string(),
        line,
        column,
        reason: reason.into(),
    }
}

/// Splits the text into sections by the letter in column 73.
pub fn split_sections(text: &str, file: &str) -> CadResult<Sections> {
    let mut s = Sections::default();
    for (k, raw) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let (letter, line) = record(raw, k + 1, file)?;
        match letter {
            'G' => s.global.push(line),
            'D' => s.directory.push(line),
            'P' => s.parameters.push(line),
            _ => {}
        }
    }
    if s.directory.is_empty() {
        let last = text.lines().count().max(1);
        return Err(syntax(
            file,
            last,
            1,
            "no Directory Entry section (truncated file?)",
        ));
    }
    Ok(s)
}

/// The section letter and data field of one physical line.
fn record(raw: &str, number: usize, file: &str) -> CadResult<(char, Line)> {
    let chars: Vec<char> = raw.trim_end_matches(['\r', '\n']).chars().collect();
    let short = || {
        syntax(
            file,
            number,
            chars.len() + 1,
            "record shorter than 73 columns (no section letter)",
        )
    };
    let letter = chars.get(DATA_COLS).copied().ok_or_else(short)?;
    let bad = |reason: String| Err(syntax(file, number, DATA_COLS + 1, reason));
    match letter {
        'S' | 'G' | 'D' | 'P' | 'T' => {}
        'C' => return bad("compressed IGES is not supported".into()),
        other => return bad(format!("unknown section letter {other:?}")),
    }
    let width = if letter == 'P' { PARAM_COLS } else { DATA_COLS };
    Ok((
        letter,
        Line {
            number,
            data: chars.iter().take(width).collect(),
        },
    ))
}

/// Delimiters and units from the Global section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Global {
    /// Parameter delimiter (default `,`).
    pub param: char,
    /// Record delimiter (default `;`).
    pub record: char,
    /// Millimetres per model unit.
    pub unit_mm: f64,
}

/// Parses the Global section.
pub fn global(lines: &[Line], file: &str) -> CadResult<Global> {
    let text: String = lines.iter().map(|l| l.data.as_str()).collect();
    let first = lines.first().map_or(1, |l| l.number);
    let (param, rest) =
        delimiter(&text, ',').ok_or_else(|| syntax(file, first, 1, "bad parameter delimiter"))?;
    let rest = rest.strip_prefix(param).unwrap_or(rest);
    let (record, _) =
        delimiter(rest, ';').ok_or_else(|| syntax(file, first, 1, "bad record delimiter"))?;
    let toks = tokenize(lines, param, record, file)?;
    let unit_mm = units(&toks, file, first)?;
    Ok(Global {
        param,
        record,
        unit_mm,
    })
}

/// A leading `1Hx` delimiter definition or the default when the field is empty.
fn delimiter(text: &str, default: char) -> Option<(char, &str)> {
    if let Some(rest) = text.strip_prefix("1H") {
        let c = rest.chars().next()?;
        return Some((c, rest.get(c.len_utf8()..)?));
    }
    Some((default, text))
}

fn units(toks: &Tokens, file: &str, line: usize) -> CadResult<f64> {
    let flag = toks.items.get(13).and_then(Token::as_int);
    let name = toks
        .items
        .get(14)
        .and_then(Token::as_str)
        .unwrap_or("")
        .trim()
        .to_ascii_uppercase();
    let by_flag = flag.and_then(unit_by_flag);
    let by_name = unit_by_name(&name);
    by_flag.or(by_name).ok_or_else(|| CadError::MissingUnits {
        file: file.to_string(),
        line,
        column: 1,
        reason: format!("Global section unit flag {flag:?} / name {name:?} not understood"),
    })
}

fn unit_by_flag(flag: i64) -> Option<f64> {
    Some(match flag {
        1 => 25.4,
        2 => 1.0,
        4 => 304.8,
        5 => 1_609_344.0,
        6 => 1000.0,
        7 => 1_000_000.0,
        8 => 0.0254,
        9 => 0.001,
        10 => 10.0,
        11 => 0.0000254,
        _ => return None,
    })
}

fn unit_by_name(name: &str) -> Option<f64> {
    Some(match name {
        "IN" | "INCH" => 25.4,
        "MM" => 1.0,
        "FT" => 304.8,
        "MI" => 1_609_344.0,
        "M" => 1000.0,
        "KM" => 1_000_000.0,
        "MIL" => 0.0254,
        "UM" => 0.001,
        "CM" => 10.0,
        "UIN" => 0.0000254,
        _ => return None,
    })
}

/// One Directory entry (two D records).
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Sequence number of the first D record (the DE pointer).
    pub seq: u64,
    /// Physical line of the first D record.
    pub line: usize,
    /// Entity type number.
    pub kind: i64,
    /// First P sequence number.
    pub param_start: usize,
    /// Number of P records.
    pub param_count: usize,
    /// DE pointer of a 124 transformation matrix (0 = none).
    pub transform: u64,
    /// Form number.
    pub form: i64,
    /// Status digits `bbssuuhh`.
    pub status: String,
    /// Entity label.
    pub label: String,
}

/// Parses the Directory entries (pairs of D records).
pub fn directory(lines: &[Line], file: &str) -> CadResult<Vec<Entry>> {
    if !lines.len().is_multiple_of(2) {
        let last = lines.last().map_or(1, |l| l.number);
        return Err(syntax(
            file,
            last,
            1,
            "odd number of Directory Entry records (truncated entry)",
        ));
    }
    lines
        .chunks(2)
        .enumerate()
        .map(|(k, pair)| entry(k, pair, file))
        .collect()
}

fn entry(k: usize, pair: &[Line], file: &str) -> CadResult<Entry> {
    let (Some(a), Some(b)) = (pair.first(), pair.get(1)) else {
        return Err(syntax(file, 1, 1, "missing Directory Entry record"));
    };
    let int = |l: &Line, field: usize| -> CadResult<i64> {
        let text = field_text(l, field);
        if text.is_empty() {
            return Ok(0);
        }
        text.parse().map_err(|_| {
            syntax(
                file,
                l.number,
                field * 8 + 1,
                format!("Directory field {} is not an integer: {text:?}", field + 1),
            )
        })
    };
    let nonneg = |v: i64| usize::try_from(v).unwrap_or(0);
    Ok(Entry {
        seq: (2 * k + 1) as u64,
        line: a.number,
        kind: int(a, 0)?,
        param_start: nonneg(int(a, 1)?),
        param_count: nonneg(int(b, 3)?),
        transform: u64::try_from(int(a, 6)?).unwrap_or(0),
        form: int(b, 4)?,
        status: field_text(a, 8),
        label: field_text(b, 7),
    })
}

fn field_text(l: &Line, field: usize) -> String {
    l.data
        .chars()
        .skip(field * 8)
        .take(8)
        .collect::<String>()
        .trim()
        .to_string()
}
