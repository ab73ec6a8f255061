//! Sample times as the faces give them ([`Times`]: a grid k·T/(N−1) with T a decimal, decimals
//! as written, binary64 values), checked, and each time at the precision a flow computes at.
//!
//! A time means its exact value (a decimal exactly, a binary64 value exactly, a grid time the
//! exact quotient k·T/(N−1)) at every precision. A flow computing at `bits` bits evaluates the
//! motion at the time rounded once to [`time_bits`] (the working precision, 64 guard bits and as
//! many bits as |t| has before its point, so that the phase u̇·t is exact to the working
//! precision however large t is); its f64 outputs are the state at that time, rounded, printed
//! next to the f64 nearest the time.

use std::cmp::Ordering;

use rug::Float;

use rsts_closed_form::{Decimal, Times};
use rsts_harness::MAX_SAMPLES;

/// Guard bits of a time beyond the working precision.
pub const TIME_GUARD_BITS: u32 = 64;

/// Bits a time of magnitude up to `t_max` carries when a flow computes at `bits`.
pub fn time_bits(bits: u32, t_max: f64) -> u32 {
    let whole = if t_max.is_finite() && t_max.abs() > 1.0 {
        t_max.abs().log2().ceil() as u32
    } else {
        0
    };
    bits.max(53) + TIME_GUARD_BITS + whole
}

/// The k-th time, exact to the working precision `bits` (rounded once to [`time_bits`]).
pub fn exact(times: &Times, k: usize, bits: u32) -> Float {
    let t = times.time_f64(k);
    times.time(k, time_bits(bits, t))
}

/// Bits of the time a [`split`] is made from (hi + lo holds 106 of them).
const SPLIT_BITS: u32 = 53 + 53 + 64;

/// The k-th time as an unevaluated sum hi + lo of two f64: hi the f64 nearest the time, lo the
/// rest rounded to f64 (0 exactly when the time is a binary64 number). |lo| ≤ ulp(hi)/2, and
/// hi + lo is the time to 2⁻¹⁰⁵ of its value.
pub fn split(times: &Times, k: usize) -> (f64, f64) {
    match times {
        Times::Binary(v) => (v[k], 0.0),
        Times::Grid { t_end, samples } => grid_split(t_end, *samples, k),
        Times::Decimals(_) => {
            let t = times.time(k, SPLIT_BITS);
            let hi = t.to_f64();
            (hi, Float::with_val(t.prec(), &t - hi).to_f64())
        }
    }
}

/// [`split`] of a grid time: for T an f64 and k·T an f64 exactly, hi = k·T/(N−1) correctly
/// rounded by one f64 division, and the exact remainder k·T − hi·(N−1) (an f64, by FMA) over
/// N−1 gives lo; else from MPFR.
fn grid_split(t_end: &Decimal, samples: usize, k: usize) -> (f64, f64) {
    let t = t_end.to_f64();
    if samples <= 1 || k == 0 {
        return (0.0, 0.0);
    }
    if k + 1 == samples {
        let lo = if t_end.is_binary64() {
            0.0
        } else {
            let x = t_end.to_float(SPLIT_BITS);
            Float::with_val(x.prec(), &x - t).to_f64()
        };
        return (t, lo);
    }
    let n = (samples - 1) as f64;
    let kt = k as f64 * t;
    let exact_product = kt.is_finite() && (kt.abs() < 2f64.powi(1000)) && {
        let e = (k as f64).mul_add(t, -kt);
        e == 0.0
    };
    if exact_product && t_end.is_binary64() && kt.abs() > 2f64.powi(-900) {
        let hi = kt / n;
        let rest = (-hi).mul_add(n, kt);
        return (hi, rest / n);
    }
    let x = Times::grid(t_end.clone(), samples).time(k, SPLIT_BITS);
    let hi = x.to_f64();
    (hi, Float::with_val(x.prec(), &x - hi).to_f64())
}

