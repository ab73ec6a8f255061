//! Correct digits, as the Bari "Test Set for IVP Solvers" counts them (Mazzia & Magherini):
//!
//! - `scd` = −log10(max over the components of |x − x_exact| / |x_exact|), significant correct
//!   digits (components whose exact value is 0 are left out: their relative error has no scale);
//! - `mescd` = −log10(max over the components of |x − x_exact| / (atol/rtol + |x_exact|)), mixed
//!   error significant correct digits (atol/rtol = 1 for data without tolerances),
//!
//! at the last sample, and their smallest values over all samples (`scd_min`, `mescd_min`). The
//! components are the nine of the state x = (ω, α, β); the errors are taken at the precision of
//! the reference. A sample without error has unbounded digits (+∞, `null` in JSON).

use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::{Real, State};
use rug::Float;
use serde::{Deserialize, Deserializer, Serialize};

/// The four digit counts of a run (top-level keys of the compare/check JSON, columns of bench).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectDigits {
    /// Significant correct digits at the last sample.
    #[serde(deserialize_with = "inf_if_null")]
    pub scd: f64,
    /// Mixed error significant correct digits at the last sample.
    #[serde(deserialize_with = "inf_if_null")]
    pub mescd: f64,
    /// The smallest `scd` over the samples.
    #[serde(deserialize_with = "inf_if_null")]
    pub scd_min: f64,
    /// The smallest `mescd` over the samples.
    #[serde(deserialize_with = "inf_if_null")]
    pub mescd_min: f64,
}

impl Default for CorrectDigits {
    /// No sample yet: no error, unbounded digits.
    fn default() -> Self {
        Self {
            scd: f64::INFINITY,
            mescd: f64::INFINITY,
            scd_min: f64::INFINITY,
            mescd_min: f64::INFINITY,
        }
    }
}

/// JSON writes +∞ (no error) as null: read it back as +∞.
fn inf_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Option::<f64>::deserialize(d).map(|x| x.unwrap_or(f64::INFINITY))
}

/// The relative and the mixed error of one sample: (max |Δ|/|y|, max |Δ|/(ratio + |y|)) over
/// the nine components, `ratio` = atol/rtol.
pub fn sample_errors(exact: &State<Float>, state: &State<Float>, ratio: f64) -> (f64, f64) {
    let (x, y) = (state.to_array(), exact.to_array());
    let mut relative = 0.0f64;
    let mut mixed = 0.0f64;
    for (x, y) in x.iter().zip(y.iter()) {
        let d = Float::with_val(y.prec(), x - y).abs();
        let size = Float::with_val(y.prec(), y.abs_ref());
        if !size.is_zero() {
            relative = relative.max(Float::with_val(y.prec(), &d / &size).to_f64());
        }
        let scale = size + ratio;
        mixed = mixed.max((d / scale).to_f64());
    }
    (relative, mixed)
}

/// [`sample_errors`] of an f64 sample `x` against the exact state in double-double (the
/// reference of f64 data: the same two numbers but within 2⁻¹⁰⁰ of an f64 rounding boundary).
#[inline(always)]
pub fn sample_errors_dd(exact: &State<DoubleDouble>, x: &[f64; 9], ratio: f64) -> (f64, f64) {
    let y = exact.to_array();
    let d: [DoubleDouble; 9] =
        std::array::from_fn(|k| (DoubleDouble::from_f64_exact(x[k]) - y[k]).abs());
    of_differences(&d, &y, ratio)
}

/// [`sample_errors_dd`] from the differences d = |x − y| (in double-double) and the exact
/// state y.
#[inline(always)]
pub(crate) fn of_differences(
    d: &[DoubleDouble; 9],
    y: &[DoubleDouble; 9],
    ratio: f64,
) -> (f64, f64) {
    // Plain loops, no closure handed to a library function (compiled with the caller's FMA).
    let mut size = [DoubleDouble::ZERO; 9];
    let mut scale = [DoubleDouble::ZERO; 9];
    for k in 0..9 {
        size[k] = y[k].abs();
        scale[k] = size[k].add_f64(ratio);
    }
    of_sizes(d, &size, &scale)
}

