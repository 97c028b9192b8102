//! Fixed-point formatting of `f64` into a caller's buffer, byte for byte as
//! `format!("{value:.decimals$}")` writes it.
//!
//! The standard library rounds the exact binary value of the number to the
//! requested decimals, ties (only possible for exactly representable values
//! such as 0.125 or 2.5) to even, prints a `-` for every negative sign bit
//! (also `-0.000`) and no decimal point for 0 decimals. This module does the
//! same with integer arithmetic: a finite `f64` is `m * 2^e` with `m < 2^53`,
//! so `value * 10^d` is `m * 10^d / 2^-e`, which for `d <= 22` fits a `u128`
//! (`2^53 * 10^22 < 2^127`), and the rounding is a shift plus a comparison
//! of the remainder with one half. Everything else (non-finite values,
//! magnitudes of 2^64 and above, more than 22 decimals on a fractional
//! value) goes to `format!` itself.
//!
//! Written here rather than taken from a crate: the maintained float
//! formatters (`ryu`, `zmij`, `itoa`) write the shortest round-trip form or
//! integers, not a fixed number of decimals with the standard library's
//! rounding.

/// Most decimals of the exact path for a value with a fractional part.
const MAX_EXACT_DECIMALS: usize = 22;

/// Largest binary exponent of the integer path (`m * 2^11 < 2^64`).
const MAX_INTEGER_EXPONENT: i32 = 11;

/// Powers of ten up to 10^[`MAX_EXACT_DECIMALS`].
const POW10: [u128; MAX_EXACT_DECIMALS + 1] = pow10_table();

const fn pow10_table() -> [u128; MAX_EXACT_DECIMALS + 1] {
    let mut table = [1u128; MAX_EXACT_DECIMALS + 1];
    let mut k = 1;
    while k <= MAX_EXACT_DECIMALS {
        table[k] = table[k - 1] * 10;
        k += 1;
    }
    table
}

/// Powers of ten that fit a `u64` (up to 10^19).
const POW10_U64: [u64; 20] = pow10_u64_table();

const fn pow10_u64_table() -> [u64; 20] {
    let mut table = [1u64; 20];
    let mut k = 1;
    while k < 20 {
        table[k] = table[k - 1] * 10;
        k += 1;
    }
    table
}

/// The two-digit strings "00" to "99", concatenated.
const DIGIT_PAIRS: [u8; 200] = digit_pairs();

const fn digit_pairs() -> [u8; 200] {
    let mut table = [0u8; 200];
    let mut k = 0;
    while k < 100 {
        table[2 * k] = b'0' + (k / 10) as u8;
        table[2 * k + 1] = b'0' + (k % 10) as u8;
        k += 1;
    }
    table
}

/// A text buffer: a `String`, or the bytes of a UTF-8 file being written.
pub trait TextSink {
    /// Appends text.
    fn push_text(&mut self, text: &str);
    /// Appends bytes that are all ASCII.
    fn push_ascii(&mut self, bytes: &[u8]);
    /// The text written so far, as bytes.
    fn text_bytes(&self) -> &[u8];
    /// Removes the ASCII byte at `at`.
    fn remove_ascii(&mut self, at: usize);
}

impl TextSink for String {
    fn push_text(&mut self, text: &str) {
        self.push_str(text);
    }

    fn push_ascii(&mut self, bytes: &[u8]) {
        // ASCII bytes are chars of their own: no UTF-8 validation needed.
        self.reserve(bytes.len());
        self.extend(bytes.iter().map(|&b| char::from(b)));
    }

    fn text_bytes(&self) -> &[u8] {
        self.as_bytes()
    }

    fn remove_ascii(&mut self, at: usize) {
        if self.is_char_boundary(at) && at < self.len() {
            self.remove(at);
        }
    }
}

impl TextSink for Vec<u8> {
    fn push_text(&mut self, text: &str) {
        self.extend_from_slice(text.as_bytes());
    }

    fn push_ascii(&mut self, bytes: &[u8]) {
        self.extend_from_slice(bytes);
    }

