//! The exact motion at times the caller chooses, with H, K, G per time: the rows of
//! `rsts reference` and of the Python package's `Case.reference` (one computation for both).
//!
//! The closed form is evaluated at the requested digits (default 30) plus
//! [`REFERENCE_GUARD_BITS`] and each value rounded once, to f64 or to the requested digits.
//! For f64 output the rows come from the double-double closed form, correctly rounded
//! ([`crate::rounded_reference`]): the same bits at a tenth of the cost.

use rug::Float;

use rsts_dynamics::scalar::bits_for_digits;

use crate::analysis::{Analysis, RunInfo};
use crate::case::Case;
use crate::rounded_reference::{integrals_on_n, integrals_on_n_exact, DdReference, VALUES};
use crate::{HarnessError, MAX_SAMPLES, REFERENCE_GUARD_BITS};

/// Names of the 13 values of a row: t, the state (ω, α, β in the body frame), H, K, G.
pub const COLUMNS: [&str; 13] = [
    "t", "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
    "H", "K", "G",
];

/// Digits a reference may carry (without: f64, correctly rounded).
pub const DIGITS: std::ops::RangeInclusive<u32> = 18..=10_000;

/// Check requested times: at least one, at most [`MAX_SAMPLES`], finite, strictly increasing.
/// The message names no option (the caller puts `--times:` or `times:` in front).
pub fn check_times(times: &[f64]) -> Result<(), String> {
    if times.is_empty() {
        return Err("no times".into());
    }
    if times.len() > MAX_SAMPLES {
        return Err(format!(
            "at most {MAX_SAMPLES} times are supported, got {}",
            times.len()
        ));
    }
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!(
            "time {} must be a finite number, got {}",
            k + 1,
            times[k]
        ));
    }
    for (k, w) in times.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(format!(
                "times must be strictly increasing: time {} ({}) does not come after {}",
                k + 2,
                rsts_dynamics::shown(w[1]),
                rsts_dynamics::shown(w[0])
            ));
        }
    }
    Ok(())
}

/// Check requested digits (`None`: f64).
pub fn check_digits(digits: Option<i64>) -> Result<Option<u32>, String> {
    match digits {
        None => Ok(None),
        Some(d) => match u32::try_from(d) {
            Ok(d) if DIGITS.contains(&d) => Ok(Some(d)),
            _ => Err(format!(
                "must be between {} and {} (without it: f64), got {d}",
                DIGITS.start(),
                DIGITS.end()
            )),
        },
    }
}

/// The exact motion of a case, ready to be evaluated at any of the times it was built for.
pub struct ReferenceTable {
    analysis: Analysis,
    bits: u32,
    digits: Option<u32>,
    /// The double-double closed form for f64 output.
    fast: Option<DdReference>,
    /// H, K, G of f64 output.
    integrals_f64: [f64; 3],
    /// H, K, G at the reference precision: constants of N, computed once.
    integrals: [Float; 3],
}

impl ReferenceTable {
    /// The motion of `case` (its a, b, m, h, torus and phases; not its grid), built for the
    /// largest |t| of `times` (its phase clock carries the bits that time needs), at `digits`
    /// (checked with [`check_digits`]; `None`: f64 output).
    pub fn new(case: &Case, times: &[f64], digits: Option<u32>) -> Result<Self, HarnessError> {
        let t_max = times.iter().fold(0.0, |m: f64, t| m.max(t.abs()));
        Self::for_reach(case, t_max, digits)
    }

    /// [`Self::new`] for times of magnitude up to `t_max`.
    pub fn for_reach(case: &Case, t_max: f64, digits: Option<u32>) -> Result<Self, HarnessError> {
        let bits = bits_for_digits(digits.unwrap_or(30)) + REFERENCE_GUARD_BITS;
        let reach = rsts_closed_form::Decimal::from_f64(t_max)
            .map_err(|e| HarnessError::Data(format!("times: {e}")))?;
        let case = case.with_grid(reach, 1);
        case.validate()?;
        let info = RunInfo {
            method: "reference".into(),
            rtol: None,
            atol: None,
            digits: digits.unwrap_or(15),
        };
        let analysis = Analysis::for_case(&case, bits, info)?;
        let mut table = Self {
            analysis,
            bits,
            digits,
            fast: None,
            integrals_f64: integrals_on_n(&case),
            integrals: integrals_on_n_exact(&case).map(|x| Float::with_val(bits, x)),
        };
        if digits.is_none() {
            table.fast = DdReference::new(&case, t_max, |t| table.mpfr_values(t));
        }
        Ok(table)
    }

    /// The state at t at the reference precision.
    fn mpfr_values(&self, t: f64) -> [Float; VALUES] {
        self.analysis
            .exact_state(&Float::with_val(self.bits, t))
            .to_array()
    }