/// The largest |t| of the times (their f64 values), 0 for none.
pub fn reach(times: &Times) -> f64 {
    match times {
        Times::Grid { t_end, .. } => t_end.to_f64().abs(),
        _ => (0..times.len()).fold(0.0, |m: f64, k| m.max(times.time_f64(k).abs())),
    }
}

/// Exact order of two decimals.
pub fn cmp(a: &Decimal, b: &Decimal) -> Ordering {
    let (an, ad, ae) = a.parts();
    let (bn, bd, be) = b.parts();
    let sign = |neg: bool, zero: bool| {
        if zero {
            0
        } else if neg {
            -1
        } else {
            1
        }
    };
    let (sa, sb) = (sign(an, ad.is_empty()), sign(bn, bd.is_empty()));
    if sa != sb || sa == 0 {
        return sa.cmp(&sb);
    }
    // Same sign, both non-zero: compare magnitudes by the power of ten of the leading digit,
    // then digit by digit.
    let lead = |d: &str, e: i64| e + d.len() as i64;
    let magnitude = lead(ad, ae).cmp(&lead(bd, be)).then_with(|| {
        let n = ad.len().max(bd.len());
        let pad = |d: &str| format!("{d:0<n$}");
        pad(ad).cmp(&pad(bd))
    });
    if sa < 0 {
        magnitude.reverse()
    } else {
        magnitude
    }
}

/// Check the number of times given (at most [`MAX_SAMPLES`]): a face checks it before it copies
/// them (a list of 10⁸ times is refused before its 800 MB are made).
pub fn check_count(n: usize) -> Result<(), String> {
    if n > MAX_SAMPLES {
        return Err(format!(
            "at most {MAX_SAMPLES} times are supported, got {n}"
        ));
    }
    Ok(())
}

/// Check times: at least one, at most [`MAX_SAMPLES`], finite, strictly increasing; a grid
/// with T ≥ 0 and N ≥ 1. The message names no option (a face puts its own in front).
pub fn check(times: &Times) -> Result<(), String> {
    if let Times::Grid { t_end, samples } = times {
        if *samples > MAX_SAMPLES {
            return Err(format!(
                "at most {MAX_SAMPLES} samples are supported, got {samples}"
            ));
        }
        return rsts_dynamics::integrators::OutputGrid::new(t_end.to_f64(), *samples)
            .map(|_| ())
            .map_err(|e| e.to_string());
    }
    let n = times.len();
    if n == 0 {
        return Err("no times".into());
    }
    check_count(n)?;
    match times {
        Times::Binary(v) => rsts_harness::reference::check_times(v),
        Times::Decimals(v) => {
            for (k, w) in v.windows(2).enumerate() {
                if cmp(&w[1], &w[0]) != Ordering::Greater {
                    return Err(format!(
                        "times must be strictly increasing: time {} ({}) does not come after {}",
                        k + 2,
                        shown(&w[1]),
                        shown(&w[0])
                    ));
                }
            }
            Ok(())
        }
        Times::Grid { .. } => unreachable!("checked above"),
    }
}

/// A decimal for a message: as written, cut when long.
fn shown(d: &Decimal) -> String {
    rsts_dynamics::number::shorten(d.as_str())
}

/// Times written in a text: numbers separated by white space, commas or newlines, `#` starting a
/// comment to the end of its line; each is the decimal as written. Errors name the line.
pub fn read_times(text: &str) -> Result<Vec<Decimal>, String> {
    rsts_harness::times_file::read_times_with(text.as_bytes(), Decimal::parse)
}

