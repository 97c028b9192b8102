//! Tokenizer for the ISO 10303-21 exchange structure.
//!
//! Works on bytes, never panics, and tracks the 1-based line and column
//! (in characters) of every token.
use super::strings::decode_string;
use crate::cad::error::{CadError, CadResult};

/// A place in the text (1-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pos {
    /// Line number.
    pub line: usize,
    /// Column number in characters.
    pub column: usize,
}

/// One token of the exchange structure.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// Standard or user keyword (`CARTESIAN_POINT`, `ISO-10303-21`, `!USER`).
    Keyword(String),
    /// Entity instance name `#12`.
    Ref(u64),
    /// Integer literal.
    Int(i64),
    /// Real literal.
    Real(f64),
    /// Decoded string literal.
    Str(String),
    /// Enumeration `.T.` (without the dots).
    Enum(String),
    /// Binary literal `"0FF"` (raw hex digits).
    Binary(String),
    /// `$` (omitted value).
    Dollar,
    /// `*` (derived value).
    Star,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `=`
    Eq,
    /// End of input.
    Eof,
}

/// Streaming tokenizer.
pub struct Lexer<'a> {
    bytes: &'a [u8],
    i: usize,
    pos: Pos,
    file: &'a str,
}

impl<'a> Lexer<'a> {
    /// A tokenizer over `text`; `file` names the source in errors.
    pub fn new(text: &'a str, file: &'a str) -> Self {
        let pos = Pos { line: 1, column: 1 };
        Lexer {
            bytes: text.as_bytes(),
            i: 0,
            pos,
            file,
        }
    }

    /// The current position.
    pub fn pos(&self) -> Pos {
        self.pos
    }

    /// A syntax error at `pos`.
    pub fn error_at(&self, pos: Pos, reason: impl Into<String>) -> CadError {
        CadError::Syntax {
            file: self.file.to_string(),
            line: pos.line,
            column: pos.column,
            reason: reason.into(),
        }
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.i).copied()
    }

    fn peek_at(&self, k: usize) -> Option<u8> {
        self.bytes.get(self.i + k).copied()
    }

    fn bump(&mut self) -> Option<u8> {
        let b = self.peek()?;
        self.i += 1;
        if b == b'\n' {
            self.pos.line += 1;
            self.pos.column = 1;
        } else if b & 0xC0 != 0x80 {
            self.pos.column += 1;
        }
        Some(b)
    }

    /// Skips white space and `/* */` comments.
    fn skip_trivia(&mut self) -> CadResult<()> {
        loop {
            match self.peek() {
                Some(b) if b.is_ascii_whitespace() => {
                    self.bump();
                }
                Some(b'/') if self.peek_at(1) == Some(b'*') => self.skip_comment()?,
                _ => return Ok(()),
            }
        }
    }

    fn skip_comment(&mut self) -> CadResult<()> {
        let start = self.pos;
        self.bump();
        self.bump();
        while let Some(b) = self.bump() {
            if b == b'*' && self.peek() == Some(b'/') {
                self.bump();
                return Ok(());
            }
        }
        Err(self.error_at(start, "unterminated comment"))
    }

    /// The next token and its position.
    pub fn next_token(&mut self) -> CadResult<(Tok, Pos)> {
        self.skip_trivia()?;
        let start = self.pos;
        let Some(b) = self.peek() else {
            return Ok((Tok::Eof, start));
        };
        let tok = match b {
            b'(' | b')' | b',' | b';' | b'=' | b'$' | b'*' => self.punct(b),
            b'#' => self.reference(start)?,
            b'\'' => self.string(start)?,
            b'.' if self
                .peek_at(1)
                .is_some_and(|c| c.is_ascii_alphabetic() || c == b'_') =>
            {
                self.enumeration(start)?
            }
            b'"' => self.binary(start)?,
            b'+' | b'-' | b'.' | b'0'..=b'9' => self.number(start)?,
            b'!' | b'A'..=b'Z' | b'a'..=b'z' | b'_' => self.keyword(),
            _ => return Err(self.error_at(start, format!("unexpected character {:?}", b as char))),
        };
        Ok((tok, start))
    }

    fn punct(&mut self, b: u8) -> Tok {
        self.bump();
        match b {
            b'(' => Tok::LParen,
            b')' => Tok::RParen,
            b',' => Tok::Comma,
            b';' => Tok::Semi,
            b'=' => Tok::Eq,
            b'$' => Tok::Dollar,
            _ => Tok::Star,
        }
    }

    fn take_while(&mut self, f: impl Fn(u8) -> bool) -> &'a str {
        let from = self.i;
        while self.peek().is_some_and(&f) {
            self.bump();
        }
        let bytes: &'a [u8] = self.bytes;
        bytes
            .get(from..self.i)
            .and_then(|s| std::str::from_utf8(s).ok())
            .unwrap_or("")
    }

    fn keyword(&mut self) -> Tok {
        let word =
            self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'!');
        Tok::Keyword(word.to_ascii_uppercase())
    }

    fn reference(&mut self, start: Pos) -> CadResult<Tok> {
        self.bump();
        let digits = self.take_while(|c| c.is_ascii_digit());
        digits
            .parse::<u64>()
            .map(Tok::Ref)
            .map_err(|_| self.error_at(start, "expected digits after '#'"))
    }

    fn enumeration(&mut self, start: Pos) -> CadResult<Tok> {
        self.bump();
        let word = self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_');
        let word = word.to_ascii_uppercase();
        if self.bump() != Some(b'.') {
            return Err(self.error_at(start, "unterminated enumeration (missing '.')"));
        }
        Ok(Tok::Enum(word))
    }

    fn binary(&mut self, start: Pos) -> CadResult<Tok> {
        self.bump();
        let hex = self.take_while(|c| c.is_ascii_hexdigit()).to_string();
        if self.bump() != Some(b'"') {
            return Err(self.error_at(start, "unterminated binary literal"));
        }
        Ok(Tok::Binary(hex))
    }

    fn number(&mut self, start: Pos) -> CadResult<Tok> {
        let text = self
            .take_while(|c| c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.' | b'E' | b'e'));
        let is_real = text.contains(['.', 'E', 'e']);
        if is_real {
            return parse_real(text)
                .map(Tok::Real)
                .ok_or_else(|| self.error_at(start, format!("malformed real {text:?}")));
        }
        text.parse::<i64>()
            .map(Tok::Int)
            .map_err(|_| self.error_at(start, format!("malformed integer {text:?}")))
    }

    fn string(&mut self, start: Pos) -> CadResult<Tok> {
        self.bump();
        let mut raw: Vec<u8> = Vec::new();
        loop {
            match self.bump() {
                None => return Err(self.error_at(start, "unterminated string")),
                Some(b'\'') if self.peek() == Some(b'\'') => {
                    self.bump();
                    raw.push(b'\'');
                }
                Some(b'\'') => break,
                Some(b'\n' | b'\r') => {}
                Some(b) => raw.push(b),
            }
        }
        decode_string(&raw)
            .map(Tok::Str)
            .map_err(|reason| self.error_at(start, reason))
    }
}

/// Parses a STEP real (`1.`, `-2.5E-3`, `.5`); `None` when malformed.
fn parse_real(text: &str) -> Option<f64> {
    let value: f64 = if text.ends_with('.') {
        text.trim_end_matches('.').parse().ok()?
    } else {
        text.replace(".E", ".0E")
            .replace(".e", ".0e")
            .parse()
            .ok()?
    };
    value.is_finite().then_some(value)
}