    /// The row at `t` in f64 ([`COLUMNS`]): the state of [`Self::row`] rounded, bit for bit,
    /// from the double-double closed form where Ziv's test decides every value (else from
    /// MPFR); H, K, G the constants of N correctly rounded ([`integrals_on_n`]).
    pub fn row_f64(&self, t: f64) -> Result<[f64; 13], String> {
        let mut row = [t; 13];
        match self.fast.as_ref().and_then(|f| f.rounded(t)) {
            Some(v) => row[1..10].copy_from_slice(&v),
            None => {
                let r = self.row(t)?;
                for k in 1..10 {
                    row[k] = r[k].to_f64();
                }
            }
        }
        row[10..].copy_from_slice(&self.integrals_f64);
        Ok(row)
    }

    /// The state at t from the double-double closed form rounded to f64, `None` where
    /// Ziv's test leaves one undecided (or without a double-double motion).
    pub fn dd_rounded(&self, t: f64) -> Option<[f64; VALUES]> {
        self.fast.as_ref()?.rounded(t)
    }

    /// Whether f64 rows come from the double-double closed form.
    pub fn has_dd(&self) -> bool {
        self.fast.is_some()
    }

    /// The analysis holding the motion (its camera, fields).
    pub fn analysis(&self) -> &Analysis {
        &self.analysis
    }

    /// The digits of the output (`None`: f64).
    pub fn digits(&self) -> Option<u32> {
        self.digits
    }

    /// Bits of the reference precision (a time given to [`Self::row_at`] should carry at least
    /// as many, plus those of its integer part).
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// [`Self::row_f64`] at a time that is not an f64 (`t` exact to the reference precision):
    /// the state there rounded from MPFR, shown at `shown` (the f64 nearest `t`).
    pub fn row_f64_at(&self, t: &Float, shown: f64) -> Result<[f64; 13], String> {
        let r = self.row_at(t)?;
        let mut row = [shown; 13];
        for k in 1..10 {
            row[k] = r[k].to_f64();
        }
        row[10..].copy_from_slice(&self.integrals_f64);
        Ok(row)
    }

    /// The row at `t`: t, the nine components of the state, H, K, G ([`COLUMNS`]), at the
    /// reference precision. H, K, G are the constants of N (H = h, K = r⁴m², G = (p²h + r⁴m)/2
    /// exactly, rounded once), as in f64 rows: the integrals of each row's state agree with them
    /// to the reference precision, at a tenth of a 100-digit row's cost less. A value that is not
    /// finite, or not finite in f64, is an error naming where it appeared, never a number.
    pub fn row(&self, t: f64) -> Result<Vec<Float>, String> {
        self.row_at(&Float::with_val(self.bits, t))
    }

    /// [`Self::row`] at the time `t` (any precision: a decimal time exact to the reference
    /// precision; the row's t is `t`).
    pub fn row_at(&self, t: &Float) -> Result<Vec<Float>, String> {
        // ω, α, β alone (not γ, Ω, Q′, Q″, ω′, ω″): the same values as the whole state's.
        let b = self.analysis.motion().body_at(t);
        let mut row = Vec::with_capacity(COLUMNS.len());
        row.push(t.clone());
        row.extend(b.omega.into_iter().chain(b.alpha).chain(b.beta));
        row.extend(self.integrals.iter().cloned());
        if let Some(c) = row
            .iter()
            .position(|x| !x.is_finite() || !x.to_f64().is_finite())
        {
            return Err(format!(
                "the closed form is not finite at t = {}: {} = {} (outside f64's range)",
                rsts_dynamics::short(t.to_f64()),
                COLUMNS[c],
                row[c].to_f64()
            ));
        }
        Ok(row)
    }

    /// A value as written: its decimal digits at the requested digits, or the shortest text
    /// that reads back to the same f64.
    pub fn text(&self, x: &Float) -> String {
        match self.digits {
            Some(d) => x.to_string_radix(10, Some(d as usize)),
            None => format!("{:?}", x.to_f64()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_must_be_finite_and_strictly_increasing() {
        assert!(check_times(&[0.0, 0.5, 2.0]).is_ok());
        assert!(check_times(&[]).unwrap_err().contains("no times"));
        assert!(check_times(&[0.0, 0.0]).unwrap_err().contains("time 2 (0)"));
        assert!(check_times(&[0.0, f64::NAN])
            .unwrap_err()
            .contains("time 2 must be a finite number"));
    }

    #[test]
    fn rows_are_the_motion_and_its_integrals() {
        let table = ReferenceTable::new(&Case::default_i_plus(), &[0.0, 1.0], None).unwrap();
        let row = table.row(1.0).unwrap();
        assert_eq!(row.len(), COLUMNS.len());
        assert_eq!(row[0].to_f64(), 1.0);
        // H is the case's h.
        assert!((row[10].to_f64() + 0.375).abs() < 1e-25);
        assert_eq!(
            check_digits(Some(17)).unwrap_err(),
            "must be between 18 and 10000 (without it: f64), got 17"
        );
    }
}