/// The times of a file as [`read_times`] reads a text, bounded before and while reading
/// (`rsts_harness::times_file`: its size, the number of times, the length of each).
pub fn read_times_file(path: &std::path::Path) -> Result<Vec<Decimal>, String> {
    rsts_harness::times_file::read_decimal_times_file(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(s: &str) -> Decimal {
        Decimal::parse(s).unwrap()
    }

    #[test]
    fn decimals_are_ordered_exactly() {
        let ordered = [
            "-1e300",
            "-2.5",
            "-2.4999999999999999999999999",
            "-1e-300",
            "0",
            "1e-300",
            "0.1",
            "0.1000000000000000000000000000001",
            "0.3",
            "1",
            "1.0000001",
            "10",
            "1e300",
        ];
        for (i, x) in ordered.iter().enumerate() {
            for (j, y) in ordered.iter().enumerate() {
                assert_eq!(cmp(&d(x), &d(y)), i.cmp(&j), "{x} vs {y}");
            }
        }
        assert_eq!(cmp(&d("1.30"), &d("13e-1")), Ordering::Equal);
        assert_eq!(cmp(&d("-0"), &d("0")), Ordering::Equal);
    }

    #[test]
    fn times_are_checked_exactly() {
        let times = |v: &[&str]| Times::Decimals(v.iter().map(|s| d(s)).collect());
        assert!(check(&times(&["0", "0.1", "0.1000000000000000000000001"])).is_ok());
        // Two decimals that are one f64 but different times are in order; equal ones are not.
        assert_eq!(
            check(&times(&["0", "0.5", "0.50"])).unwrap_err(),
            "times must be strictly increasing: time 3 (0.50) does not come after 0.5"
        );
        assert_eq!(check(&times(&[])).unwrap_err(), "no times");
        assert!(check(&Times::grid(d("-1"), 3))
            .unwrap_err()
            .contains("t-end must be non-negative"));
        assert!(check(&Times::grid(d("1"), 0)).is_err());
        assert!(check(&Times::Binary(vec![0.0, 1.0])).is_ok());
        assert!(check(&Times::Binary(vec![1.0, 1.0])).is_err());
    }

    /// hi + lo is the exact time to 2⁻¹⁰⁵ of its value, hi the nearest f64 (checked against
    /// MPFR at 400 bits), for grids of f64 and non-f64 T and for decimals.
    #[test]
    fn a_split_time_is_the_nearest_f64_and_the_rest() {
        let grids = [
            Times::grid(d("10"), 101),
            Times::grid(d("1000"), 999_999),
            Times::grid(d("0.1"), 7),
            Times::grid(d("1e300"), 3),
            Times::Decimals(vec![
                d("0"),
                d("0.1"),
                d("2.5"),
                d("3.3333333333333333333333"),
            ]),
            Times::Binary(vec![0.1, 7.25]),
        ];
        for times in &grids {
            for k in [0, 1, 2, times.len() / 3, times.len() - 1] {
                if k >= times.len() {
                    continue;
                }
                let (hi, lo) = split(times, k);
                let t = times.time(k, 400);
                assert_eq!(hi, t.to_f64(), "{times:?} {k}");
                let rest = Float::with_val(400, &t - hi);
                assert!(
                    lo.abs() <= rest.to_f64().abs() * (1.0 + 1e-15),
                    "{times:?} {k}"
                );
                let off = Float::with_val(400, &rest - lo).abs().to_f64();
                assert!(off <= t.to_f64().abs() * 2f64.powi(-105), "{times:?} {k}");
            }
        }
        assert_eq!(split(&Times::grid(d("10"), 101), 5), (0.5, 0.0));
        assert_ne!(split(&Times::grid(d("10"), 101), 1).1, 0.0);
    }

    #[test]
    fn a_times_text_is_read_as_decimals_by_line() {
        let t = read_times("0, 0.1\t1 # one\n# none\n\n2,3\r\n4").unwrap();
        let want: Vec<Decimal> = ["0", "0.1", "1", "2", "3", "4"]
            .iter()
            .map(|s| d(s))
            .collect();
        assert_eq!(t, want);
        assert_eq!(t[1].as_str(), "0.1");
        assert_eq!(
            read_times("0\n1\nx").unwrap_err(),
            "line 3: 'x' is not a number"
        );
        assert!(read_times("0\n1e400")
            .unwrap_err()
            .starts_with("line 2: must be a finite"));
    }
}
