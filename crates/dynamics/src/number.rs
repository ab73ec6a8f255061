//! Numbers as the user wrote them (issue 32, "one motion, one number").
//!
//! A [`Decimal`] is the decimal a user wrote — a command-line option, a suite file, a protocol
//! string, CSV or JSON text, a Python `str` — and means that decimal exactly at every precision:
//! it is rounded once, correctly, to the precision a computation asks for ([`Decimal::to_float`],
//! [`Decimal::to_f64`]). A binary64 value (a Python float, an f64 of an npy or MCAP file) is its
//! exact binary value ([`Decimal::from_f64`] writes it out in full).
//!
//! [`Times`] are sample times: N times evenly spaced on [0, T] with T a decimal (t_k = k·T/(N−1)
//! exactly, rounded once to the precision asked), or a list of decimals or of binary64 values.

use std::fmt;
use std::hash::{Hash, Hasher};

use rug::Float;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::scalar::Real;

/// Longest decimal accepted, in characters (100 000 digits: the most `--digits` accepts).
pub const MAX_DECIMAL_CHARS: usize = 100_100;
/// Decimal exponents of the leading digit accepted: |x| below 1e309 (f64's range) and not below
/// 1e-10000 unless zero.
pub const MIN_DECIMAL_EXPONENT: i64 = -10_000;
pub const MAX_DECIMAL_EXPONENT: i64 = 308;

/// Why a text is not a decimal.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NumberError {
    #[error("'{0}' is not a number")]
    NotANumber(String),
    /// NaN, an infinity, or a decimal beyond f64's range (what it would round to is shown).
    #[error("must be a finite number, got {0}")]
    NotFinite(String),
    #[error("a number of {0} characters is too long (at most {MAX_DECIMAL_CHARS})")]
    TooLong(usize),
    #[error("'{0}' is too small: its leading digit is below 1e{MIN_DECIMAL_EXPONENT} (write 0 for zero)")]
    TooSmall(String),
}

/// A decimal number exactly as written: `-0.52`, `1.3e-2`, `1.30000000000000004440892098500626162`.
///
/// Equality and hashing are by value (`1.30` equals `1.3`); [`Decimal::as_str`] keeps the text.
#[derive(Clone)]
pub struct Decimal {
    /// The text as written (trimmed), or the exact expansion of a binary64 value.
    text: String,
    /// Canonical value: sign, significant digits (no leading or trailing zeros; empty for 0) and
    /// the power of ten of the last digit.
    negative: bool,
    digits: String,
    exponent: i64,
}

impl Decimal {
    /// Read a decimal: an optional sign, digits with an optional point, an optional exponent
    /// (`[eE][+-]?digits`). NaN, infinities, hexadecimal and values beyond f64's range are
    /// refused.
    pub fn parse(text: &str) -> Result<Decimal, NumberError> {
        let s = text.trim();
        if s.len() > MAX_DECIMAL_CHARS {
            return Err(NumberError::TooLong(s.len()));
        }
        let short = || shorten(s);
        let (negative, rest) = match s.as_bytes().first() {
            Some(b'-') => (true, &s[1..]),
            Some(b'+') => (false, &s[1..]),
            _ => (false, s),
        };
        let (mantissa, exp_text) = match rest.find(['e', 'E']) {
            Some(i) => (&rest[..i], Some(&rest[i + 1..])),
            None => (rest, None),
        };
        let (int_part, frac_part) = match mantissa.split_once('.') {
            Some((i, f)) => (i, f),
            None => (mantissa, ""),
        };
        let all_digits = |p: &str| p.bytes().all(|c| c.is_ascii_digit());
        if (int_part.is_empty() && frac_part.is_empty())
            || !all_digits(int_part)
            || !all_digits(frac_part)
        {
            return Err(not_a_number(s));
        }
        let mut exponent: i64 = match exp_text {
            None => 0,
            Some(e) => {
                let body = e.strip_prefix(['+', '-']).unwrap_or(e);
                if body.is_empty() || !all_digits(body) {
                    return Err(NumberError::NotANumber(short()));
                }
                // Exponents beyond ±10^15 are out of every range below; keep them finite.
                let significant = body.trim_start_matches('0');
                let magnitude: i64 = if significant.len() > 15 {
                    i64::MAX / 4
                } else {
                    significant.parse().unwrap_or(0)
                };
                if e.starts_with('-') {
                    -magnitude
                } else {
                    magnitude
                }
            }
        };
        exponent -= frac_part.len() as i64;
        let mut digits: String = int_part.chars().chain(frac_part.chars()).collect();
        let lead = digits.len() - digits.trim_start_matches('0').len();
        digits.drain(..lead);
        let trail = digits.len() - digits.trim_end_matches('0').len();
        digits.truncate(digits.len() - trail);
        exponent += trail as i64;
        if digits.is_empty() {
            return Ok(Decimal {
                text: s.to_string(),
                negative: false,
                digits,
                exponent: 0,
            });
        }
        let leading = exponent + digits.len() as i64 - 1;
        if leading < MIN_DECIMAL_EXPONENT {
            return Err(NumberError::TooSmall(short()));
        }
        let d = Decimal {
            text: s.to_string(),
            negative,
            digits,
            exponent,
        };
        if leading > MAX_DECIMAL_EXPONENT || !d.to_f64().is_finite() {
            return Err(NumberError::NotFinite(short()));
        }
        Ok(d)
    }

