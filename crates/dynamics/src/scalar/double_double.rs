//! Double-double arithmetic: a real number as an unevaluated sum `hi + lo` of two `f64` with
//! |lo| ≤ ulp(hi)/2, carrying 106 bits (about 32 decimal digits) with the exponent range of
//! `f64`.
//!
//! The field operations are built on the error-free transformations `two_sum` (Knuth) and
//! `two_prod` (one fused multiply-add, `f64::mul_add`); addition is the accurate ("IEEE") variant
//! of Hida, Li & Bailey's QD library, whose relative error is a few units of 2⁻¹⁰⁶ even under
//! cancellation (Joldes, Muller, Popescu, ACM TOMS 44 (2017), Alg. 6). The elementary functions
//! (sqrt, 1/√, sin and cos, exp, ln, atan2) are in `double_double/functions.rs`; in this module:
//!
//! * `parse` and `to_decimal` go through MPFR (`rug::Float`) at 256 bits, so decimal input is
//!   correctly rounded to the double-double grid up to the last bit of `lo`.
//!
//! Accuracy is tested against `rug::Float` at 200 bits on random inputs (`tests`).

use std::cmp::Ordering;
use std::fmt;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use rug::Float;

use super::Real;

/// Precision reported by [`DoubleDouble`]: 2 × 53 bits.
pub const DD_BITS: u32 = 106;

/// Bits used when a double-double goes through MPFR (parse, print, conversion).
const MPFR_BITS: u32 = 256;

/// `hi + lo`, normalised so that `hi` is `hi + lo` rounded to the nearest `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DoubleDouble {
    pub hi: f64,
    pub lo: f64,
}

/// Error-free sum: s + e = a + b exactly, s = fl(a + b) (Knuth's TwoSum, 6 flops, any order).
#[inline(always)]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free sum for |a| ≥ |b| (Dekker's FastTwoSum, 3 flops).
#[inline(always)]
pub fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let e = b - (s - a);
    (s, e)
}

/// Error-free product: p + e = a·b exactly, p = fl(a·b), with one fused multiply-add.
#[inline(always)]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let e = a.mul_add(b, -p);
    (p, e)
}

// Constants split into f64 parts (computed with 400-bit arithmetic; checked in the tests).
const PI: [f64; 3] = [
    std::f64::consts::PI,
    1.2246467991473532e-16,
    -2.9947698097183397e-33,
];
const LN2: [f64; 3] = [
    std::f64::consts::LN_2,
    2.3190468138462996e-17,
    5.707708438416212e-34,
];

/// Terms of a series below this fraction of the sum are dropped (2⁻¹¹⁰).
const SERIES_CUTOFF: f64 = 7.7e-34;

impl DoubleDouble {
    pub const ZERO: Self = Self { hi: 0.0, lo: 0.0 };
    pub const ONE: Self = Self { hi: 1.0, lo: 0.0 };
    /// π to 106 bits.
    pub const PI: Self = Self {
        hi: PI[0],
        lo: PI[1],
    };
    /// ln 2 to 106 bits.
    pub const LN2: Self = Self {
        hi: LN2[0],
        lo: LN2[1],
    };
    /// 2⁻¹⁰⁵, the spacing of double-doubles just above 1 (as [`Real::epsilon`] defines it).
    pub const EPSILON: Self = Self {
        hi: 2.465190328815662e-32,
        lo: 0.0,
    };

    /// `hi + lo` normalised (any two f64).
    pub fn new(hi: f64, lo: f64) -> Self {
        let (hi, lo) = two_sum(hi, lo);
        Self { hi, lo }
    }