/// [`of_differences`] from the differences d, the sizes |y| and the scales |y| + atol/rtol.
#[inline(always)]
pub(crate) fn of_sizes(
    d: &[DoubleDouble; 9],
    size: &[DoubleDouble; 9],
    scale: &[DoubleDouble; 9],
) -> (f64, f64) {
    // Relative errors of 0 size have no scale: left out.
    let relative = largest_quotient(d, size, |k| size[k].to_f64() != 0.0);
    let mixed = largest_quotient(d, scale, |_| true);
    (relative, mixed)
}

/// max over the components `k` with `counted(k)` of d/s in double-double rounded to f64 (0
/// for none). Each quotient is evaluated in double-double only where its f64 estimate
/// d.hi/s.hi (relative error below 2⁻⁵⁰) is within 2⁻⁴⁸ of the largest estimate: the others
/// are smaller, so the maximum is the same number, at a fraction of the divisions.
#[inline(always)]
fn largest_quotient(
    d: &[DoubleDouble; 9],
    s: &[DoubleDouble; 9],
    counted: impl Fn(usize) -> bool,
) -> f64 {
    let mut estimate = [0.0f64; 9];
    let mut top = 0.0f64;
    for k in 0..9 {
        estimate[k] = d[k].hi / s[k].hi;
        if counted(k) {
            top = top.max(estimate[k]);
        }
    }
    // Near the underflow or for a non-finite quotient the estimate is not trusted.
    let trusted = top.is_finite() && top > 1e-280;
    let floor = top * (1.0 - 2f64.powi(-48));
    let mut largest = 0.0f64;
    for k in 0..9 {
        if counted(k) && (!trusted || estimate[k] >= floor) {
            largest = largest.max((d[k] / s[k]).to_f64());
        }
    }
    largest
}

/// −log10 of an error: +∞ for no error.
fn digits_of(error: f64) -> f64 {
    -error.log10()
}

/// Digits of a run taken one sample at a time (bounded memory).
#[derive(Clone, Copy, Debug)]
pub struct DigitsTracker {
    ratio: f64,
    worst: (f64, f64),
    last: (f64, f64),
}

impl DigitsTracker {
    /// `rtol`, `atol` of the integrator (none: atol/rtol = 1).
    pub fn new(rtol: Option<f64>, atol: Option<f64>) -> Self {
        let ratio = match (rtol, atol) {
            (Some(r), Some(a)) if r > 0.0 && a.is_finite() && a >= 0.0 => a / r,
            _ => 1.0,
        };
        Self {
            ratio,
            worst: (0.0, 0.0),
            last: (0.0, 0.0),
        }
    }

    /// Add the next sample.
    pub fn sample(&mut self, exact: &State<Float>, state: &State<Float>) {
        self.add(sample_errors(exact, state, self.ratio));
    }

    /// Add the next sample's relative and mixed errors ([`sample_errors`] with
    /// [`DigitsTracker::ratio`]).
    pub fn add(&mut self, errors: (f64, f64)) {
        self.last = errors;
        self.worst = (self.worst.0.max(self.last.0), self.worst.1.max(self.last.1));
    }

    /// atol/rtol of the mixed error.
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// The digits so far.
    pub fn summary(&self) -> CorrectDigits {
        CorrectDigits {
            scd: digits_of(self.last.0),
            mescd: digits_of(self.last.1),
            scd_min: digits_of(self.worst.0),
            mescd_min: digits_of(self.worst.1),
        }
    }
}