    fn text_bytes(&self) -> &[u8] {
        self
    }

    fn remove_ascii(&mut self, at: usize) {
        if at < self.len() {
            self.remove(at);
        }
    }
}

/// Appends `value` with `decimals` digits after the point, exactly as
/// `format!("{value:.decimals$}")` writes it.
pub fn push_std_fixed<S: TextSink + ?Sized>(out: &mut S, value: f64, decimals: usize) {
    if !push_exact(out, value, decimals) {
        out.push_ascii(format!("{value:.decimals$}").as_bytes());
    }
}

/// Appends the decimal digits of `n`.
pub fn push_integer<S: TextSink + ?Sized>(out: &mut S, n: u64) {
    let mut buf = [b'0'; 20];
    let end = buf.len();
    let start = write_u64(&mut buf, end, n);
    out.push_ascii(buf.get(start..).unwrap_or_default());
}

/// The sign, binary mantissa and exponent of a finite `value`
/// (`|value| = mantissa * 2^exponent`).
fn decompose(value: f64) -> (bool, u64, i32) {
    let bits = value.to_bits();
    let negative = bits >> 63 == 1;
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1u64 << 52) - 1);
    if biased == 0 {
        (negative, fraction, -1074)
    } else {
        (negative, fraction | (1u64 << 52), biased - 1075)
    }
}

/// The exact path; `false` (nothing written) where it does not apply.
fn push_exact<S: TextSink + ?Sized>(out: &mut S, value: f64, decimals: usize) -> bool {
    if !value.is_finite() {
        return false;
    }
    let (negative, mantissa, exponent) = decompose(value);
    let applies = if exponent >= 0 {
        exponent <= MAX_INTEGER_EXPONENT
    } else {
        decimals <= MAX_EXACT_DECIMALS
    };
    if !applies {
        return false;
    }
    if negative {
        out.push_ascii(b"-");
    }
    if exponent >= 0 {
        push_digits(out, u128::from(mantissa << exponent), 0);
        if decimals > 0 {
            out.push_ascii(b".");
            for _ in 0..decimals {
                out.push_ascii(b"0");
            }
        }
    } else if !push_scaled_u64(out, mantissa, exponent.unsigned_abs(), decimals) {
        let scaled = u128::from(mantissa) * POW10[decimals];
        push_digits(out, round_shift(scaled, exponent.unsigned_abs()), decimals);
    }
    true
}

/// The exact path's `mantissa * 10^decimals / 2^shift` (`shift` > 0)
/// rounded as [`round_shift`] does and written with `decimals` decimals,
/// all in `u64` arithmetic: the common case of report numbers (a few
/// decimals, not tiny). `false` (nothing written) where it does not fit.
fn push_scaled_u64<S: TextSink + ?Sized>(
    out: &mut S,
    mantissa: u64,
    shift: u32,
    decimals: usize,
) -> bool {
    let unit = POW10_U64.get(decimals).copied();
    let Some(scaled) = unit.and_then(|unit| mantissa.checked_mul(unit)) else {
        return false;
    };
    if shift == 0 || shift >= u64::BITS {
        return false;
    }
    let quotient = scaled >> shift;
    let remainder = scaled & ((1u64 << shift) - 1);
    let half = 1u64 << (shift - 1);
    let up = remainder > half || (remainder == half && quotient & 1 == 1);
    push_u64_digits(out, quotient + u64::from(up), decimals);
    true
}

/// `n / 2^shift` rounded to the nearest integer, ties to even.
fn round_shift(n: u128, shift: u32) -> u128 {
    // n < 2^127, so from a shift of 128 on the quotient is 0 and the
    // remainder below one half.
    if shift >= 128 {
        return 0;
    }
    let quotient = n >> shift;
    let remainder = n & ((1u128 << shift) - 1);
    let half = 1u128 << (shift - 1);
    let up = remainder > half || (remainder == half && quotient & 1 == 1);
    quotient + u128::from(up)
}