    /// The exact value of a binary64 number, written out in full (`0.1` →
    /// `0.1000000000000000055511151231257827021181583404541015625`). NaN and infinities are
    /// refused.
    pub fn from_f64(x: f64) -> Result<Decimal, NumberError> {
        if !x.is_finite() {
            return Err(NumberError::NotFinite(format!("{x}")));
        }
        let bits = x.to_bits();
        let negative = bits >> 63 == 1 && x != 0.0;
        let biased = ((bits >> 52) & 0x7ff) as i64;
        let fraction = bits & ((1u64 << 52) - 1);
        let (mantissa, power_of_two) = if biased == 0 {
            (fraction, -1074)
        } else {
            (fraction | (1u64 << 52), biased - 1075)
        };
        // x = mantissa · 2^p; for p < 0 that is mantissa · 5^(−p) · 10^p.
        let mut big = BigDigits::from_u64(mantissa);
        let exponent = if power_of_two >= 0 {
            for _ in 0..power_of_two {
                big.mul_small(2);
            }
            0
        } else {
            for _ in 0..-power_of_two {
                big.mul_small(5);
            }
            power_of_two
        };
        let digits = big.to_decimal_string();
        let significant = digits.trim_end_matches('0');
        let exponent = exponent + (digits.len() - significant.len()) as i64;
        let text = if significant.is_empty() {
            "0".to_string()
        } else {
            render(negative, significant, exponent)
        };
        Ok(Decimal::parse(&text).expect("an f64 written out is a decimal"))
    }

    /// The shortest decimal that rounds to `x` (what `{x:?}` prints): the number a JSON or TOML
    /// reader saw when the text is gone. NaN and infinities are refused.
    pub fn shortest(x: f64) -> Result<Decimal, NumberError> {
        if !x.is_finite() {
            return Err(NumberError::NotFinite(format!("{x}")));
        }
        Decimal::parse(&format!("{x:?}"))
    }

    /// A whole number.
    pub fn from_integer(n: i64) -> Decimal {
        Decimal::parse(&n.to_string()).expect("an integer is a decimal")
    }

    /// The text as written.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The nearest f64 (correctly rounded, ties to even).
    pub fn to_f64(&self) -> f64 {
        self.text.parse().unwrap_or(f64::NAN)
    }

    /// The value rounded once to `bits` bits (correctly rounded, ties to even).
    pub fn to_float(&self, bits: u32) -> Float {
        Float::with_val(
            bits,
            Float::parse(&self.text).expect("a checked decimal parses"),
        )
    }

    /// The value in the scalar `T` at `bits` bits (f64: [`Decimal::to_f64`]; MPFR:
    /// [`Decimal::to_float`]; double-double: rounded from MPFR).
    pub fn to_real<T: Real>(&self, bits: u32) -> T {
        T::parse(&self.text, bits).expect("a checked decimal parses")
    }

    /// True when the value is a binary64 number exactly (the decimal is f64's exact value).
    pub fn is_binary64(&self) -> bool {
        Decimal::from_f64(self.to_f64()).is_ok_and(|d| d == *self)
    }

    /// True for zero.
    pub fn is_zero(&self) -> bool {
        self.digits.is_empty()
    }

