//! Text helpers shared by the writers: escaping for XML/HTML and CSV, and
//! number formatting (deterministic, locale-free).

/// Escapes `&`, `<`, `>`, `"` and `'` for XML/HTML text and attribute values;
/// control characters other than tab, CR and LF (not allowed in XML 1.0)
/// become U+FFFD.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if c.is_control() => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// A CSV field (RFC 4180): quoted when it holds a comma, quote, CR or LF.
pub fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// A number exactly as `serde_json` writes it (shortest round-trip form,
/// e.g. `0.1`, `1.0`, `-2.5e-7`); non-finite values as Rust prints them
/// (`NaN`, `inf`, `-inf`), which JSON cannot hold (it writes `null`).
pub fn json_number(value: f64) -> String {
    match serde_json::Number::from_f64(value) {
        Some(number) => number.to_string(),
        None => value.to_string(),
    }
}

/// Fixed-point formatting with `decimals` digits; `-0.000` becomes `0.000`
/// so that output does not depend on the sign of tiny values.
pub fn fixed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
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
        for v in [0.1, 1.0, -2.5e-7, 1e21, 123456.789] {
            assert_eq!(json_number(v), serde_json::to_string(&v).unwrap());
        }
        assert_eq!(json_number(f64::NAN), "NaN");
    }

    #[test]
    fn fixed_drops_negative_zero() {
        assert_eq!(fixed(-0.00001, 3), "0.000");
        assert_eq!(fixed(-0.5, 1), "-0.5");
    }
}
