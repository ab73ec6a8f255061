//! CSV rows of f64 data read straight from the input's buffer, in one pass over their bytes: a
//! line in the plain shape (ASCII, unquoted values of digits, point, sign and exponent, `\n`
//! or `\r\n` ends) is read without a copy, a UTF-8 check or a string per field. Any other line
//! (blank, comment, quoted, spaced, a value that is not a finite number or out of range, a
//! line not whole in the buffer) is left to the general reader ([`super::csv_row`]), which
//! reads it as before, with its messages: the plain reading accepts a subset of what the
//! general one accepts, with the same values and digits.

use super::f64_rows::Row;
use crate::files::CsvHeader;

/// A field not read (a column beyond the ten).
const SKIP: u8 = u8::MAX;

/// Where each field of a CSV line goes: the column (0: t, 1..=9: ω, α, β) or [`SKIP`].
pub(super) struct Layout {
    column_of: Vec<u8>,
}

impl Layout {
    pub(super) fn of(h: &CsvHeader) -> Self {
        let mut column_of = vec![SKIP; h.fields];
        for (c, &i) in h.index.iter().enumerate() {
            column_of[i] = c as u8;
        }
        Self { column_of }
    }
}

/// The row at the start of `bytes` into `row`, when its line is whole in `bytes` and in the
/// plain shape: the length of the line with its end. `None`: read it the general way.
pub(super) fn plain_row(bytes: &[u8], layout: &Layout, row: &mut Row) -> Option<usize> {
    let max = rsts_dynamics::state::MAX_COMPONENT;
    let mut p = 0;
    let mut digits = 0;
    let last = layout.column_of.len() - 1;
    for (field, &c) in layout.column_of.iter().enumerate() {
        let start = p;
        if c == SKIP {
            // Not read: any ASCII text up to the next comma or line end.
            let n = memchr::memchr2(b',', b'\n', &bytes[p..])?;
            if !bytes[p..p + n].is_ascii() {
                return None;
            }
            p += n;
        } else {
            let (x, d, len) = plain_value(&bytes[p..])?;
            p += len;
            digits = digits.max(d);
            if c == 0 {
                row.t = x;
                row.t_text.clear();
                // SAFETY: the bytes of a value plain_value read.
                row.t_text.push_str(unsafe { ascii(&bytes[start..p]) });
            } else {
                if x.abs() > max {
                    return None;
                }
                row.x[c as usize - 1] = x;
            }
        }
        // The end of `bytes` (a line not whole) or a byte not ASCII: the general way.
        match (*bytes.get(p)?, field == last) {
            (b',', false) => p += 1,
            (b'\n', true) => {
                p += 1;
                break;
            }
            // `\r\n` ends a line; a `\r` elsewhere is part of a field.
            (b'\r', true) if bytes.get(p + 1) == Some(&b'\n') => {
                p += 2;
                break;
            }
            _ => return None,
        }
    }
    row.digits = digits;
    Some(p)
}

/// Powers of ten that are f64 exactly.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The value of the eight decimal digits at `s[i..i + 8]`, if they are digits (eight at a
/// time in one word, as simdjson and fast_float read them).
fn eight_digits(s: &[u8], i: usize) -> Option<u64> {
    let word = u64::from_le_bytes(s.get(i..i + 8)?.try_into().ok()?);
    let below = word.wrapping_sub(0x3030_3030_3030_3030);
    let above = word.wrapping_add(0x4646_4646_4646_4646);
    if (below | above) & 0x8080_8080_8080_8080 != 0 {
        return None;
    }
    // Pairs, then fours, then the eight digits.
    let v = below.wrapping_mul(10).wrapping_add(below >> 8);
    let pairs = 0x0000_00FF_0000_00FF;
    let low = (v & pairs).wrapping_mul(0x000F_4240_0000_0064);
    let high = ((v >> 16) & pairs).wrapping_mul(0x0000_2710_0000_0001);
    Some(u64::from(low.wrapping_add(high).wrapping_shr(32) as u32))
}