    /// An `f64` exactly.
    pub const fn from_f64_exact(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    #[inline(always)]
    fn from_quick(a: f64, b: f64) -> Self {
        let (hi, lo) = quick_two_sum(a, b);
        Self { hi, lo }
    }

    /// The sum of two f64, exactly.
    #[inline(always)]
    pub fn sum_f64(a: f64, b: f64) -> Self {
        let (hi, lo) = two_sum(a, b);
        Self { hi, lo }
    }

    /// The product of two f64, exactly.
    #[inline(always)]
    pub fn prod_f64(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod(a, b);
        Self { hi, lo }
    }

    /// Nearest double-double to an MPFR number (hi = x rounded, lo = (x − hi) rounded).
    pub fn from_float(x: &Float) -> Self {
        let hi = x.to_f64();
        if !hi.is_finite() || x.is_zero() {
            return Self { hi, lo: 0.0 };
        }
        let rest = Float::with_val(x.prec().max(MPFR_BITS), x - hi);
        Self::from_quick(hi, rest.to_f64())
    }

    /// The value as an MPFR number of `bits` bits (exact when `bits` ≥ the span of hi and lo).
    pub fn to_float(&self, bits: u32) -> Float {
        if !self.hi.is_finite() {
            return Float::with_val(bits, self.hi);
        }
        let mut f = Float::with_val(bits.max(MPFR_BITS), self.hi);
        f += self.lo;
        Float::with_val(bits, f)
    }

    /// x·2ⁿ, exactly (barring overflow or underflow).
    pub fn ldexp(&self, n: i32) -> Self {
        // Two factors so that 2^n itself never overflows for |n| ≤ 2100.
        let half = n / 2;
        let f1 = 2f64.powi(half);
        let f2 = 2f64.powi(n - half);
        Self {
            hi: self.hi * f1 * f2,
            lo: self.lo * f1 * f2,
        }
    }

    /// self + b for an f64 b.
    #[inline(always)]
    pub fn add_f64(self, b: f64) -> Self {
        let (s, e) = two_sum(self.hi, b);
        Self::from_quick(s, e + self.lo)
    }

    /// self · b for an f64 b.
    #[inline(always)]
    pub fn mul_f64(self, b: f64) -> Self {
        let (p, e) = two_prod(self.hi, b);
        Self::from_quick(p, self.lo.mul_add(b, e))
    }

    /// self / b for an f64 b.
    #[inline(always)]
    pub fn div_f64(self, b: f64) -> Self {
        let q1 = self.hi / b;
        let r = self - Self::prod_f64(q1, b);
        let q2 = r.hi / b;
        let r = r - Self::prod_f64(q2, b);
        let q3 = r.hi / b;
        Self::from_quick(q1, q2).add_f64(q3)
    }

    /// self².
    #[inline(always)]
    pub fn sqr(self) -> Self {
        let (p, e) = two_prod(self.hi, self.hi);
        let e = (2.0 * self.hi).mul_add(self.lo, e);
        Self::from_quick(p, e)
    }

    #[inline(always)]
    fn is_zero(&self) -> bool {
        self.hi == 0.0
    }

    #[inline(always)]
    fn is_negative(&self) -> bool {
        self.hi < 0.0 || (self.hi == 0.0 && self.hi.is_sign_negative())
    }

    fn nan() -> Self {
        Self {
            hi: f64::NAN,
            lo: f64::NAN,
        }
    }

    /// self + b for addends that do not cancel (|self + b| at least half the larger of
    /// |self|, |b|): QD's `sloppy_add`, one error-free sum instead of two, error a few units of
    /// 2⁻¹⁰⁶ of the sum.
    #[inline(always)]
    fn add_no_cancel(self, b: Self) -> Self {
        let (s, e) = two_sum(self.hi, b.hi);
        Self::from_quick(s, e + (self.lo + b.lo))
    }
}

impl fmt::Display for DoubleDouble {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&Real::to_decimal(self, 32))
    }
}

impl PartialOrd for DoubleDouble {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        match self.hi.partial_cmp(&other.hi)? {
            Ordering::Equal => self.lo.partial_cmp(&other.lo),
            o => Some(o),
        }
    }
}

impl Neg for DoubleDouble {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for DoubleDouble {
    type Output = Self;
    /// Accurate double-double sum (QD's `ieee_add`).
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let (s, e) = quick_two_sum(s, e + t);
        Self::from_quick(s, e + f)
    }
}

impl Sub for DoubleDouble {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        self + (-b)
    }
}

impl Mul for DoubleDouble {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let (p, e) = two_prod(self.hi, b.hi);
        let e = self.hi.mul_add(b.lo, self.lo.mul_add(b.hi, e));
        Self::from_quick(p, e)
    }
}

