//! Parser for the exchange structure: HEADER and DATA sections, simple and
//! complex entity instances, typed parameters, lists.
//!
//! Recursion is bounded by [`MAX_NESTING`], so no input can overflow the stack.
use super::lexer::{Lexer, Pos, Tok};
use crate::cad::error::CadResult;
use std::collections::HashMap;

/// Deepest allowed nesting of lists and typed parameters.
pub const MAX_NESTING: usize = 64;

/// One parameter value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// `#id`
    Ref(u64),
    /// Integer.
    Int(i64),
    /// Real.
    Real(f64),
    /// String (decoded).
    Str(String),
    /// Enumeration value without dots (`T`, `F`, `MILLI`).
    Enum(String),
    /// Binary hex digits.
    Binary(String),
    /// `$`
    Null,
    /// `*`
    Derived,
    /// `( ... )`
    List(Vec<Value>),
    /// `NAME(value)`, e.g. `LENGTH_MEASURE(1.)`.
    Typed(String, Box<Value>),
}

/// `NAME(params)`: a simple record or one part of a complex instance.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Upper-case entity name.
    pub name: String,
    /// Parameters in order.
    pub params: Vec<Value>,
}

/// An entity instance `#id = ...;`.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// Instance number.
    pub id: u64,
    /// One record (simple instance) or several (complex instance).
    pub records: Vec<Record>,
    /// Position of the `#id` that starts the instance.
    pub pos: Pos,
    /// True for the `( A() B() )` form.
    pub complex: bool,
}

/// A parsed exchange structure.
#[derive(Debug, Clone, Default)]
pub struct StepFile {
    /// HEADER section records.
    pub header: Vec<Record>,
    /// DATA instances in file order.
    pub instances: Vec<Instance>,
    /// Position of the first `DATA` keyword.
    pub data_pos: Pos,
    index: HashMap<u64, usize>,
}

impl StepFile {
    /// The instance `#id`, if defined.
    pub fn get(&self, id: u64) -> Option<&Instance> {
        self.index.get(&id).and_then(|&k| self.instances.get(k))
    }

    /// The file-order index of `#id` (`usize::MAX` when undefined).
    pub fn position(&self, id: u64) -> usize {
        self.index.get(&id).copied().unwrap_or(usize::MAX)
    }
}

/// Parses the whole text (syntax only).
pub fn parse_syntax(text: &str, file: &str) -> CadResult<StepFile> {
    let mut p = Parser::new(text, file)?;
    p.file()
}

struct Parser<'a> {
    lex: Lexer<'a>,
    tok: Tok,
    pos: Pos,
}

impl<'a> Parser<'a> {
    fn new(text: &'a str, file: &'a str) -> CadResult<Self> {
        let mut lex = Lexer::new(text, file);
        let (tok, pos) = lex.next_token()?;
        Ok(Parser { lex, tok, pos })
    }

    fn advance(&mut self) -> CadResult<Tok> {
        let (tok, pos) = self.lex.next_token()?;
        self.pos = pos;
        Ok(std::mem::replace(&mut self.tok, tok))
    }

    fn fail<T>(&self, reason: impl Into<String>) -> CadResult<T> {
        let found = match &self.tok {
            Tok::Eof => "end of file (truncated file?)".to_string(),
            other => format!("{other:?}"),
        };
        Err(self
            .lex
            .error_at(self.pos, format!("{}, found {found}", reason.into())))
    }

    fn expect(&mut self, want: &Tok, what: &str) -> CadResult<()> {
        if &self.tok == want {
            self.advance()?;
            return Ok(());
        }
        self.fail(format!("expected {what}"))
    }

    fn expect_keyword(&mut self, word: &str) -> CadResult<()> {
        if matches!(&self.tok, Tok::Keyword(k) if k == word) {
            self.advance()?;
            return Ok(());
        }
        self.fail(format!("expected {word}"))
    }

    fn is_keyword(&self, word: &str) -> bool {
        matches!(&self.tok, Tok::Keyword(k) if k == word)
    }

    fn file(&mut self) -> CadResult<StepFile> {
        self.expect_keyword("ISO-10303-21")?;
        self.expect(&Tok::Semi, "';'")?;
        let mut out = StepFile {
            header: self.header()?,
            ..StepFile::default()
        };
        out.data_pos = self.pos;
        if !self.is_keyword("DATA") {
            return self.fail("expected DATA section");
        }
        while self.is_keyword("DATA") {
            self.data_section(&mut out)?;
        }
        self.expect_keyword("END-ISO-10303-21")?;
        self.expect(&Tok::Semi, "';'")?;
        Ok(out)
    }

