//! Tokenizer for IGES parameter data (free-format fields with Hollerith
//! strings and `D` exponents), tracking line and column of every field.
use super::records::{syntax, Line};
use crate::cad::error::CadResult;

/// One parameter field.
#[derive(Debug, Clone, PartialEq)]
pub enum Token {
    /// Empty field (default value).
    Empty,
    /// Integer.
    Int(i64),
    /// Real.
    Real(f64),
    /// Hollerith string.
    Str(String),
}

impl Token {
    /// The value as an integer (reals with integral value included).
    pub fn as_int(&self) -> Option<i64> {
        match self {
            Token::Int(i) => Some(*i),
            Token::Empty => Some(0),
            Token::Real(r) if r.fract() == 0.0 && r.abs() < 9.0e15 => Some(*r as i64),
            _ => None,
        }
    }

    /// The value as a real.
    pub fn as_real(&self) -> Option<f64> {
        match self {
            Token::Int(i) => Some(*i as f64),
            Token::Real(r) => Some(*r),
            Token::Empty => Some(0.0),
            Token::Str(_) => None,
        }
    }

    /// The value as a string.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Token::Str(s) => Some(s),
            _ => None,
        }
    }
}

/// The fields of one entity (or of the Global section) with their places.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tokens {
    /// Field values.
    pub items: Vec<Token>,
    /// `(line, column)` of each field.
    pub places: Vec<(usize, usize)>,
}

struct Cursor<'a> {
    chars: Vec<(char, usize, usize)>,
    i: usize,
    file: &'a str,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.i).map(|c| c.0)
    }

    fn place(&self) -> (usize, usize) {
        self.chars
            .get(self.i)
            .or(self.chars.last())
            .map_or((1, 1), |c| (c.1, c.2))
    }
}

/// Splits the records' data into fields up to the record delimiter.
pub fn tokenize(lines: &[Line], param: char, record: char, file: &str) -> CadResult<Tokens> {
    let chars = lines
        .iter()
        .flat_map(|l| {
            l.data
                .chars()
                .enumerate()
                .map(move |(k, c)| (c, l.number, k + 1))
        })
        .collect();
    let mut cur = Cursor { chars, i: 0, file };
    let mut out = Tokens::default();
    loop {
        let place = cur.place();
        let tok = field(&mut cur, param, record)?;
        out.items.push(tok);
        out.places.push(place);
        match cur.peek() {
            Some(c) if c == param => cur.i += 1,
            Some(c) if c == record => return Ok(out),
            _ => {
                let (l, c) = cur.place();
                return Err(syntax(
                    file,
                    l,
                    c,
                    "parameter data not terminated by the record delimiter",
                ));
            }
        }
    }
}

fn field(cur: &mut Cursor, param: char, record: char) -> CadResult<Token> {
    let start = cur.place();
    let mut text = String::new();
    while let Some(c) = cur.peek() {
        if c == param || c == record {
            break;
        }
        if c == 'H' && !text.trim().is_empty() && text.trim().chars().all(|d| d.is_ascii_digit()) {
            cur.i += 1;
            return hollerith(cur, text.trim(), start);
        }
        text.push(c);
        cur.i += 1;
    }
    number(text.trim(), cur.file, start)
}

fn hollerith(cur: &mut Cursor, count: &str, start: (usize, usize)) -> CadResult<Token> {
    let n: usize = count
        .parse()
        .map_err(|_| syntax(cur.file, start.0, start.1, "bad Hollerith count"))?;
    let s: String = cur.chars.iter().skip(cur.i).take(n).map(|c| c.0).collect();
    if s.chars().count() < n {
        return Err(syntax(
            cur.file,
            start.0,
            start.1,
            "Hollerith string runs past the end of the data",
        ));
    }
    cur.i += n;
    while cur.peek() == Some(' ') {
        cur.i += 1;
    }
    Ok(Token::Str(s))
}

fn number(text: &str, file: &str, (line, col): (usize, usize)) -> CadResult<Token> {
    if text.is_empty() {
        return Ok(Token::Empty);
    }
    let cleaned: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    if let Ok(i) = cleaned.parse::<i64>() {
        return Ok(Token::Int(i));
    }
    let fixed = if cleaned.ends_with('.') {
        format!("{cleaned}0")
    } else {
        cleaned.replace(".E", ".0E")
    };
    match fixed.parse::<f64>() {
        Ok(r) if r.is_finite() => Ok(Token::Real(r)),
        _ => Err(syntax(
            file,
            line,
            col,
            format!("malformed number {text:?}"),
        )),
    }
}
