//! Samples read from outside (a file, a process's answer): values as they were written, then
//! converted to high-precision numbers by one rule.
//!
//! **The precision rule.** A trajectory whose values all have at most 17 significant digits is
//! taken as `f64` data: each value is the `f64` nearest to its decimal text (what any program
//! that prints `f64`s with round-trip precision meant), widened exactly. A trajectory with any
//! longer value is high-precision data: its decimal texts are read exactly at the reference
//! precision (and JSON numbers, which are `f64` by nature, exactly as `f64`).

use rsts_dynamics::State;
use rug::Float;

/// Significant digits above which a value is read as a high-precision decimal.
pub const F64_TEXT_DIGITS: usize = 17;
/// Most significant digits a value may carry: what the reference can use (`check --digits` and
/// an adapter's request go up to 10000). A longer value is refused before it is parsed.
pub const MAX_TEXT_DIGITS: usize = 10_000;

/// One number as it was written.
#[derive(Clone, Debug, PartialEq)]
pub enum Number {
    /// A binary64 value (a JSON number, an npy float64, an MCAP field).
    F64(f64),
    /// A decimal text (a CSV field, a JSON string), already checked to be a finite number.
    Text(String),
}

impl Number {
    /// Significant digits of a decimal text (0 for an `f64`).
    pub fn digits(&self) -> usize {
        match self {
            Number::F64(_) => 0,
            Number::Text(s) => significant_digits(s),
        }
    }

    /// The value at `bits`: see the module doc for `high` (true: high-precision data).
    pub fn to_float(&self, bits: u32, high: bool) -> Float {
        match self {
            Number::F64(x) => Float::with_val(bits, *x),
            Number::Text(s) if high => {
                Float::with_val(bits, Float::parse(s).expect("checked when read"))
            }
            Number::Text(s) => Float::with_val(bits, s.parse::<f64>().expect("checked when read")),
        }
    }

    /// The value rounded to f64.
    pub fn to_f64(&self) -> f64 {
        match self {
            Number::F64(x) => *x,
            Number::Text(s) => s.parse().expect("checked when read"),
        }
    }
}

/// Digits of the mantissa of a decimal text, leading zeros not counted.
pub fn significant_digits(s: &str) -> usize {
    significant_digits_of_bytes(s.as_bytes())
}

/// [`significant_digits`] of a text's bytes (an ASCII `e` is never part of a longer UTF-8
/// character: the same count).
pub fn significant_digits_of_bytes(s: &[u8]) -> usize {
    let end = s.iter().position(|&b| b == b'e' || b == b'E');
    let mantissa = &s[..end.unwrap_or(s.len())];
    // Counted without a copy: this runs on every value of a file.
    let digits = || mantissa.iter().copied().filter(u8::is_ascii_digit);
    let leading = digits().take_while(|&d| d == b'0').count();
    let all = digits().count();
    (all - leading).max(1)
}

/// Check a decimal text: a finite number (as f64 it may over- or underflow only when it has more
/// than 17 digits and is read exactly). Returns why not.
pub fn check_text(s: &str) -> Result<Number, String> {
    let t_full = s.trim();
    let shown = cut(t_full);
    let t = shown.as_str();
    if t.is_empty() {
        return Err("empty value".into());
    }
    // Counted on the raw text first: a 50 MB field is refused without being parsed.
    if t_full.len() > 2 * MAX_TEXT_DIGITS + 64 || significant_digits(t_full) > MAX_TEXT_DIGITS {
        return Err(format!(
            "'{t}' has more than {MAX_TEXT_DIGITS} significant digits, the most the reference can use"
        ));
    }
    let lower = t_full.to_ascii_lowercase();
    if lower.contains("nan") {
        return Err(format!("'{t}' is not a finite number (NaN)"));
    }
    if lower.contains("inf") {
        return Err(format!("'{t}' is not a finite number (infinite)"));
    }
    match t_full.parse::<f64>() {
        Ok(x) if x.is_finite() => {}
        Ok(_) => return Err(format!("'{t}' overflows (not a finite number)")),
        Err(_) => return Err(format!("'{t}' is not a number")),
    }
    if Float::parse(t_full).is_err() {
        return Err(format!("'{t}' is not a number"));
    }
    Ok(Number::Text(t_full.to_string()))
}