/// Appends the integer `scaled / 10^decimals` with `decimals` digits after
/// the point (no point for 0 decimals); `decimals` is at most 22.
fn push_digits<S: TextSink + ?Sized>(out: &mut S, scaled: u128, decimals: usize) {
    match u64::try_from(scaled) {
        Ok(small) => push_u64_digits(out, small, decimals),
        Err(_) => push_u128_digits(out, scaled, decimals),
    }
}

/// [`push_digits`] for a `scaled` that fits a `u64`: the decimals one by
/// one from the right, the point, then the integer's digits.
fn push_u64_digits<S: TextSink + ?Sized>(out: &mut S, scaled: u64, decimals: usize) {
    // At most 20 integer digits, the point and 22 decimals.
    let mut buf = [b'0'; 43];
    let (integer, mut fraction) = match POW10_U64.get(decimals) {
        Some(&unit) => (scaled / unit, scaled % unit),
        None => (0, scaled),
    };
    let mut at = buf.len();
    if decimals > 0 {
        for _ in 0..decimals {
            at -= 1;
            buf[at] = b'0' + (fraction % 10) as u8;
            fraction /= 10;
        }
        at -= 1;
        buf[at] = b'.';
    }
    let start = write_u64(&mut buf, at, integer);
    out.push_ascii(buf.get(start..).unwrap_or_default());
}

/// [`push_digits`] for any `u128`.
fn push_u128_digits<S: TextSink + ?Sized>(out: &mut S, scaled: u128, decimals: usize) {
    // At most 39 digits of a u128, at least decimals + 1 <= 23; the buffer
    // starts as zeros, which pad a short number on the left, and keeps
    // room in front for the point.
    let mut buf = [b'0'; 41];
    let end = buf.len();
    let start = write_u128(&mut buf, end, scaled).min(end - decimals - 1);
    if decimals == 0 {
        out.push_ascii(buf.get(start..).unwrap_or_default());
        return;
    }
    // The integer digits move one place to the left, the point follows
    // them: the whole number goes out in one piece.
    let point = end - decimals;
    buf.copy_within(start..point, start - 1);
    if let Some(dot) = buf.get_mut(point - 1) {
        *dot = b'.';
    }
    out.push_ascii(buf.get(start - 1..).unwrap_or_default());
}

/// Writes the decimal digits of `n` into `buf` ending before `end`;
/// returns where they start ("0" for 0).
fn write_u64(buf: &mut [u8], end: usize, mut n: u64) -> usize {
    let mut at = end;
    while n >= 100 {
        let pair = (n % 100) as usize * 2;
        n /= 100;
        at -= 2;
        buf[at..at + 2].copy_from_slice(&DIGIT_PAIRS[pair..pair + 2]);
    }
    if n >= 10 {
        let pair = n as usize * 2;
        at -= 2;
        buf[at..at + 2].copy_from_slice(&DIGIT_PAIRS[pair..pair + 2]);
    } else {
        at -= 1;
        buf[at] = b'0' + n as u8;
    }
    at
}