/// Digits of whole trajectories (`states` against `reference`, same length), `ratio` = atol/rtol.
pub fn correct_digits(
    reference: &[State<Float>],
    states: &[State<Float>],
    rtol: Option<f64>,
    atol: Option<f64>,
) -> CorrectDigits {
    let mut t = DigitsTracker::new(rtol, atol);
    for (y, x) in reference.iter().zip(states) {
        t.sample(y, x);
    }
    t.summary()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The digits of f64 data against double-double, every quotient evaluated (what
    /// `largest_quotient` skips some of).
    fn every_quotient(exact: &State<DoubleDouble>, x: &[f64; 9], ratio: f64) -> (f64, f64) {
        let y = exact.to_array();
        let (mut relative, mut mixed) = (0.0f64, 0.0f64);
        for (x, y) in x.iter().zip(y.iter()) {
            let d = (DoubleDouble::from_f64_exact(*x) - *y).abs();
            let size = y.abs();
            if size.to_f64() != 0.0 {
                relative = relative.max((d / size).to_f64());
            }
            mixed = mixed.max((d / size.add_f64(ratio)).to_f64());
        }
        (relative, mixed)
    }

    /// The quotients skipped by their f64 estimate never change the digits: bit for bit on
    /// 20 000 random samples, with errors from 1e-18 to 1e-2, exact zeros, components of equal
    /// quotients and quotients a few ulps apart.
    #[test]
    fn digits_of_f64_data_are_those_of_every_quotient() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in 0..20_000 {
            let mut y = [DoubleDouble::from_f64_exact(0.0); 9];
            let mut x = [0.0; 9];
            for k in 0..9 {
                let hi = 4.0 * uniform() - 2.0;
                let lo = hi * 1e-17 * (uniform() - 0.5);
                y[k] = DoubleDouble::from_f64_exact(hi).add_f64(lo);
                let error = 10f64.powf(-18.0 + 16.0 * uniform()) * (uniform() - 0.5);
                x[k] = hi + error;
            }
            match n % 4 {
                // An exact zero component.
                1 => (y[4], x[4]) = (DoubleDouble::from_f64_exact(0.0), 1e-12 * uniform()),
                // Two components with the same quotient.
                2 => (y[7], x[7]) = (y[2], x[2]),
                // Quotients a few ulps apart.
                3 => (y[5], x[5]) = (y[1], f64::from_bits(x[1].to_bits() + 1)),
                _ => {}
            }
            let exact = State::from_slice(&y);
            let ratio = [1.0, 1e-3, 0.0][n % 3];
            let fast = sample_errors_dd(&exact, &x, ratio);
            let slow = every_quotient(&exact, &x, ratio);
            assert_eq!(
                (fast.0.to_bits(), fast.1.to_bits()),
                (slow.0.to_bits(), slow.1.to_bits()),
                "sample {n}: {fast:?} vs {slow:?}"
            );
        }
    }

    fn state(values: [f64; 9]) -> State<Float> {
        let f = |k: usize| Float::with_val(200, values[k]);
        State {
            omega: [f(0), f(1), f(2)],
            alpha: [f(3), f(4), f(5)],
            beta: [f(6), f(7), f(8)],
        }
    }

    /// Hand-worked: exact (2, 0, 0.5, 1, …), errors 2e-6 on the 2 (relative 1e-6), 1e-9 on the
    /// exact 0 (no relative error; mixed 1e-9/ratio), 5e-8 on the 0.5 (relative 1e-7).
    #[test]
    fn digits_of_a_hand_worked_sample_and_the_worst_over_samples() {
        let y = state([2.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        let x = state([2.0 + 2e-6, 1e-9, 0.5 + 5e-8, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        let (rel, mixed) = sample_errors(&y, &x, 1.0);
        assert!((rel - 1e-6).abs() < 1e-15, "{rel:e}");
        // max(2e-6 / 3, 1e-9 / 1, 5e-8 / 1.5) = 6.67e-7.
        assert!((mixed - 2e-6 / 3.0).abs() < 1e-15, "{mixed:e}");
        // atol/rtol = 1e-3: the exact 0 dominates, 1e-9 / 1e-3 = 1e-6 > 2e-6 / 2.001.
        let (_, mixed) = sample_errors(&y, &x, 1e-3);
        assert!((mixed - 1e-6).abs() < 1e-15, "{mixed:e}");

        let mut t = DigitsTracker::new(Some(1e-9), Some(1e-12));
        assert_eq!(t.summary().scd, f64::INFINITY);
        t.sample(&y, &x);
        t.sample(&y, &y);
        let d = t.summary();
        assert_eq!(
            (d.scd, d.mescd),
            (f64::INFINITY, f64::INFINITY),
            "last exact"
        );
        assert!((d.scd_min - 6.0).abs() < 1e-9, "{d:?}");
        assert!((d.mescd_min - 6.0).abs() < 1e-9, "{d:?}");
        let json = serde_json::to_string(&d).unwrap();
        let back: CorrectDigits = serde_json::from_str(&json).unwrap();
        assert_eq!(back, d, "{json}");
    }
}