/// A decimal text's value as f64 and its significant digits, checked as [`check_text`] checks
/// it but parsed once: a text of digits, point, sign and exponent that the f64 parser reads is
/// one MPFR reads too (test `one_parse_accepts_what_check_text_accepts`), so it needs no
/// MPFR parse. Errors with [`check_text`]'s message.
pub fn text_f64(s: &str) -> Result<(f64, usize), String> {
    let t = s.trim();
    let digits = significant_digits(t);
    let plain = t.len() <= 2 * MAX_TEXT_DIGITS + 64
        && digits <= MAX_TEXT_DIGITS
        && !t
            .bytes()
            .any(|b| b.is_ascii_alphabetic() && b != b'e' && b != b'E');
    if plain {
        if let Ok(x) = t.parse::<f64>() {
            if x.is_finite() {
                return Ok((x, digits));
            }
        }
    }
    check_text(s).map(|n| (n.to_f64(), n.digits()))
}

/// A value as shown in a message: at most 40 characters (a 50 MB field is not repeated whole).
pub use rsts_io::cut;

/// Check that a state component read from outside is within the stated range
/// ([`rsts_dynamics::state::MAX_COMPONENT`]): a larger value would only make the geometry of
/// the error search without end.
pub fn check_component(n: Number) -> Result<Number, String> {
    let max = rsts_dynamics::state::MAX_COMPONENT;
    let x = n.to_f64();
    if x.abs() > max {
        return Err(format!(
            "{x:e} is outside the range of a state component (|x| <= {max:e}, docs/output.md)"
        ));
    }
    Ok(n)
}

/// A state component of f64 rows that data read from outside may not hold: its row and column
/// (0-based; columns ω₁..β₃ in the order of a row) and why ([`check_f64`], [`check_component`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BadComponent {
    pub row: usize,
    pub column: usize,
    pub why: String,
}

/// The first component of `states` (rows of ω, α, β as f64) that a trajectory read from outside
/// may not hold — not finite, or beyond [`rsts_dynamics::state::MAX_COMPONENT`] — checked by the
/// rule of every file reader and adapter answer ([`check_f64`], then [`check_component`]): the
/// same refusal for arrays given to a library flow and a Python integrator's answers.
pub fn check_f64_states(states: &[[f64; 9]]) -> Result<(), BadComponent> {
    let max = rsts_dynamics::state::MAX_COMPONENT;
    for (row, s) in states.iter().enumerate() {
        // The common case in one test per row; the message from the readers' own checks.
        if s.iter().all(|x| x.abs() <= max) {
            continue;
        }
        for (column, &x) in s.iter().enumerate() {
            if let Err(why) = check_f64(x).and_then(check_component) {
                return Err(BadComponent { row, column, why });
            }
        }
    }
    Ok(())
}

/// Check an f64 value.
pub fn check_f64(x: f64) -> Result<Number, String> {
    if x.is_finite() {
        Ok(Number::F64(x))
    } else {
        Err(format!("{x} is not a finite number"))
    }
}

/// A trajectory as read: one time and nine components (ω, α, β) per sample, each sample with
/// the place it came from (for messages).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RawTrajectory {
    pub times: Vec<Number>,
    pub states: Vec<[Number; 9]>,
    /// Where sample k was read ("line 5", "samples[3]", "row 4", "message 7").
    pub places: Vec<String>,
    /// The cost the file states (a JSON file's `stats` block; nothing for other formats).
    pub stats: rsts_harness::StatedStats,
}

/// A trajectory at a precision, with absolute times.
#[derive(Clone, Debug)]
pub struct Samples {
    pub times: Vec<Float>,
    pub states: Vec<State<Float>>,
    /// The most significant digits of any value (0: all values are f64).
    pub digits: usize,
}

impl RawTrajectory {
    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Add one sample.
    pub fn push(&mut self, t: Number, state: [Number; 9], place: String) {
        self.times.push(t);
        self.states.push(state);
        self.places.push(place);
    }

    /// The most significant digits of any value (0: all binary64).
    pub fn digits(&self) -> usize {
        self.times
            .iter()
            .chain(self.states.iter().flatten())
            .map(Number::digits)
            .max()
            .unwrap_or(0)
    }

    /// True when the precision rule reads the texts exactly (some value has > 17 digits).
    pub fn is_high_precision(&self) -> bool {
        self.digits() > F64_TEXT_DIGITS
    }

    /// Check that times strictly increase, compared as the precision rule reads this whole
    /// trajectory ([`RawTrajectory::check_times_at`]).
    pub fn check_times(&self) -> Result<(), String> {
        self.check_times_at(self.is_high_precision())
    }

