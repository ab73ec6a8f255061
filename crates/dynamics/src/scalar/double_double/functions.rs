//! The elementary functions of [`DoubleDouble`] (the arithmetic is in the parent module):
//!
//! * `sqrt`: one Newton step on the f64 square root (Karp's trick); `recip_sqrt` likewise;
//! * `exp`: reduction by m·ln 2 (ln 2 in three parts) and by 2⁻⁹, Taylor series of expm1,
//!   nine squarings, scaling by 2^m;
//! * `sin`, `cos`: reduction by n·π/16 (π/16 in three parts, exact products; a table of sin,
//!   cos kπ/16, |k| ≤ 4, and the quadrant by symmetry), Taylor polynomials of sin and cos on
//!   |t| ≤ π/32 (written once over the lane count in `lanes.rs`, here in one lane);
//! * `ln`, `atan2`: one Newton step from the `f64` value (the error squares: 53 → 106 bits);
//!   `ln` near 1 is accurate to ~1e-32 absolutely rather than relatively.

use rug::Float;

use super::lanes::DoubleDoubleLanes;
use super::{DoubleDouble, LN2, MPFR_BITS, PI, SERIES_CUTOFF};

/// 2π to 106 bits (π's parts doubled, exactly).
pub(super) const TWO_PI: DoubleDouble = DoubleDouble {
    hi: 2.0 * PI[0],
    lo: 2.0 * PI[1],
};

impl DoubleDouble {
    /// (sin x, cos x): x = nπ/16 + t with |t| ≤ π/32 in one reduction (π/16 in three parts,
    /// n·p₀ and n·p₁ exact: accurate to 2⁻¹⁰⁶ relative to t for |n| < 2⁵⁰), n = 8j + k with
    /// |k| ≤ 4, the quadrant j by symmetry.
    #[inline(always)]
    pub fn sin_cos(&self) -> (Self, Self) {
        if !self.hi.is_finite() {
            return (Self::nan(), Self::nan());
        }
        if self.is_zero() {
            return (*self, Self::ONE);
        }
        let n = (self.hi * (16.0 / std::f64::consts::PI)).round();
        // π/16 in three parts (exact: π's parts scaled by 2⁻⁴).
        let t = *self - Self::prod_f64(n, PI[0] / 16.0);
        let t = t - Self::prod_f64(n, PI[1] / 16.0);
        let t = t - Self::from_f64_exact(n * (PI[2] / 16.0));
        Self::sin_cos_sixteenths(t, n)
    }

    /// (sin, cos) of nπ/16 + t for |t| ≤ π/32: the one kernel of
    /// [`DoubleDoubleLanes::sin_cos_turns`] in one lane.
    #[inline(always)]
    fn sin_cos_sixteenths(t: Self, n: f64) -> (Self, Self) {
        let (s, c) = DoubleDoubleLanes::<1>::sin_cos_sixteenths(t.into(), [n]);
        (s.lane(0), c.lane(0))
    }

    /// (sin 2πx, cos 2πx) for x in turns: [`DoubleDoubleLanes::sin_cos_turns`] in one lane
    /// (the reduction by one product instead of three, for an angle known in turns).
    #[inline(always)]
    pub fn sin_cos_turns(&self) -> (Self, Self) {
        let (s, c) = DoubleDoubleLanes::<1>::from(*self).sin_cos_turns();
        (s.lane(0), c.lane(0))
    }

    /// √x by Karp's step from the f64 reciprocal square root.
    #[inline(always)]
    pub(super) fn sqrt_karp(&self) -> Self {
        if self.is_zero() {
            return *self;
        }
        if self.is_negative() || self.hi.is_nan() {
            return Self::nan();
        }
        if self.hi.is_infinite() {
            return *self;
        }
        self.karp_step()
    }

    /// Karp's step for a positive finite x: y ≈ 1/√x, √x ≈ x·y + (x − (x·y)²)·y/2.
    #[inline(always)]
    pub(super) fn karp_step(&self) -> Self {
        let y = 1.0 / self.hi.sqrt();
        let ay = self.hi * y;
        let r = *self - Self::prod_f64(ay, ay);
        Self::from_f64_exact(ay).add_f64(r.hi * (y * 0.5))
    }

    /// Newton's step for 1/√x from the f64 value y: with r = 1 − x·y² (x·y² in double-double,
    /// r to f64), 1/√x = y·(1 + r/2 + 3r²/8 + …), r ≈ 2⁻⁵² so the sum in f64 errs by ~2⁻¹⁰⁶.
    /// One f64 division instead of the two of [`Self::sqrt_karp`] and a double-double division.
    #[inline(always)]
    pub(super) fn recip_sqrt_newton(&self) -> Self {
        if !(self.hi > 0.0 && self.hi.is_finite()) {
            return Self::ONE / self.sqrt_karp();
        }
        let y = 1.0 / self.hi.sqrt();
        let r = (Self::ONE - *self * Self::prod_f64(y, y)).hi;
        Self::from_f64_exact(y).add_f64(y * r * 0.375f64.mul_add(r, 0.5))
    }