    /// True for a value below zero.
    pub fn is_negative(&self) -> bool {
        self.negative
    }

    /// Significant digits of the value (0 for zero).
    pub fn significant_digits(&self) -> usize {
        self.digits.len()
    }

    /// The value as the canonical integer significand and power of ten: (negative, digits,
    /// exponent) with x = ±digits·10^exponent.
    pub fn parts(&self) -> (bool, &str, i64) {
        (self.negative, &self.digits, self.exponent)
    }
}

fn not_a_number(s: &str) -> NumberError {
    let lower = s.to_ascii_lowercase();
    let word = lower.trim_start_matches(['+', '-']);
    if matches!(word, "nan" | "inf" | "infinity") {
        let x: f64 = s.parse().unwrap_or(f64::NAN);
        NumberError::NotFinite(format!("{x}"))
    } else {
        NumberError::NotANumber(shorten(s))
    }
}

/// A value for a message: at most 40 characters (longer text is cut in the middle).
pub fn shorten(s: &str) -> String {
    const MAX: usize = 40;
    if s.chars().count() <= MAX {
        return s.to_string();
    }
    let head: String = s.chars().take(24).collect();
    let tail: String = {
        let v: Vec<char> = s.chars().collect();
        v[v.len() - 12..].iter().collect()
    };
    format!("{head}…{tail} ({} characters)", s.chars().count())
}

/// Plain notation for moderate exponents, scientific beyond.
fn render(negative: bool, digits: &str, exponent: i64) -> String {
    let sign = if negative { "-" } else { "" };
    let n = digits.len() as i64;
    let point = n + exponent; // digits before the decimal point
    if exponent >= 0 && point <= 40 {
        format!("{sign}{digits}{}", "0".repeat(exponent as usize))
    } else if exponent < 0 && point > 0 {
        let (i, f) = digits.split_at(point as usize);
        format!("{sign}{i}.{f}")
    } else if exponent < 0 && point > -30 {
        format!("{sign}0.{}{digits}", "0".repeat((-point) as usize))
    } else {
        let (first, rest) = digits.split_at(1);
        let sep = if rest.is_empty() { "" } else { "." };
        format!("{sign}{first}{sep}{rest}e{}", point - 1)
    }
}

/// A non-negative integer in base 10⁹ limbs (least significant first), for writing out a
/// binary64 value exactly.
struct BigDigits(Vec<u32>);

impl BigDigits {
    const BASE: u64 = 1_000_000_000;

    fn from_u64(mut x: u64) -> Self {
        let mut limbs = Vec::new();
        while x > 0 {
            limbs.push((x % Self::BASE) as u32);
            x /= Self::BASE;
        }
        BigDigits(limbs)
    }

    fn mul_small(&mut self, k: u32) {
        let mut carry = 0u64;
        for limb in &mut self.0 {
            let v = u64::from(*limb) * u64::from(k) + carry;
            *limb = (v % Self::BASE) as u32;
            carry = v / Self::BASE;
        }
        while carry > 0 {
            self.0.push((carry % Self::BASE) as u32);
            carry /= Self::BASE;
        }
    }

    fn to_decimal_string(&self) -> String {
        let Some((last, rest)) = self.0.split_last() else {
            return "0".to_string();
        };
        let mut s = last.to_string();
        for limb in rest.iter().rev() {
            s.push_str(&format!("{limb:09}"));
        }
        s
    }
}

impl PartialEq for Decimal {
    fn eq(&self, other: &Self) -> bool {
        self.negative == other.negative
            && self.exponent == other.exponent
            && self.digits == other.digits
    }
}
impl Eq for Decimal {}

impl Hash for Decimal {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.negative.hash(state);
        self.digits.hash(state);
        self.exponent.hash(state);
    }
}

impl fmt::Display for Decimal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

impl fmt::Debug for Decimal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Decimal({})", self.text)
    }
}

impl std::str::FromStr for Decimal {
    type Err = NumberError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Decimal::parse(s)
    }
}

impl Default for Decimal {
    fn default() -> Self {
        Decimal::from_integer(0)
    }
}

impl From<i32> for Decimal {
    fn from(n: i32) -> Self {
        Decimal::from_integer(i64::from(n))
    }
}

/// In a report a decimal is a JSON number: its nearest f64 (the reports' figures are f64; the
/// exact text travels where it is computed with: the `--exec` request, the motion itself).
impl Serialize for Decimal {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(self.to_f64())
    }
}