    fn header(&mut self) -> CadResult<Vec<Record>> {
        self.expect_keyword("HEADER")?;
        self.expect(&Tok::Semi, "';'")?;
        let mut records = Vec::new();
        while !self.is_keyword("ENDSEC") {
            records.push(self.record(0)?);
            self.expect(&Tok::Semi, "';' after header entity")?;
        }
        self.advance()?;
        self.expect(&Tok::Semi, "';' after ENDSEC")?;
        Ok(records)
    }

    fn data_section(&mut self, out: &mut StepFile) -> CadResult<()> {
        self.advance()?;
        if self.tok == Tok::LParen {
            self.list(0)?;
        }
        self.expect(&Tok::Semi, "';' after DATA")?;
        while !self.is_keyword("ENDSEC") {
            let inst = self.instance()?;
            if out.index.insert(inst.id, out.instances.len()).is_some() {
                return Err(self
                    .lex
                    .error_at(inst.pos, format!("duplicate instance #{}", inst.id)));
            }
            out.instances.push(inst);
        }
        self.advance()?;
        self.expect(&Tok::Semi, "';' after ENDSEC")
    }

    fn instance(&mut self) -> CadResult<Instance> {
        let pos = self.pos;
        let Tok::Ref(id) = self.tok else {
            return self.fail("expected entity instance '#n = ...' or ENDSEC");
        };
        self.advance()?;
        self.expect(&Tok::Eq, "'='")?;
        let complex = self.tok == Tok::LParen;
        let records = if complex {
            self.complex_records()?
        } else {
            vec![self.record(0)?]
        };
        self.expect(&Tok::Semi, "';' after entity instance")?;
        Ok(Instance {
            id,
            records,
            pos,
            complex,
        })
    }

    fn complex_records(&mut self) -> CadResult<Vec<Record>> {
        self.advance()?;
        let mut records = Vec::new();
        while self.tok != Tok::RParen {
            records.push(self.record(0)?);
        }
        self.advance()?;
        if records.is_empty() {
            return self.fail("empty complex entity instance");
        }
        Ok(records)
    }

    fn record(&mut self, depth: usize) -> CadResult<Record> {
        let Tok::Keyword(name) = &self.tok else {
            return self.fail("expected entity name");
        };
        let name = name.clone();
        self.advance()?;
        let params = self.list(depth)?;
        Ok(Record { name, params })
    }

    /// `( value, value, ... )`
    fn list(&mut self, depth: usize) -> CadResult<Vec<Value>> {
        if depth > MAX_NESTING {
            return self.fail(format!("nesting deeper than {MAX_NESTING}"));
        }
        self.expect(&Tok::LParen, "'('")?;
        let mut items = Vec::new();
        if self.tok == Tok::RParen {
            self.advance()?;
            return Ok(items);
        }
        loop {
            items.push(self.value(depth + 1)?);
            match self.tok {
                Tok::Comma => self.advance()?,
                Tok::RParen => {
                    self.advance()?;
                    return Ok(items);
                }
                _ => return self.fail("expected ',' or ')'"),
            };
        }
    }

    /// One parameter; consumes all its tokens.
    fn value(&mut self, depth: usize) -> CadResult<Value> {
        let value = match &self.tok {
            Tok::LParen => return self.list(depth).map(Value::List),
            Tok::Keyword(_) => return self.typed(depth),
            Tok::Ref(id) => Value::Ref(*id),
            Tok::Int(i) => Value::Int(*i),
            Tok::Real(r) => Value::Real(*r),
            Tok::Str(s) => Value::Str(s.clone()),
            Tok::Enum(e) => Value::Enum(e.clone()),
            Tok::Binary(b) => Value::Binary(b.clone()),
            Tok::Dollar => Value::Null,
            Tok::Star => Value::Derived,
            _ => return self.fail("expected a parameter value"),
        };
        self.advance()?;
        Ok(value)
    }

    /// `LENGTH_MEASURE(1.)`
    fn typed(&mut self, depth: usize) -> CadResult<Value> {
        let pos = self.pos;
        let rec = self.record(depth)?;
        match <[Value; 1]>::try_from(rec.params) {
            Ok([inner]) => Ok(Value::Typed(rec.name, Box::new(inner))),
            Err(_) => Err(self.lex.error_at(
                pos,
                format!("typed parameter {} needs exactly one value", rec.name),
            )),
        }
    }
}