    /// Check that times strictly increase as read with the precision rule decided (`high`:
    /// decimal texts read exactly; else as the f64 values they are, [`time_order`]); the
    /// message names the sample's place.
    pub fn check_times_at(&self, high: bool) -> Result<(), String> {
        for k in 1..self.times.len() {
            time_order(&self.times[k - 1], &self.times[k], high, &self.places[k])?;
        }
        Ok(())
    }

    /// The samples at `bits` bits by the precision rule.
    pub fn to_samples(&self, bits: u32) -> Samples {
        self.to_samples_at(bits, self.is_high_precision())
    }

    /// The samples at `bits` bits, decimal texts read exactly when `high` (the precision rule
    /// decided for a whole trajectory of which these samples may be a part).
    pub fn to_samples_at(&self, bits: u32, high: bool) -> Samples {
        Samples {
            times: self.times.iter().map(|t| t.to_float(bits, high)).collect(),
            states: self
                .states
                .iter()
                .map(|s| {
                    let v: Vec<Float> = s.iter().map(|x| x.to_float(bits, high)).collect();
                    State::from_slice(&v)
                })
                .collect(),
            digits: self.digits(),
        }
    }
}

/// Check that the time `t` (at `place`) comes after `previous` in data read by the precision
/// rule as `high` (decimal texts exact) or not (f64 data: each text is the f64 nearest to it,
/// so `0.1` and `0.10000000000000001` are one time, as in an npy file). A time that is not 0
/// but rounds to 0 as f64 is refused in any data (a report would show it as t = 0).
pub(crate) fn time_order(
    previous: &Number,
    t: &Number,
    high: bool,
    place: &str,
) -> Result<(), String> {
    if let Number::Text(s) = t {
        if t.to_f64() == 0.0
            && Float::parse(s.trim()).is_ok_and(|x| !Float::with_val(64, x).is_zero())
        {
            return Err(format!(
                "{place}: t = {} rounds to 0 as f64 (below the smallest positive f64, 4.9e-324): \
                 not a time after t = 0",
                cut(s.trim())
            ));
        }
    }
    let after = if high {
        comes_after(previous, t)
    } else {
        t.to_f64() > previous.to_f64()
    };
    if after {
        return Ok(());
    }
    let mut e = not_after(place, t, previous);
    if !high && t != previous && t.to_f64() == previous.to_f64() {
        e.push_str(&format!(
            "; in f64 data (no value of more than {F64_TEXT_DIGITS} digits) both are the double {:?}",
            t.to_f64()
        ));
    }
    Err(e)
}

/// Whether `b` comes strictly after `a` (decimal texts beyond f64 compared exactly).
pub(crate) fn comes_after(a: &Number, b: &Number) -> bool {
    let (x, y) = (a.to_f64(), b.to_f64());
    if x != y {
        y > x
    } else {
        b.to_float(2000, true) > a.to_float(2000, true)
    }
}

/// The message of a time that does not come after the previous one.
pub(crate) fn not_after(place: &str, t: &Number, previous: &Number) -> String {
    format!(
        "{place}: t = {} does not come after the previous sample's t = {} (times must be strictly increasing)",
        show(t),
        show(previous)
    )
}