/// A value in the plain shape (`[+-]digits[.digits][(e|E)[+-]digits]`, a digit in the
/// mantissa, at most 64 bytes) at the start of `s`, ended by a byte that is not part of it,
/// that is a finite f64: the value, its significant digits (those of
/// [`crate::samples::significant_digits`], the value of [`crate::samples::text_f64`]) and its
/// length. A mantissa of at most 2⁵³ times a power of ten up to 10²² is exact in f64 and is
/// read with one rounding (Clinger's fast path); other mantissas of at most 19 digits by the
/// Eisel–Lemire algorithm ([`super::decimal`]); the rest by `f64::from_str`.
fn plain_value(s: &[u8]) -> Option<(f64, usize, usize)> {
    let negative = s.first() == Some(&b'-');
    let mut i = usize::from(negative || s.first() == Some(&b'+'));
    let mut w: u64 = 0;
    let digit = |i: usize| s.get(i).map(|b| b.wrapping_sub(b'0')).filter(|&d| d < 10);
    let int = i;
    let mut digits = |i: &mut usize| {
        while let Some(v) = eight_digits(s, *i) {
            w = w.wrapping_mul(100_000_000).wrapping_add(v);
            *i += 8;
        }
        while let Some(d) = digit(*i) {
            w = w.wrapping_mul(10).wrapping_add(d as u64);
            *i += 1;
        }
    };
    digits(&mut i);
    let mut all = i - int;
    let mut fraction = 0;
    if s.get(i) == Some(&b'.') {
        i += 1;
        let from = i;
        digits(&mut i);
        fraction = i - from;
        all += fraction;
    }
    if all == 0 {
        return None;
    }
    let mut exponent: i64 = 0;
    if matches!(s.get(i), Some(b'e' | b'E')) {
        i += 1;
        let minus = s.get(i) == Some(&b'-');
        i += usize::from(minus || s.get(i) == Some(&b'+'));
        let from = i;
        while let Some(d) = digit(i) {
            exponent = (10 * exponent + d as i64).min(1 << 40);
            i += 1;
        }
        if i == from {
            return None;
        }
        if minus {
            exponent = -exponent;
        }
    }
    if i > 64 {
        return None;
    }
    // Leading zeros (before and after the point) are not significant.
    let leading = s[int..i]
        .iter()
        .take_while(|&&b| b == b'0' || b == b'.')
        .filter(|&&b| b == b'0')
        .count();
    let significant = (all - leading).max(1);
    let e10 = exponent - fraction as i64;
    let x = if significant <= 19 && w <= 1 << 53 && e10.unsigned_abs() <= 22 {
        let m = w as f64;
        let x = match e10 < 0 {
            true => m / POW10[e10.unsigned_abs() as usize],
            false => m * POW10[e10 as usize],
        };
        if negative {
            -x
        } else {
            x
        }
    } else {
        let fast = (significant <= 19).then(|| super::decimal::decimal_f64(w, e10));
        match fast.flatten() {
            Some(x) if negative => -x,
            Some(x) => x,
            // SAFETY: the bytes read above.
            None => unsafe { ascii(&s[..i]) }.parse().ok()?,
        }
    };
    x.is_finite().then_some((x, significant, i))
}

