//! The layout of `report.json`: serde_json's pretty layout (two-space
//! indent, one key per line), except that an array whose first element is
//! a number, string, boolean or null is written on one line
//! (`[12.5, -3.0, 40.0]`): a point's coordinates stay readable and the
//! file is about half the size of one with every coordinate on a line.
//!
//! serde_json's own `PrettyFormatter` cannot look ahead, and no crate
//! offers this layout, so it is written here: the formatter defers the
//! line break before an array's first element until it sees what that
//! element is.
use std::io::{self, Write};

use serde_json::ser::Formatter;

/// How an array is being written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Array {
    /// Its first element has not come yet.
    Open,
    /// On one line.
    Inline,
    /// One element per line.
    Block,
}

/// The formatter (see the module docs).
#[derive(Debug, Default)]
pub struct ReportFormatter {
    indent: usize,
    /// Whether the object or block array being written has an element.
    has_value: bool,
    /// The arrays being written, innermost last.
    arrays: Vec<Array>,
}

impl ReportFormatter {
    /// A formatter for a value written at the given depth of the report
    /// (a member's value whose key is indented `indent` levels): it writes
    /// the value as it would inside the whole report.
    pub fn at_indent(indent: usize) -> ReportFormatter {
        ReportFormatter {
            indent,
            ..ReportFormatter::default()
        }
    }

    fn newline<W: ?Sized + Write>(&self, w: &mut W) -> io::Result<()> {
        w.write_all(b"\n")?;
        (0..self.indent).try_for_each(|_| w.write_all(b"  "))
    }

    /// Settles the layout of the innermost array before a value: a scalar
    /// first element makes it inline, anything else a block.
    fn before_value<W: ?Sized + Write>(&mut self, w: &mut W, scalar: bool) -> io::Result<()> {
        match self.arrays.last_mut() {
            Some(a @ Array::Open) if scalar => {
                *a = Array::Inline;
                Ok(())
            }
            Some(a @ Array::Open) => {
                *a = Array::Block;
                self.newline(w)
            }
            _ => Ok(()),
        }
    }
}

/// A scalar's writer: settles the array layout, then writes as serde_json
/// would.
macro_rules! scalar {
    ($($name:ident($t:ty)),* $(,)?) => {$(
        fn $name<W: ?Sized + Write>(&mut self, w: &mut W, value: $t) -> io::Result<()> {
            self.before_value(w, true)?;
            serde_json::ser::CompactFormatter.$name(w, value)
        }
    )*};
}

impl Formatter for ReportFormatter {
    scalar!(
        write_bool(bool),
        write_i8(i8),
        write_i16(i16),
        write_i32(i32),
        write_i64(i64),
        write_i128(i128),
        write_u8(u8),
        write_u16(u16),
        write_u32(u32),
        write_u64(u64),
        write_u128(u128),
        write_f32(f32),
        write_f64(f64),
        write_number_str(&str),
    );

    fn write_null<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.before_value(w, true)?;
        w.write_all(b"null")
    }

    fn begin_string<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.before_value(w, true)?;
        w.write_all(b"\"")
    }

    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.before_value(w, false)?;
        self.indent += 1;
        self.has_value = false;
        self.arrays.push(Array::Open);
        w.write_all(b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.indent = self.indent.saturating_sub(1);
        if self.arrays.pop() == Some(Array::Block) && self.has_value {
            self.newline(w)?;
        }
        self.has_value = true;
        w.write_all(b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        match (self.arrays.last(), first) {
            (_, true) => Ok(()),
            (Some(Array::Inline), false) => w.write_all(b", "),
            (_, false) => {
                w.write_all(b",")?;
                self.newline(w)
            }
        }
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.before_value(w, false)?;
        self.indent += 1;
        self.has_value = false;
        // An object's own keys are not an array's elements.
        self.arrays.push(Array::Block);
        w.write_all(b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.indent = self.indent.saturating_sub(1);
        self.arrays.pop();
        if self.has_value {
            self.newline(w)?;
        }
        self.has_value = true;
        w.write_all(b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if !first {
            w.write_all(b",")?;
        }
        self.newline(w)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Serialize;

    fn layout<T: Serialize>(value: &T) -> String {
        let mut out = Vec::new();
        let mut ser = serde_json::Serializer::with_formatter(&mut out, ReportFormatter::default());
        value.serialize(&mut ser).unwrap_or_else(|e| panic!("{e}"));
        String::from_utf8(out).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn scalar_arrays_go_on_one_line_the_rest_as_serde_json_prints_it() {
        let value = serde_json::json!({
            "a": [1.5, -2.0, 3e-9],
            "b": [],
            "c": [{"x": [1, 2], "s": ["p", null]}, {}],
            "d": [[1.0, 2.0], [3.0, 4.0]],
            "e": {"f": true}
        });
        let text = layout(&value);
        let expected = "{\n  \"a\": [1.5, -2.0, 3e-9],\n  \"b\": [],\n  \"c\": [\n    {\n      \
                        \"s\": [\"p\", null],\n      \"x\": [1, 2]\n    },\n    {}\n  ],\n  \
                        \"d\": [\n    [1.0, 2.0],\n    [3.0, 4.0]\n  ],\n  \"e\": {\n    \"f\": true\n  }\n}";
        assert_eq!(text, expected);
        let back: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
        assert_eq!(back, value);
    }
}