fn show(n: &Number) -> String {
    match n {
        Number::F64(x) => format!("{x:?}"),
        Number::Text(s) => cut(s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digits_are_counted_without_sign_point_exponent_or_leading_zeros() {
        assert_eq!(significant_digits("-0.000123e-5"), 3);
        assert_eq!(significant_digits("0.1"), 1);
        assert_eq!(significant_digits("0"), 1);
        assert_eq!(significant_digits("1.2345678901234567"), 17);
        assert_eq!(significant_digits("0.10000000000000000000000000000001"), 32);
    }

    /// The one-parse reading of a text accepts and refuses what check_text does (same message),
    /// with the same value and digits.
    #[test]
    fn one_parse_accepts_what_check_text_accepts() {
        let texts = [
            "",
            " ",
            ".",
            "+",
            "-",
            "e5",
            ".e5",
            "1.",
            "1.e5",
            ".5",
            "+.5",
            "-.5e-3",
            "1e",
            "1e+",
            "1e+5",
            "1E-5",
            "+1",
            "--1",
            "1..2",
            "1e5.0",
            "1e5e5",
            "0x10",
            "1_0",
            "1 0",
            "١",
            "nan",
            "-inf",
            "Infinity",
            "1e400",
            "-1e400",
            "1e-400",
            "4.9e-324",
            "1.7976931348623157e308",
            "0.1",
            " -1.5e-3 ",
            "00012.5",
            "-0.0",
            "1d5",
            "1f",
            "∞",
            "0.10000000000000001",
            "123456789012345678901234567890",
            "1e99999999999999999999",
        ];
        for s in texts {
            let fast = text_f64(s);
            let slow = check_text(s).map(|n| (n.to_f64(), n.digits()));
            assert_eq!(fast, slow, "{s:?}");
        }
        let long = "1".repeat(MAX_TEXT_DIGITS + 1);
        assert_eq!(
            text_f64(&long),
            check_text(&long).map(|n| (0.0, n.digits()))
        );
    }

    #[test]
    fn texts_are_checked() {
        for bad in [
            "",
            "abc",
            "nan",
            "NaN",
            "inf",
            "-Infinity",
            "1e999",
            "1.2.3",
        ] {
            assert!(check_text(bad).is_err(), "{bad:?} accepted");
        }
        assert!(check_text(" -1.5e-3 ").is_ok());
        assert!(check_f64(f64::NAN).is_err());
    }

    /// The first component beyond the bound or not finite, by row then column; 1e8 itself is
    /// held.
    #[test]
    fn states_beyond_the_bound_are_named_by_row_and_column() {
        let mut states = vec![[0.5; 9]; 4];
        states[1][8] = -1e8;
        assert_eq!(check_f64_states(&states), Ok(()));
        states[2][3] = 1e200;
        states[3][0] = f64::NAN;
        let bad = check_f64_states(&states).unwrap_err();
        assert_eq!((bad.row, bad.column), (2, 3));
        assert!(
            bad.why.contains("1e200 is outside the range"),
            "{}",
            bad.why
        );
        states[2][3] = 0.0;
        let bad = check_f64_states(&states).unwrap_err();
        assert_eq!(
            (bad.row, bad.column, bad.why.as_str()),
            (3, 0, "NaN is not a finite number")
        );
    }

    /// Short texts are the f64 they print; a long text makes the whole file exact.
    #[test]
    fn the_precision_rule() {
        let mut raw = RawTrajectory::default();
        let zero = || std::array::from_fn(|_| Number::Text("0.1".into()));
        raw.push(Number::Text("0".into()), zero(), "line 2".into());
        let s = raw.to_samples(200);
        assert_eq!(s.states[0].omega[0], Float::with_val(200, 0.1f64));
        let mut long = zero();
        long[0] = Number::Text("0.100000000000000000000000000000".into());
        raw.push(Number::Text("1".into()), long, "line 3".into());
        assert!(raw.is_high_precision());
        let s = raw.to_samples(200);
        let exact = Float::with_val(200, Float::parse("0.1").unwrap());
        assert_eq!(s.states[0].omega[0], exact);
        assert_ne!(exact, Float::with_val(200, 0.1f64));
    }

    /// f64 data compare their times as f64 (two texts of one double are one time, as npy
    /// has it); high-precision data compare them exactly; a time that rounds to 0 is refused.
    #[test]
    fn times_are_compared_as_the_data_are_read() {
        let z = || std::array::from_fn(|_| Number::F64(0.0));
        let mut raw = RawTrajectory::default();
        raw.push(Number::Text("0.1".into()), z(), "line 2".into());
        raw.push(
            Number::Text("0.10000000000000001".into()),
            z(),
            "line 3".into(),
        );
        let e = raw.check_times().unwrap_err();
        assert!(
            e.starts_with("line 3: t = 0.10000000000000001 does not come after"),
            "{e}"
        );
        assert!(raw.check_times_at(true).is_ok());
        let mut raw = RawTrajectory::default();
        raw.push(Number::Text("0".into()), z(), "line 2".into());
        raw.push(Number::Text("1e-400".into()), z(), "line 3".into());
        for high in [false, true] {
            let e = raw.check_times_at(high).unwrap_err();
            assert!(
                e.starts_with("line 3: t = 1e-400 rounds to 0 as f64"),
                "{e}"
            );
        }
    }

    #[test]
    fn times_must_increase() {
        let mut raw = RawTrajectory::default();
        let z = || std::array::from_fn(|_| Number::F64(0.0));
        raw.push(Number::F64(0.0), z(), "row 1".into());
        raw.push(Number::F64(1.0), z(), "row 2".into());
        assert!(raw.check_times().is_ok());
        raw.push(Number::F64(1.0), z(), "row 3".into());
        let e = raw.check_times().unwrap_err();
        assert!(e.starts_with("row 3: t = 1.0"), "{e}");
    }
}
