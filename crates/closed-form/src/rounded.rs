//! Correctly rounded f64 values from the double-double closed form (Ziv's strategy).
//!
//! The closed form in [`DoubleDouble`] (106 bits, constants and phase from 170-bit MPFR, see
//! [`crate::scalar`]) is ~15× cheaper than in MPFR at the 172 bits of the reference. A value
//! computed in it is rounded to f64 when every number within its error bound rounds to the same
//! f64 ([`ziv_round`]); otherwise the caller recomputes it in MPFR. The bound of each value is
//! calibrated once per motion ([`RoundingBounds::calibrate`]): the largest difference between
//! the double-double and the MPFR value over times spread across both periods, times 2¹⁶, and at
//! least 2⁻⁸⁸ of the value's scale. With the double-double error a few units of 2⁻¹⁰⁶ of the
//! scale, a value falls back to MPFR only when it lies within ~2⁻³⁵ ulp of a rounding boundary
//! or is below ~1e-9 of its scale: 43 of 240 000 random rows in the harness's test
//! (crates/harness/tests/harness/rounded_reference.rs), all within 1e-9 of Σ.

use rsts_dynamics::scalar::DoubleDouble;
use rug::Float;

/// Margin of a calibrated bound over the largest error measured.
pub const BOUND_MARGIN: f64 = 65536.0;
/// Least bound, as a fraction of a value's scale (2⁻⁸⁸).
pub const BOUND_FLOOR: f64 = 3.2311742677852644e-27;

/// `x` rounded to the nearest f64 when every number within `bound` of it rounds there (the
/// exact value lies within `bound` of `x`); `None` when that cannot be decided (Ziv's test)
/// or `x` is not finite.
#[inline]
pub fn ziv_round(x: DoubleDouble, bound: f64) -> Option<f64> {
    // Rounding is monotonic: the ends of [x − b, x + b] decide. lo ± b is rounded (by up to
    // 2⁻⁵³ of |lo| + b), hence the factor 2 on the bound.
    let b = 2.0 * bound;
    let down = x.hi + (x.lo - b);
    let up = x.hi + (x.lo + b);
    (down == up && down.is_finite()).then_some(down)
}

/// Per-value error bounds of a double-double evaluation of N values.
#[derive(Clone, Debug, PartialEq)]
pub struct RoundingBounds<const N: usize> {
    /// Absolute bound of each value.
    pub bounds: [f64; N],
}

impl<const N: usize> RoundingBounds<N> {
    /// The bounds of the N values `dd(t)` against the same values `mp(t)` in MPFR (at ≥ 150
    /// bits) at `times`: [`BOUND_MARGIN`] × the largest difference, at least [`BOUND_FLOOR`] ×
    /// the largest |value|.
    pub fn calibrate(
        times: &[f64],
        dd: impl Fn(f64) -> [DoubleDouble; N],
        mp: impl Fn(f64) -> [Float; N],
    ) -> Self {
        let mut err = [0f64; N];
        let mut scale = [f64::MIN_POSITIVE; N];
        for &t in times {
            let (d, m) = (dd(t), mp(t));
            for k in 0..N {
                let diff = Float::with_val(m[k].prec().max(160), &d[k].to_float(160) - &m[k]);
                let e = diff.to_f64().abs();
                // A NaN difference (a value not finite) makes that value always fall back.
                err[k] = if e.is_nan() {
                    f64::INFINITY
                } else {
                    err[k].max(e)
                };
                scale[k] = scale[k].max(m[k].to_f64().abs());
            }
        }
        Self {
            bounds: std::array::from_fn(|k| {
                BOUND_MARGIN * err[k].max(BOUND_FLOOR * scale[k] / BOUND_MARGIN)
            }),
        }
    }

    /// Every value rounded by [`ziv_round`] with its bound, or `None` if one is undecided.
    #[inline]
    pub fn round(&self, values: &[DoubleDouble; N]) -> Option<[f64; N]> {
        let mut out = [0.0; N];
        for k in 0..N {
            out[k] = ziv_round(values[k], self.bounds[k])?;
        }
        Some(out)
    }
}

/// 64 calibration times spread over both periods (a low-discrepancy sequence on [0, 2P],
/// P the longer period, capped at 1e4 when a period is not finite or very long).
pub fn calibration_times(periods: [f64; 2]) -> Vec<f64> {
    let p = periods
        .iter()
        .copied()
        .filter(|p| p.is_finite() && *p > 0.0)
        .fold(0.0, f64::max);
    let span = if p > 0.0 { (2.0 * p).min(1e4) } else { 100.0 };
    let golden = 0.618_033_988_749_894_9;
    (0..64)
        .map(|j| span * (f64::from(j) * golden).fract())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ziv_round_decides_only_away_from_boundaries() {
        let one = DoubleDouble::new(1.0, 1e-20);
        assert_eq!(ziv_round(one, 1e-25), Some(1.0));
        // 1 + 2⁻⁵³ is the midpoint between 1 and its successor: undecidable within any bound.
        let half_ulp = f64::EPSILON / 2.0;
        let mid = DoubleDouble::new(1.0, half_ulp);
        assert_eq!(ziv_round(mid, 1e-30), None);
        // Just above the midpoint, with a bound smaller than the distance: the successor.
        let above = DoubleDouble::new(1.0, half_ulp * (1.0 + 1e-6));
        assert_eq!(ziv_round(above, 1e-30), Some(1.0 + f64::EPSILON));
        assert_eq!(ziv_round(above, 1e-20), None);
        assert_eq!(ziv_round(DoubleDouble::new(f64::NAN, 0.0), 1e-30), None);
        // A value of 0 with any bound is undecidable (the sign of the neighbours differ).
        assert_eq!(ziv_round(DoubleDouble::ZERO, 1e-40), None);
    }

    #[test]
    fn calibrated_bounds_cover_the_measured_error() {
        let x = DoubleDouble::new(0.1, 0.0);
        let exact = Float::with_val(200, 1) / 10u32;
        let b = RoundingBounds::<1>::calibrate(&[0.0, 1.0], |_| [x], |_| [exact.clone()]);
        // 0.1 as an f64 is 5.55e-18 off: the bound is 2¹⁶ of it.
        assert!((b.bounds[0] / 5.551115123125783e-18 - BOUND_MARGIN).abs() < 1.0);
        assert_eq!(b.round(&[x]), None);
        let times = calibration_times([2.0, 3.0]);
        assert_eq!(times.len(), 64);
        assert!(times.iter().all(|t| (0.0..6.0).contains(t)));
    }
}
