//! Text helpers shared by the writers: escaping for XML/HTML and CSV, and
//! number formatting (deterministic, locale-free), as new strings or
//! appended to a caller's buffer.

use super::decimal::push_std_fixed;
pub use super::decimal::TextSink;

/// Escapes `&`, `<`, `>`, `"` and `'` for XML/HTML text and attribute values;
/// control characters other than tab, CR and LF (not allowed in XML 1.0)
/// become U+FFFD.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    push_escaped(&mut out, text);
    out
}

/// Appends `text` escaped as by [`escape`] to a `String` or UTF-8 bytes.
pub fn push_escaped<S: TextSink + ?Sized>(out: &mut S, text: &str) {
    let mut plain = 0;
    for (at, c) in text.char_indices() {
        let replacement = match c {
            '&' => "&amp;",
            '<' => "&lt;",
            '>' => "&gt;",
            '"' => "&quot;",
            '\'' => "&apos;",
            '\t' | '\n' | '\r' => continue,
            c if c.is_control() => "\u{FFFD}",
            _ => continue,
        };
        out.push_text(&text[plain..at]);
        out.push_text(replacement);
        plain = at + c.len_utf8();
    }
    out.push_text(&text[plain..]);
}

/// A CSV field (RFC 4180): quoted when it holds a comma, quote, CR or LF.
pub fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Appends a number exactly as `serde_json` writes it (shortest round-trip
/// form, e.g. `0.1`, `1.0`, `-2.5e-7`); non-finite values as Rust prints
/// them (`NaN`, `inf`, `-inf`), which JSON cannot hold (it writes `null`).
///
/// Written by `zmij`, the formatter `serde_json` itself writes floats with,
/// straight into the buffer: the same bytes without the formatting
/// machinery, which costs several times more on a report's hundreds of
/// thousands of numbers.
pub fn push_json_number<S: TextSink + ?Sized>(out: &mut S, value: f64) {
    if value.is_finite() {
        out.push_ascii(zmij::Buffer::new().format_finite(value).as_bytes());
    } else {
        out.push_ascii(format!("{value}").as_bytes());
    }
}

/// Fixed-point formatting with `decimals` digits; `-0.000` becomes `0.000`
/// so that output does not depend on the sign of tiny values.
pub fn fixed(value: f64, decimals: usize) -> String {
    let mut out = String::new();
    push_fixed(&mut out, value, decimals);
    out
}

/// Appends `value` as by [`fixed`] to a `String` or UTF-8 bytes.
pub fn push_fixed<S: TextSink + ?Sized>(out: &mut S, value: f64, decimals: usize) {
    let start = out.text_bytes().len();
    push_std_fixed(out, value, decimals);
    let written = out.text_bytes().get(start..).unwrap_or_default();
    if let Some((b'-', rest)) = written.split_first() {
        if rest.iter().all(|&b| b == b'0' || b == b'.') {
            out.remove_ascii(start);
        }
    }
}

/// The snake_case name a serialisable unit enum has in JSON
/// (e.g. an attempt outcome `"lost_contact"`).
pub fn json_name<T: serde::Serialize>(value: &T) -> String {
    crate::formats::serde_name(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_controls() {
        assert_eq!(
            escape("a<b & 'c'\"\u{1}"),
            "a&lt;b &amp; &apos;c&apos;&quot;\u{FFFD}"
        );
    }

    #[test]
    fn quotes_csv_fields_only_when_needed() {
        assert_eq!(csv_field("plain"), "plain");
        assert_eq!(csv_field("a,\"b\""), "\"a,\"\"b\"\"\"");
    }

    #[test]
    fn numbers_match_serde_json() {
        let json_number = |v: f64| {
            let mut out = String::new();
            push_json_number(&mut out, v);
            out
        };
        for v in [0.1, 1.0, -2.5e-7, 1e21, 123456.789, -0.0, 5e-324] {
            assert_eq!(json_number(v), serde_json::to_string(&v).unwrap());
        }
        // Seeded random bit patterns (every magnitude) and report-sized
        // coordinates.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(7);
        for _ in 0..20_000 {
            let bits = f64::from_bits(rng.random::<u64>());
            let mm = rng.random_range(-500.0..500.0_f64);
            for v in [bits, mm].into_iter().filter(|v| v.is_finite()) {
                assert_eq!(json_number(v), serde_json::to_string(&v).unwrap());
            }
        }
        assert_eq!(json_number(f64::NAN), "NaN");
        assert_eq!(json_number(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn fixed_drops_negative_zero() {
        assert_eq!(fixed(-0.00001, 3), "0.000");
        assert_eq!(fixed(-0.5, 1), "-0.5");
        assert_eq!(fixed(-0.0, 0), "0");
        assert_eq!(fixed(-0.4, 0), "0");
        assert_eq!(fixed(-0.6, 0), "-1");
        assert_eq!(fixed(f64::NEG_INFINITY, 2), "-inf");
    }

    #[test]
    fn fixed_matches_the_format_macro_without_negative_zero() {
        let values = [
            -0.0, -1e-9, -0.00049, -0.0005, -0.00051, 0.125, -0.125, 2.5, -2.5,
        ];
        for value in values {
            for decimals in 0..=8 {
                let text = format!("{value:.decimals$}");
                let expected = match text.strip_prefix('-') {
                    Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest,
                    _ => &text,
                };
                let mut out = String::from("<");
                push_fixed(&mut out, value, decimals);
                assert_eq!(out, format!("<{expected}"), "{value} at {decimals}");
            }
        }
    }

    #[test]
    fn appending_escape_matches_escape_of_mixed_text() {
        let text = "\u{1}ä<&>'\"\tend\u{7f}é";
        let mut out = String::from("x");
        push_escaped(&mut out, text);
        assert_eq!(out, "x\u{FFFD}ä&lt;&amp;&gt;&apos;&quot;\tend\u{FFFD}é");
    }
}