/// The text of a value [`plain_value`] read, without a second pass over its bytes to check
/// their encoding.
///
/// # Safety
/// `value` is ASCII (as the bytes of a value read by `plain_value` are: its signs, digits,
/// point and exponent letter are matched byte by byte), hence UTF-8.
unsafe fn ascii(value: &[u8]) -> &str {
    debug_assert!(value.is_ascii());
    // SAFETY: ASCII, by the caller's contract.
    unsafe { std::str::from_utf8_unchecked(value) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::samples::{significant_digits, text_f64};

    /// Every text the plain reading accepts, the general one accepts with the same value and
    /// digits; it leaves the others (spaces, quotes, NaN, overflow, hex, ...) to it.
    #[test]
    fn a_plain_value_is_what_text_f64_reads() {
        let plain = [
            "0",
            "-0.0",
            "+1",
            "1.",
            ".5",
            "+.5",
            "-.5e-3",
            "1e5",
            "1E-5",
            "1e+5",
            "00012.5",
            "0.000123e-5",
            "4.9e-324",
            "1e-400",
            "1.7976931348623157e308",
            "0.10000000000000001",
            "-0.17131207221604822",
            "123456789012345678901234567890",
        ];
        for s in plain {
            let text = format!("{s},");
            let (x, d, n) = plain_value(text.as_bytes()).unwrap_or_else(|| panic!("{s:?}"));
            assert_eq!(n, s.len(), "{s:?}");
            let (y, e) = text_f64(s).unwrap_or_else(|m| panic!("{s:?}: {m}"));
            assert_eq!((x.to_bits(), d), (y.to_bits(), e), "{s:?}");
            assert_eq!(d, significant_digits(s), "{s:?}");
        }
        let left = [
            "1e400", "1e", "1e+", ".", "-", "e5", ".e5", "1..2", "1e5.0", "0x10", " 1", "1 ",
            "\"1\"", "nan", "inf", "1d5", "1_0", "", "--1", "1e5e5",
        ];
        for s in left {
            let read = plain_value(format!("{s},").as_bytes());
            assert!(read.is_none_or(|(_, _, n)| n < s.len()), "{s:?}: {read:?}");
        }
        assert_eq!(plain_value(format!("{},", "1".repeat(65)).as_bytes()), None);
    }

    /// 10⁶ random f64 (all bit patterns, and state-like values in [-2, 2]) printed as Rust
    /// prints them (`{:?}`, `{:e}`) and with 15 digits (Clinger's path) are read bit for bit as `f64::from_str`
    /// reads them, with their digits.
    #[test]
    fn plain_values_are_std_bit_for_bit() {
        let mut next = super::super::decimal::tests::xorshift(0x9e37_79b9_7f4a_7c15);
        let mut fast = 0;
        for k in 0..1_000_000 {
            let bits = next();
            let x = match k % 2 {
                0 => f64::from_bits(bits),
                _ => 4.0 * ((bits >> 11) as f64 / (1u64 << 53) as f64) - 2.0,
            };
            if !x.is_finite() {
                continue;
            }
            for text in [format!("{x:?}"), format!("{x:e}"), format!("{x:.14e}")] {
                let line = format!("{text}\n");
                let (y, d, n) = plain_value(line.as_bytes()).unwrap_or_else(|| panic!("{text}"));
                let z: f64 = text.parse().unwrap();
                assert_eq!(
                    (y.to_bits(), d, n),
                    (z.to_bits(), significant_digits(&text), text.len()),
                    "{text}"
                );
                fast += usize::from(d <= 15);
            }
        }
        assert!(fast > 400_000, "{fast}");
    }

    /// A plain line is read whole (its end too); a line not whole, with a quote, a space, a
    /// byte not ASCII, a `\r` in a value, too few or too many fields, or a component beyond the
    /// range is left to the general reading.
    #[test]
    fn plain_rows_and_the_lines_left_to_the_general_reading() {
        let h = CsvHeader::parse(
            1,
            "omega1,t,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3,H",
        )
        .unwrap();
        let layout = Layout::of(&h);
        let mut row = Row::default();
        let line = b"0.1,2.5e1,0.2,0.3,1,0,0,0,1,-0.123456789012345678,x y\r\n0,";
        assert_eq!(plain_row(line, &layout, &mut row), Some(line.len() - 2));
        assert_eq!(
            (row.t, row.t_text.as_str(), row.digits),
            (25.0, "2.5e1", 18)
        );
        assert_eq!(
            row.x,
            [
                0.1,
                0.2,
                0.3,
                1.0,
                0.0,
                0.0,
                0.0,
                1.0,
                "-0.123456789012345678".parse().unwrap()
            ]
        );
        // A field not read may hold any ASCII text.
        let other = b"0.1,2.5,0.2,0.3,1,0,0,0,1,0,x\ry\n";
        assert_eq!(plain_row(other, &layout, &mut row), Some(other.len()));
        for bad in [
            &b"0.1,2.5,0.2,0.3,1,0,0,0,1,0,x"[..],
            b"0.1,\"2.5\",0.2,0.3,1,0,0,0,1,0,x\n",
            b"0.1, 2.5,0.2,0.3,1,0,0,0,1,0,x\n",
            b"0.1,2.5,0.2,0.3,1,0,0,0,1,0,caf\xc3\xa9\n",
            b"0.1,2.5\r,0.2,0.3,1,0,0,0,1,0,x\n",
            b"0.1,2.5,0.2,0.3,1,0,0,0,1,0\n",
            b"0.1,2.5,0.2,0.3,1,0,0,0,1,0,x,y\n",
            b"1e300,2.5,0.2,0.3,1,0,0,0,1,0,x\n",
            b"# 0.1,2.5,0.2,0.3,1,0,0,0,1,0,x\n",
            b"\n",
        ] {
            let text = String::from_utf8_lossy(bad);
            assert_eq!(plain_row(bad, &layout, &mut row), None, "{text:?}");
        }
    }
}