/// A JSON or TOML string is read as the decimal it holds; a number, whose text the reader no
/// longer has, as the shortest decimal that rounds to it (the text as written for up to 15
/// significant digits; write longer decimals as strings).
impl<'de> Deserialize<'de> for Decimal {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Decimal;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a decimal string")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Decimal, E> {
                Decimal::parse(v).map_err(E::custom)
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Decimal, E> {
                Decimal::shortest(v).map_err(E::custom)
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Decimal, E> {
                Ok(Decimal::from_integer(v))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Decimal, E> {
                Decimal::parse(&v.to_string()).map_err(E::custom)
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// Sample times.
#[derive(Clone, Debug, PartialEq)]
pub enum Times {
    /// N ≥ 1 times evenly spaced on [0, T]: t_k = k·T/(N−1) exactly (N = 1: t = 0).
    Grid { t_end: Decimal, samples: usize },
    /// Times as written (decimals).
    Decimals(Vec<Decimal>),
    /// Binary64 times (their exact values).
    Binary(Vec<f64>),
}

impl Times {
    /// N evenly spaced times on [0, T].
    pub fn grid(t_end: Decimal, samples: usize) -> Times {
        Times::Grid { t_end, samples }
    }

    /// Number of times.
    pub fn len(&self) -> usize {
        match self {
            Times::Grid { samples, .. } => *samples,
            Times::Decimals(v) => v.len(),
            Times::Binary(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The k-th time rounded once (correctly, ties to even) to `bits` bits.
    pub fn time(&self, k: usize, bits: u32) -> Float {
        match self {
            Times::Grid { t_end, samples } => grid_time(t_end, *samples, k, bits),
            Times::Decimals(v) => v[k].to_float(bits),
            Times::Binary(v) => Float::with_val(bits, v[k]),
        }
    }

    /// The k-th time rounded once to f64.
    pub fn time_f64(&self, k: usize) -> f64 {
        match self {
            Times::Binary(v) => v[k],
            Times::Decimals(v) => v[k].to_f64(),
            Times::Grid { .. } => self.time(k, 53).to_f64(),
        }
    }

    /// Every time rounded to f64.
    pub fn to_f64s(&self) -> Vec<f64> {
        (0..self.len()).map(|k| self.time_f64(k)).collect()
    }

    /// The last time (rounded to f64), 0 for no times.
    pub fn last_f64(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            self.time_f64(self.len() - 1)
        }
    }
}

/// k·T/(N−1) rounded once to `bits` bits: numerator k·D and denominator (N−1)·10^(−e) (or k·D·10^e
/// over N−1) are integers held exactly, so the one division rounds correctly.
fn grid_time(t_end: &Decimal, samples: usize, k: usize, bits: u32) -> Float {
    assert!(k < samples.max(1), "time {k} of a grid of {samples}");
    if samples <= 1 || k == 0 || t_end.is_zero() {
        return Float::with_val(bits, 0);
    }
    if k + 1 == samples {
        return t_end.to_float(bits);
    }
    let (negative, digits, exponent) = t_end.parts();
    // Bits that hold the integers exactly: digits·log2(10) + the factors.
    let int_bits =
        |decimal_digits: usize| (decimal_digits as f64 * std::f64::consts::LOG2_10) as u32 + 70;
    let d = Float::with_val(
        int_bits(digits.len()),
        Float::parse(digits).expect("digits"),
    );
    let ten_power = |e: i64| {
        let p = int_bits(e as usize + 1);
        Float::with_val(p, Float::parse(format!("1e{e}")).expect("a power of ten"))
    };
    let kf = k as f64; // exact: k < 2^53
    let nf = (samples - 1) as f64;
    let mut num = Float::with_val(d.prec() + 64, &d * kf);
    let mut den = Float::with_val(64, nf);
    if exponent >= 0 {
        let t = ten_power(exponent);
        num = Float::with_val(num.prec() + t.prec(), &num * &t);
    } else {
        let t = ten_power(-exponent);
        den = Float::with_val(den.prec() + t.prec(), &den * &t);
    }
    let mut t = Float::with_val(bits, &num / &den);
    if negative {
        t = -t;
    }
    t
}

#[cfg(test)]
mod tests;