    /// atan2 by one Newton step from the f64 value (on sin z or cos z, whichever is steeper).
    pub(super) fn atan2_newton(&self, x: &Self) -> Self {
        let y = self;
        if x.is_zero() || y.is_zero() || !x.hi.is_finite() || !y.hi.is_finite() {
            // Exact special values (0, ±π/2, ±π) or IEEE results for infinities/NaN; the
            // multiples of π are given to full precision.
            let z = f64::atan2(y.hi, x.hi);
            let pi = Self::PI;
            return if z == std::f64::consts::PI {
                pi
            } else if z == -std::f64::consts::PI {
                -pi
            } else if z == std::f64::consts::FRAC_PI_2 {
                pi.mul_f64(0.5)
            } else if z == -std::f64::consts::FRAC_PI_2 {
                -pi.mul_f64(0.5)
            } else {
                Self::from_f64_exact(z)
            };
        }
        let z = Self::from_f64_exact(f64::atan2(y.hi, x.hi));
        let r = (x.sqr() + y.sqr()).sqrt_karp();
        let (xx, yy) = (*x / r, *y / r);
        let (s, c) = z.sin_cos();
        if xx.hi.abs() > yy.hi.abs() {
            // Newton on sin z = yy.
            z + (yy - s) / c
        } else {
            // Newton on cos z = xx.
            z - (xx - c) / s
        }
    }

    /// exp by reduction by m·ln 2 and 2⁻⁹, the Taylor series of expm1 and nine squarings.
    pub(super) fn exp_series(&self) -> Self {
        if self.hi > 709.79 {
            return Self::from_f64_exact(f64::INFINITY);
        }
        if self.hi < -745.2 {
            return Self::ZERO;
        }
        if self.hi.is_nan() {
            return Self::nan();
        }
        if self.is_zero() {
            return Self::ONE;
        }
        let m = (self.hi / LN2[0]).round();
        let r = *self - Self::prod_f64(m, LN2[0]);
        let r = r - Self::prod_f64(m, LN2[1]);
        let r = r - Self::from_f64_exact(m * LN2[2]);
        // |r| ≤ ln2/2; r/512 ≤ 6.8e-4: expm1 by Taylor series, then (1+s)² − 1 = s(s + 2) nine
        // times.
        let r = r.ldexp(-9);
        let mut term = r;
        let mut s = r;
        let mut i = 2.0;
        loop {
            term = (term * r).div_f64(i);
            s += term;
            i += 1.0;
            if term.hi.abs() <= SERIES_CUTOFF * s.hi.abs() {
                break;
            }
        }
        for _ in 0..9 {
            s = s * s.add_f64(2.0);
        }
        s.add_f64(1.0).ldexp(m as i32)
    }

    /// ln by one Newton step on exp(y) = x from the f64 value.
    pub(super) fn ln_newton(&self) -> Self {
        if self.hi.is_nan() || self.is_negative() && !self.is_zero() {
            return Self::nan();
        }
        if self.is_zero() {
            return Self::from_f64_exact(f64::NEG_INFINITY);
        }
        if self.hi.is_infinite() {
            return *self;
        }
        if *self == Self::ONE {
            return Self::ZERO;
        }
        // Newton on exp(y) = x: y ← y + x·exp(−y) − 1.
        let y = Self::from_f64_exact(self.hi.ln());
        y + (*self * (-y).exp_series()).add_f64(-1.0)
    }
}

/// Constants of [`DoubleDouble::sin_cos`], computed once in MPFR.
pub(super) struct SinCosTables {
    /// (−1)ⁿ/(2n + 1)! for n = 1…9 (the odd Taylor coefficients of sin from t³ to t¹⁹).
    pub(super) inverse_factorials: [DoubleDouble; 9],
    /// (−1)ⁿ/(2n)! for n = 1…9 (the even Taylor coefficients of cos from t² to t¹⁸).
    pub(super) inverse_even_factorials: [DoubleDouble; 9],
    /// (sin kπ/16, cos kπ/16) for k = 1…4.
    pub(super) sin_cos_k16: [(DoubleDouble, DoubleDouble); 4],
}

pub(super) fn sin_cos_tables() -> &'static SinCosTables {
    static TABLES: std::sync::OnceLock<SinCosTables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let bits = MPFR_BITS;
        let inverse_factorial = |n: u32| {
            let mut f = Float::with_val(bits, 1);
            for j in 2..=n {
                f *= j;
            }
            Float::with_val(bits, 1) / f
        };
        let inverse_even_factorials = std::array::from_fn(|i| {
            let x = inverse_factorial(2 * i as u32 + 2);
            DoubleDouble::from_float(&if i % 2 == 0 { -x } else { x })
        });
        let inverse_factorials = std::array::from_fn(|i| {
            let x = inverse_factorial(2 * i as u32 + 3);
            DoubleDouble::from_float(&if i % 2 == 0 { -x } else { x })
        });
        let pi = Float::with_val(bits, rug::float::Constant::Pi);
        let sin_cos_k16 = std::array::from_fn(|i| {
            let a = Float::with_val(bits, &pi * (i as u32 + 1)) / 16u32;
            let (s, c) = a.sin_cos(Float::new(bits));
            (DoubleDouble::from_float(&s), DoubleDouble::from_float(&c))
        });
        SinCosTables {
            inverse_factorials,
            inverse_even_factorials,
            sin_cos_k16,
        }
    })
}
