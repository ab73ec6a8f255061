//! The scalar abstraction: every formula of the project is written once over [`Real`] and runs in
//! `f64`, in the double-double type of the Taylor integrators and in `rug::Float` at any precision.
//!
//! A value carries its own precision (`rug::Float` does, `f64` has 53 bits). Constants are made
//! with [`Real::from_f64`] or [`Real::parse`] at a precision given in bits; generic code that has a
//! value at hand uses [`Real::lit`] to make a constant of the same precision.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use rug::float::Constant;
use rug::Float;

pub mod double_double;
pub use double_double::lanes::{every_lane, DoubleDouble4, DoubleDoubleLanes, LANES};
pub use double_double::DoubleDouble;

/// Bits of a `f64` mantissa, the precision `f64` reports.
pub const F64_BITS: u32 = 53;

/// Bits needed for `digits` decimal digits (plus a guard of 8 bits).
pub fn bits_for_digits(digits: u32) -> u32 {
    (f64::from(digits) * std::f64::consts::LOG2_10).ceil() as u32 + 8
}

/// Decimal digits carried by `bits` bits.
pub fn digits_for_bits(bits: u32) -> u32 {
    (f64::from(bits) / std::f64::consts::LOG2_10).floor() as u32
}

/// A real scalar: field operations, elementary functions, conversions.
pub trait Real:
    Clone
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + for<'a> Add<&'a Self, Output = Self>
    + for<'a> Sub<&'a Self, Output = Self>
    + for<'a> Mul<&'a Self, Output = Self>
    + for<'a> Div<&'a Self, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + for<'a> AddAssign<&'a Self>
    + for<'a> SubAssign<&'a Self>
    + for<'a> MulAssign<&'a Self>
    + for<'a> DivAssign<&'a Self>
{
    /// Short name of the type, for reports.
    const NAME: &'static str;

    /// `x` rounded to a scalar of `bits` bits of precision (ignored by fixed-precision types).
    fn from_f64(x: f64, bits: u32) -> Self;
    /// A decimal string read at `bits` bits of precision (exactly rounded where the type can).
    fn parse(s: &str, bits: u32) -> Option<Self>;
    /// Precision in bits.
    fn prec(&self) -> u32;
    /// Nearest `f64`.
    fn to_f64(&self) -> f64;
    /// A constant at the precision of `self`.
    fn lit(&self, x: f64) -> Self {
        Self::from_f64(x, self.prec())
    }
    /// π at `bits` bits.
    fn pi(bits: u32) -> Self;
    /// Machine epsilon of this precision, 2^(1-prec). Built from factors an f64 holds: beyond
    /// 1074 bits 2^(1-prec) itself underflows f64 to 0, and an epsilon of 0 made every
    /// convergence test fail, so identify at thousands of digits ran every loop to its limit.
    fn epsilon(&self) -> Self {
        let mut left = self.prec() as i32 - 1;
        let mut e = self.one_like();
        while left > 0 {
            let k = left.min(1000);
            e *= &self.lit(2f64.powi(-k));
            left -= k;
        }
        e
    }

    fn sqrt(&self) -> Self;
    fn abs(&self) -> Self;
    fn sin(&self) -> Self;
    fn cos(&self) -> Self;
    /// (sin, cos) together (one call in MPFR, which shares the argument reduction).
    fn sin_cos(&self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    fn atan2(&self, x: &Self) -> Self;
    fn exp(&self) -> Self;
    fn ln(&self) -> Self;
    fn floor(&self) -> Self;
    fn is_finite(&self) -> bool;

    /// Decimal text with `digits` significant digits.
    fn to_decimal(&self, digits: u32) -> String;

    fn zero_like(&self) -> Self {
        self.lit(0.0)
    }
    fn one_like(&self) -> Self {
        self.lit(1.0)
    }
    /// `self * self`.
    fn square(&self) -> Self {
        self.clone() * self
    }
    /// `self /= d` for a small integer d (the Taylor recursion's 1/(n + 1)): exactly rounded
    /// like the division by d as a scalar, without making one (MPFR: `mpfr_div_ui`).
    fn div_small(&mut self, d: u32) {
        let d = self.lit(f64::from(d));
        *self /= &d;
    }
    /// `self += a·b`, with no clone of `a` (the Taylor coefficients' inner loop).
    fn mul_add_assign(&mut self, a: &Self, b: &Self) {
        *self += a.clone() * b;
    }
    /// `self + other` for two numbers of one sign (no cancellation): double-double adds them
    /// with one error-free sum instead of two.
    fn add_same_sign(self, other: &Self) -> Self {
        self + other
    }
    /// 1/√self.
    fn recip_sqrt(&self) -> Self {
        self.one_like() / self.sqrt()
    }
    fn max_of(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    fn min_of(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
}

impl Real for f64 {
    const NAME: &'static str = "f64";

    fn from_f64(x: f64, _bits: u32) -> Self {
        x
    }
    fn parse(s: &str, _bits: u32) -> Option<Self> {
        s.trim().parse().ok()
    }
    fn prec(&self) -> u32 {
        F64_BITS
    }
    fn to_f64(&self) -> f64 {
        *self
    }
    fn pi(_bits: u32) -> Self {
        std::f64::consts::PI
    }
    fn epsilon(&self) -> Self {
        f64::EPSILON
    }
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    fn abs(&self) -> Self {
        f64::abs(*self)
    }
    fn sin(&self) -> Self {
        f64::sin(*self)
    }
    fn cos(&self) -> Self {
        f64::cos(*self)
    }
    fn atan2(&self, x: &Self) -> Self {
        f64::atan2(*self, *x)
    }
    fn exp(&self) -> Self {
        f64::exp(*self)
    }
    fn ln(&self) -> Self {
        f64::ln(*self)
    }
    fn floor(&self) -> Self {
        f64::floor(*self)
    }
    fn div_small(&mut self, d: u32) {
        *self /= f64::from(d);
    }
    fn is_finite(&self) -> bool {
        f64::is_finite(*self)
    }
    fn to_decimal(&self, digits: u32) -> String {
        if digits >= 17 || digits == 0 {
            // Shortest text that reads back to the same f64.
            format!("{self:e}")
        } else {
            format!("{:.*e}", digits.saturating_sub(1) as usize, self)
        }
    }
}

impl Real for Float {
    const NAME: &'static str = "mpfr";

    fn from_f64(x: f64, bits: u32) -> Self {
        Float::with_val(bits, x)
    }
    fn parse(s: &str, bits: u32) -> Option<Self> {
        Float::parse(s.trim())
            .ok()
            .map(|p| Float::with_val(bits, p))
    }
    fn prec(&self) -> u32 {
        Float::prec(self)
    }
    fn to_f64(&self) -> f64 {
        Float::to_f64(self)
    }
    fn pi(bits: u32) -> Self {
        Float::with_val(bits, Constant::Pi)
    }
    fn sqrt(&self) -> Self {
        self.clone().sqrt()
    }
    fn abs(&self) -> Self {
        self.clone().abs()
    }
    fn sin(&self) -> Self {
        self.clone().sin()
    }
    fn cos(&self) -> Self {
        self.clone().cos()
    }
    fn sin_cos(&self) -> (Self, Self) {
        self.clone().sin_cos(Float::new(self.prec()))
    }
    fn atan2(&self, x: &Self) -> Self {
        self.clone().atan2(x)
    }
    fn exp(&self) -> Self {
        self.clone().exp()
    }
    fn ln(&self) -> Self {
        self.clone().ln()
    }
    fn floor(&self) -> Self {
        self.clone().floor()
    }
    fn is_finite(&self) -> bool {
        Float::is_finite(self)
    }
    fn div_small(&mut self, d: u32) {
        *self /= d;
    }
    fn recip_sqrt(&self) -> Self {
        self.clone().recip_sqrt()
    }
    fn mul_add_assign(&mut self, a: &Self, b: &Self) {
        // Product rounded to the working precision, then a same-precision sum: about twice as
        // fast as mpfr_fma (which forms the exact 2p-bit product and adds it by the generic
        // path) in the Taylor coefficients.
        let p = Float::with_val(self.prec(), a * b);
        *self += &p;
    }
    fn to_decimal(&self, digits: u32) -> String {
        let digits = digits.max(1) as usize;
        if self.is_zero() {
            return "0".to_string();
        }
        self.to_string_radix(10, Some(digits))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mpfr_parse_is_exact_beyond_f64() {
        let bits = bits_for_digits(50);
        let x = <Float as Real>::parse("0.1", bits).unwrap();
        let ten = Float::with_val(bits, 10);
        let one = x * ten - 1u32;
        // 0.1 read at 50 digits is 0.1 to 50 digits, not the f64 nearest 0.1 (off by 5.6e-18).
        assert!(one.abs() < 1e-49);
        let y = <f64 as Real>::parse("0.1", 53).unwrap() * 10.0 - 1.0;
        assert!(y.abs() < 1e-15);
    }

    #[test]
    fn epsilon_is_two_to_one_minus_prec_at_any_precision() {
        for bits in [53, 200, 1074, 1100, 3000, 33_220] {
            let one = Float::with_val(bits, 1);
            let eps = Real::epsilon(&one);
            assert!(eps > 0, "epsilon at {bits} bits is 0");
            assert_eq!(eps, Float::with_val(bits, 1) >> (bits - 1), "{bits} bits");
            // 1 + eps is the next number after 1, 1 + eps/2 rounds back to 1.
            assert!(one.clone() + &eps > one, "{bits} bits");
        }
    }

    #[test]
    fn decimal_text_carries_the_requested_digits() {
        let bits = bits_for_digits(40);
        let third = Float::with_val(bits, 1) / Float::with_val(bits, 3);
        let s = Real::to_decimal(&third, 40);
        assert_eq!(s.matches('3').count(), 40, "{s}");
        assert!(bits_for_digits(1000) >= 3322);
        assert_eq!(digits_for_bits(bits_for_digits(30)), 32);
    }
}
