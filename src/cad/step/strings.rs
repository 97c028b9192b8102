//! Decoding of ISO 10303-21 string escapes (`\\`, `\S\`, `\P?\`, `\X\hh`,
//! `\X2\...\X0\`, `\X4\...\X0\`, `\N\`).

/// Decodes the raw bytes between the quotes (with `''` already collapsed).
pub fn decode_string(raw: &[u8]) -> Result<String, String> {
    let mut out = String::with_capacity(raw.len());
    let mut i = 0;
    while let Some(&b) = raw.get(i) {
        if b == b'\\' {
            i = escape(raw, i, &mut out)?;
        } else {
            let len = utf8_len(b);
            let chunk = raw.get(i..i + len).ok_or("truncated UTF-8 character")?;
            out.push_str(std::str::from_utf8(chunk).map_err(|_| "invalid UTF-8 in string")?);
            i += len;
        }
    }
    Ok(out)
}

fn utf8_len(b: u8) -> usize {
    match b {
        0xF0..=0xFF => 4,
        0xE0..=0xEF => 3,
        0xC0..=0xDF => 2,
        _ => 1,
    }
}

/// Handles one escape starting at `raw[i] == b'\\'`; returns the next index.
fn escape(raw: &[u8], i: usize, out: &mut String) -> Result<usize, String> {
    let at = |k: usize| raw.get(i + k).copied();
    match (at(1), at(2), at(3)) {
        (Some(b'\\'), _, _) => {
            out.push('\\');
            Ok(i + 2)
        }
        (Some(b'S'), Some(b'\\'), Some(c)) => {
            out.push(char::from(c.wrapping_add(128)));
            Ok(i + 4)
        }
        (Some(b'P'), Some(_), Some(b'\\')) => Ok(i + 4),
        (Some(b'N'), Some(b'\\'), _) => Ok(i + 3),
        (Some(b'X'), Some(b'\\'), _) => {
            let code = hex_value(raw.get(i + 3..i + 5))?;
            out.push(char::from_u32(code).ok_or("invalid \\X\\ code")?);
            Ok(i + 5)
        }
        (Some(b'X'), Some(b'2'), Some(b'\\')) => wide(raw, i + 4, 4, out),
        (Some(b'X'), Some(b'4'), Some(b'\\')) => wide(raw, i + 4, 8, out),
        _ => Err("invalid escape sequence in string".to_string()),
    }
}

fn hex_value(digits: Option<&[u8]>) -> Result<u32, String> {
    let digits = digits.ok_or("truncated hex escape")?;
    let text = std::str::from_utf8(digits).map_err(|_| "invalid hex escape")?;
    u32::from_str_radix(text, 16).map_err(|_| format!("invalid hex digits {text:?}"))
}

/// Decodes `\X2\` (4 hex digits per UTF-16 unit) or `\X4\` (8 per char) up to `\X0\`.
fn wide(raw: &[u8], mut i: usize, width: usize, out: &mut String) -> Result<usize, String> {
    let mut units: Vec<u16> = Vec::new();
    loop {
        if raw.get(i..i + 4) == Some(b"\\X0\\".as_slice()) {
            break;
        }
        let code = hex_value(raw.get(i..i + width))?;
        if width == 4 {
            units.push(u16::try_from(code).map_err(|_| "bad UTF-16 unit")?);
        } else {
            out.push(char::from_u32(code).ok_or("invalid \\X4\\ code point")?);
        }
        i += width;
    }
    out.push_str(&String::from_utf16(&units).map_err(|_| "invalid UTF-16 in \\X2\\ escape")?);
    Ok(i + 4)
}