impl Div for DoubleDouble {
    type Output = Self;
    /// Two f64 quotient digits: q₁ = a/b in f64, the remainder r = a − q₁b with the exact
    /// product q₁·b.hi (a.hi − p is exact: p is within a factor 2 of a.hi, Sterbenz), then
    /// q₂ = r/b.hi. Relative error a few units of 2⁻¹⁰⁶ (each of the ~6 roundings in r and q₂
    /// is 2⁻⁵³ of a number 2⁻⁵³ below the quotient); two divisions instead of QD's three.
    #[inline(always)]
    fn div(self, b: Self) -> Self {
        let q1 = self.hi / b.hi;
        let (p, e) = two_prod(q1, b.hi);
        let r = (((self.hi - p) - e) + self.lo) - q1 * b.lo;
        Self::from_quick(q1, r / b.hi)
    }
}

macro_rules! forward_ops {
    ($($tr:ident $m:ident $atr:ident $am:ident),*) => {$(
        impl<'a> $tr<&'a DoubleDouble> for DoubleDouble {
            type Output = DoubleDouble;
            #[inline(always)]
            fn $m(self, o: &'a DoubleDouble) -> DoubleDouble {
                $tr::$m(self, *o)
            }
        }
        impl $atr for DoubleDouble {
            #[inline(always)]
            fn $am(&mut self, o: DoubleDouble) {
                *self = $tr::$m(*self, o);
            }
        }
        impl<'a> $atr<&'a DoubleDouble> for DoubleDouble {
            #[inline(always)]
            fn $am(&mut self, o: &'a DoubleDouble) {
                *self = $tr::$m(*self, *o);
            }
        }
    )*};
}
forward_ops!(
    Add add AddAssign add_assign,
    Sub sub SubAssign sub_assign,
    Mul mul MulAssign mul_assign,
    Div div DivAssign div_assign
);

impl Real for DoubleDouble {
    const NAME: &'static str = "dd";

    fn from_f64(x: f64, _bits: u32) -> Self {
        Self::from_f64_exact(x)
    }
    fn parse(s: &str, _bits: u32) -> Option<Self> {
        let p = Float::parse(s.trim()).ok()?;
        Some(Self::from_float(&Float::with_val(MPFR_BITS, p)))
    }
    fn prec(&self) -> u32 {
        DD_BITS
    }
    fn to_f64(&self) -> f64 {
        if self.hi.is_finite() {
            self.hi + self.lo
        } else {
            self.hi
        }
    }
    fn pi(_bits: u32) -> Self {
        Self::PI
    }
    fn epsilon(&self) -> Self {
        Self::EPSILON
    }
    #[inline(always)]
    fn sqrt(&self) -> Self {
        self.sqrt_karp()
    }
    /// Newton's step from the f64 value ([`DoubleDouble::recip_sqrt_newton`]).
    #[inline(always)]
    fn recip_sqrt(&self) -> Self {
        self.recip_sqrt_newton()
    }
    #[inline(always)]
    fn add_same_sign(self, other: &Self) -> Self {
        self.add_no_cancel(*other)
    }
    #[inline(always)]
    fn abs(&self) -> Self {
        if self.is_negative() {
            -*self
        } else {
            *self
        }
    }
    #[inline(always)]
    fn sin(&self) -> Self {
        self.sin_cos().0
    }
    #[inline(always)]
    fn cos(&self) -> Self {
        self.sin_cos().1
    }
    /// Both from one reduction and one series (the default would run [`Self::sin_cos`] twice).
    #[inline(always)]
    fn sin_cos(&self) -> (Self, Self) {
        DoubleDouble::sin_cos(self)
    }
    #[inline(always)]
    fn square(&self) -> Self {
        self.sqr()
    }
    fn atan2(&self, x: &Self) -> Self {
        self.atan2_newton(x)
    }
    fn exp(&self) -> Self {
        self.exp_series()
    }
    fn ln(&self) -> Self {
        self.ln_newton()
    }
    fn floor(&self) -> Self {
        let hi = self.hi.floor();
        if hi == self.hi {
            Self::from_quick(hi, self.lo.floor())
        } else {
            Self { hi, lo: 0.0 }
        }
    }
    fn is_finite(&self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }
    fn to_decimal(&self, digits: u32) -> String {
        if !self.hi.is_finite() {
            return format!("{}", self.hi);
        }
        let digits = digits.clamp(1, 32);
        Real::to_decimal(&self.to_float(MPFR_BITS), digits)
    }
}

mod functions;
pub mod lanes;
#[cfg(test)]
mod tests;