/// As [`write_u64`] for any `u128`: beyond `u64`, the low 19 digits (with
/// their leading zeros) and then the rest in front of them.
fn write_u128(buf: &mut [u8], end: usize, n: u128) -> usize {
    const LOW_DIGITS: usize = 19;
    const LOW: u128 = 10_000_000_000_000_000_000;
    if let Ok(small) = u64::try_from(n) {
        return write_u64(buf, end, small);
    }
    let low_start = write_u64(buf, end, (n % LOW) as u64);
    buf[end - LOW_DIGITS..low_start].fill(b'0');
    write_u128(buf, end - LOW_DIGITS, n / LOW)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};

    /// Checks one value at one number of decimals against `format!`.
    fn check(value: f64, decimals: usize) {
        let mut out = String::from("x");
        push_std_fixed(&mut out, value, decimals);
        let expected = format!("{value:.decimals$}");
        let mut bytes = b"x".to_vec();
        push_std_fixed(&mut bytes, value, decimals);
        assert_eq!(&bytes[1..], expected.as_bytes());
        assert_eq!(
            &out[1..],
            expected,
            "value {value:e} ({:#x}) at {decimals} decimals",
            value.to_bits()
        );
    }

    /// The decimals the report writers use and those around the limit of
    /// the exact path.
    fn some_decimals(rng: &mut ChaCha8Rng) -> usize {
        match rng.random_range(0..8) {
            0 => rng.random_range(0..=30),
            1 => 2,
            2 => 3,
            3 => 4,
            4 => 6,
            _ => rng.random_range(0..=MAX_EXACT_DECIMALS),
        }
    }

    #[test]
    fn hand_picked_values_match_format() {
        let values = [
            0.0,
            -0.0,
            0.125,
            -0.125,
            0.375,
            2.5,
            3.5,
            0.5,
            1.5,
            -2.5,
            0.0005,
            0.045,
            1e-5,
            -1e-5,
            -0.0004,
            -0.00049999,
            5e-324,
            -5e-324,
            2.2250738585072014e-308,
            1e-300,
            1e15,
            123456.789,
            4503599627370496.5,
            9007199254740993.0,
            1.8446744073709552e19,
            2f64.powi(64).next_down(),
            1e21,
            1e300,
            f64::MAX,
            f64::MIN,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.1,
            0.2,
            0.3,
            0.7,
            9.995,
            9.9949999,
            99.5,
            999.9995,
        ];
        for value in values {
            for decimals in 0..=40 {
                check(value, decimals);
            }
        }
    }

    #[test]
    fn ties_go_to_even() {
        let mut out = String::new();
        push_std_fixed(&mut out, 0.125, 2);
        out.push(' ');
        push_std_fixed(&mut out, 2.5, 0);
        out.push(' ');
        push_std_fixed(&mut out, 0.375, 2);
        out.push(' ');
        push_std_fixed(&mut out, -0.0, 3);
        assert_eq!(out, "0.12 2 0.38 -0.000");
    }

    #[test]
    fn neighbours_of_ties_and_half_ulps_match_format() {
        // k / 2^j are exact ties at j decimals; their neighbours one and two
        // ulps away are just below or above.
        for j in 1..=12u32 {
            let step = 0.5f64.powi(j as i32);
            for k in 0..4096u32 {
                let tie = f64::from(k) * step;
                for value in [tie, tie.next_up(), tie.next_down(), -tie] {
                    check(value, j as usize - 1);
                    check(value, j as usize);
                }
            }
        }
    }

    #[test]
    fn decimal_grid_neighbours_match_format() {
        // Values nearest to x.xxx5 at a random number of decimals, and their
        // neighbours: the hardest inputs for the remainder comparison.
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_f1c5);
        for _ in 0..1_000_000 {
            let decimals = rng.random_range(0..=8usize);
            let units = rng.random_range(-10_000_000i64..10_000_000) as f64 + 0.5;
            let value = units / 10f64.powi(decimals as i32);
            let value = match rng.random_range(0..3) {
                0 => value.next_down(),
                1 => value.next_up(),
                _ => value,
            };
            check(value, decimals);
        }
    }

    #[test]
    fn random_bit_patterns_match_format() {
        let mut rng = ChaCha8Rng::seed_from_u64(0xf1_7ed);
        for _ in 0..2_000_000 {
            let value = f64::from_bits(rng.random::<u64>());
            let decimals = some_decimals(&mut rng);
            check(value, decimals);
        }
    }

    #[test]
    fn random_report_sized_values_match_format() {
        // Pixel coordinates, millimetres and times: magnitudes 1e-9 to 1e7.
        let mut rng = ChaCha8Rng::seed_from_u64(0xc0_0d5);
        for _ in 0..2_000_000 {
            let magnitude = 10f64.powi(rng.random_range(-9..=7));
            let value = (rng.random::<f64>() * 2.0 - 1.0) * magnitude;
            let decimals = some_decimals(&mut rng);
            check(value, decimals);
        }
    }
}
