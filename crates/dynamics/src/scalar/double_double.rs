//! Double-double arithmetic: a real number as an unevaluated sum `hi + lo` of two `f64` with
//! |lo| ≤ ulp(hi)/2, carrying 106 bits (about 32 decimal digits) with the exponent range of
//! `f64`.
//!
//! The field operations are built on the error-free transformations `two_sum` (Knuth) and
//! `two_prod` (one fused multiply-add, `f64::mul_add`); addition is the accurate ("IEEE") variant
//! of Hida, Li & Bailey's QD library, whose relative error is a few units of 2⁻¹⁰⁶ even under
//! cancellation (Joldes, Muller, Popescu, ACM TOMS 44 (2017), Alg. 6). Elementary functions:
//!
//! * `sqrt`: one Newton step on the f64 square root (Karp's trick);
//! * `exp`: reduction by m·ln 2 (ln 2 in three parts) and by 2⁻⁹, Taylor series of expm1,
//!   nine squarings, scaling by 2^m;
//! * `sin`, `cos`: reduction by n·π/16 (π/16 in three parts, exact products; a table of sin,
//!   cos kπ/16, |k| ≤ 4, and the quadrant by symmetry), Taylor series of sin on |t| ≤ π/32,
//!   cos t = √(1 − sin²t);
//! * `ln`, `atan2`: one Newton step from the `f64` value (the error squares: 53 → 106 bits);
//!   `ln` near 1 is accurate to ~1e-32 absolutely rather than relatively;
//! * `parse` and `to_decimal` go through MPFR (`rug::Float`) at 256 bits, so decimal input is
//!   correctly rounded to the double-double grid up to the last bit of `lo`.
//!
//! Accuracy is tested against `rug::Float` at 200 bits on random inputs (unit tests below).

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

    /// (sin t, cos t) for |t| ≤ π/32, rotated by kπ/16 (|k| ≤ 4): sin t and cos t by their
    /// Taylor polynomials to t¹⁹ and t¹⁸ (Horner in t², coefficients 1/n! to 106 bits, the terms
    /// from t¹¹ and t¹⁰ on in f64; two independent chains, no square root), then the angle-sum
    /// formulas with sin, cos of kπ/16 from a table (QD's method). No sum here cancels (each
    /// one's smaller addend is below half the larger: |sin(π/16)cos(π/32)| > 2·|cos(π/16)sin(π/32)|),
    /// so they are [`Self::add_no_cancel`].
    #[inline(always)]
    fn sin_cos_reduced(t: Self, k: f64) -> (Self, Self) {
        let tables = sin_cos_tables();
        let t2 = t.sqr();
        let (s, c) = (&tables.inverse_factorials, &tables.inverse_even_factorials);
        // The terms from t¹¹ on are below 1.3e-15 of the first (t⁸·3!/11! for |t| ≤ π/32):
        // their sum in plain f64 errs by ~1e-31 of the series (t³/6), ~1e-33 of sin t; those of
        // cos from t¹⁰ on, below 5e-15 of t²/2: ~1e-33 of cos t.
        let (mut tail_s, mut tail_c) = (s[8].hi, c[8].hi);
        for (sk, ck) in s[4..8].iter().zip(&c[4..8]).rev() {
            tail_s = tail_s * t2.hi + sk.hi;
            tail_c = tail_c * t2.hi + ck.hi;
        }
        let mut ps = t2.mul_f64(tail_s).add_no_cancel(s[3]);
        let mut pc = t2.mul_f64(tail_c).add_no_cancel(c[3]);
        for (sk, ck) in s[..3].iter().zip(&c[..3]).rev() {
            ps = (ps * t2).add_no_cancel(*sk);
            pc = (pc * t2).add_no_cancel(*ck);
        }
        let sin_t = t.add_no_cancel(t * t2 * ps);
        let cos_t = Self::ONE.add_no_cancel(t2 * pc);
        let j = k.abs() as usize;
        if j == 0 {
            return (sin_t, cos_t);
        }
        let (sk, ck) = tables.sin_cos_k16[j - 1];
        let sk = if k < 0.0 { -sk } else { sk };
        (
            (sk * cos_t).add_no_cancel(ck * sin_t),
            (ck * cos_t).add_no_cancel(-(sk * sin_t)),
        )
    }

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
        let j = (n / 8.0).round();
        let (s, c) = Self::sin_cos_reduced(t, n - 8.0 * j);
        match (j.rem_euclid(4.0)) as u32 {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }
}

/// Constants of [`DoubleDouble::sin_cos`], computed once in MPFR.
struct SinCosTables {
    /// (−1)ⁿ/(2n + 1)! for n = 1…9 (the odd Taylor coefficients of sin from t³ to t¹⁹).
    inverse_factorials: [DoubleDouble; 9],
    /// (−1)ⁿ/(2n)! for n = 1…9 (the even Taylor coefficients of cos from t² to t¹⁸).
    inverse_even_factorials: [DoubleDouble; 9],
    /// (sin kπ/16, cos kπ/16) for k = 1…4.
    sin_cos_k16: [(DoubleDouble, DoubleDouble); 4],
}

fn sin_cos_tables() -> &'static SinCosTables {
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
        if self.is_zero() {
            return *self;
        }
        if self.is_negative() || self.hi.is_nan() {
            return Self::nan();
        }
        if self.hi.is_infinite() {
            return *self;
        }
        // Karp: y ≈ 1/√a, √a ≈ a·y + (a − (a·y)²)·y/2.
        let y = 1.0 / self.hi.sqrt();
        let ay = self.hi * y;
        let r = *self - Self::prod_f64(ay, ay);
        Self::from_f64_exact(ay).add_f64(r.hi * (y * 0.5))
    }
    /// Newton's step for 1/√x from the f64 value y: with r = 1 − x·y² (x·y² in double-double,
    /// r to f64), 1/√x = y·(1 + r/2 + 3r²/8 + …), r ≈ 2⁻⁵² so the sum in f64 errs by ~2⁻¹⁰⁶.
    /// One f64 division instead of the two of [`Real::sqrt`] and a double-double division.
    #[inline(always)]
    fn recip_sqrt(&self) -> Self {
        if !(self.hi > 0.0 && self.hi.is_finite()) {
            return Self::ONE / self.sqrt();
        }
        let y = 1.0 / self.hi.sqrt();
        let r = (Self::ONE - *self * Self::prod_f64(y, y)).hi;
        Self::from_f64_exact(y).add_f64(y * r * 0.375f64.mul_add(r, 0.5))
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
        let r = (x.sqr() + y.sqr()).sqrt();
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
    fn exp(&self) -> Self {
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
    fn ln(&self) -> Self {
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
        y + (*self * (-y).exp()).add_f64(-1.0)
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    const REF_BITS: u32 = 200;
    const SAMPLES: usize = 2000;
    /// Required relative accuracy of every operation (2⁻¹⁰⁶ ≈ 1.2e-32; a few ulps allowed).
    const TOL: f64 = 1e-30;

    type Dd = DoubleDouble;

    /// A random double-double with hi log-uniform in ±[2^lo_exp, 2^hi_exp] and a full lo.
    fn random_dd(rng: &mut ChaCha8Rng, lo_exp: f64, hi_exp: f64, signed: bool) -> Dd {
        let mag = 2f64.powf(rng.gen_range(lo_exp..hi_exp));
        let sign = if signed && rng.gen_bool(0.5) {
            -1.0
        } else {
            1.0
        };
        let hi = sign * mag;
        // |lo| < ulp(hi)/2.
        let ulp = 2f64.powi(hi.abs().log2().floor() as i32 - 52);
        Dd::new(hi, rng.gen_range(-0.49..0.49) * ulp)
    }

    fn rel_err(x: &Dd, reference: &Float) -> f64 {
        let d = Float::with_val(REF_BITS, &x.to_float(REF_BITS) - reference);
        if reference.is_zero() {
            return d.to_f64().abs();
        }
        (d / reference).to_f64().abs()
    }

    /// Largest relative error of a unary operation over random inputs from `input`.
    fn max_err_unary(
        seed: u64,
        input: impl Fn(&mut ChaCha8Rng) -> Dd,
        op: impl Fn(&Dd) -> Dd,
        reference: impl Fn(Float) -> Float,
    ) -> f64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..SAMPLES)
            .map(|_| {
                let x = input(&mut rng);
                rel_err(&op(&x), &reference(x.to_float(REF_BITS)))
            })
            .fold(0.0, f64::max)
    }

    fn max_err_binary(
        seed: u64,
        op: impl Fn(Dd, Dd) -> Dd,
        reference: impl Fn(Float, Float) -> Float,
    ) -> f64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..SAMPLES)
            .map(|_| {
                let x = random_dd(&mut rng, -30.0, 30.0, true);
                let y = random_dd(&mut rng, -30.0, 30.0, true);
                rel_err(
                    &op(x, y),
                    &reference(x.to_float(REF_BITS), y.to_float(REF_BITS)),
                )
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn field_operations_are_accurate_to_106_bits() {
        let cases: [(&str, f64); 4] = [
            ("add", max_err_binary(1, |a, b| a + b, |a, b| a + b)),
            ("sub", max_err_binary(2, |a, b| a - b, |a, b| a - b)),
            ("mul", max_err_binary(3, |a, b| a * b, |a, b| a * b)),
            ("div", max_err_binary(4, |a, b| a / b, |a, b| a / b)),
        ];
        for (name, err) in cases {
            assert!(err < TOL, "{name}: max relative error {err:e}");
        }
    }

    #[test]
    fn sums_of_one_sign_are_accurate_with_one_error_free_sum() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        let mut worst: f64 = 0.0;
        for _ in 0..SAMPLES {
            let x = random_dd(&mut rng, -30.0, 30.0, true);
            let y = random_dd(&mut rng, -30.0, 30.0, false);
            let y = if x.hi < 0.0 { -y } else { y };
            let r = x.to_float(REF_BITS) + y.to_float(REF_BITS);
            worst = worst.max(rel_err(&x.add_same_sign(&y), &Float::with_val(REF_BITS, r)));
        }
        assert!(worst < TOL, "max relative error {worst:e}");
    }

    #[test]
    fn subtraction_under_cancellation_stays_relative() {
        // x − y with y = x(1 + δ): the accurate sum keeps the relative accuracy of the result.
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut worst: f64 = 0.0;
        for _ in 0..SAMPLES {
            let x = random_dd(&mut rng, -5.0, 5.0, true);
            let d = random_dd(&mut rng, -90.0, -10.0, true);
            let y = x * d.add_f64(1.0);
            let r = x.to_float(REF_BITS) - y.to_float(REF_BITS);
            worst = worst.max(rel_err(&(x - y), &Float::with_val(REF_BITS, r)));
        }
        assert!(worst < TOL, "max relative error {worst:e}");
    }

    #[test]
    fn functions_are_accurate_to_about_32_digits() {
        let pos = |rng: &mut ChaCha8Rng| random_dd(rng, -40.0, 40.0, false);
        let angle = |rng: &mut ChaCha8Rng| random_dd(rng, -20.0, 7.0, true);
        let exp_arg = |rng: &mut ChaCha8Rng| random_dd(rng, -30.0, 9.4, true);
        let cases: [(&str, f64); 6] = [
            ("sqrt", max_err_unary(11, pos, |x| x.sqrt(), |x| x.sqrt())),
            (
                "recip_sqrt",
                max_err_unary(18, pos, |x| x.recip_sqrt(), |x| x.recip_sqrt()),
            ),
            ("sin", max_err_unary(12, angle, |x| x.sin(), |x| x.sin())),
            ("cos", max_err_unary(13, angle, |x| x.cos(), |x| x.cos())),
            ("exp", max_err_unary(14, exp_arg, |x| x.exp(), |x| x.exp())),
            (
                "ln",
                // Away from 1 (where ln is accurate absolutely, tested below).
                max_err_unary(
                    15,
                    |rng| {
                        let x = pos(rng);
                        if (x.hi - 1.0).abs() < 0.05 {
                            x.add_f64(0.5)
                        } else {
                            x
                        }
                    },
                    |x| x.ln(),
                    |x| x.ln(),
                ),
            ),
        ];
        for (name, err) in cases {
            assert!(err < TOL, "{name}: max relative error {err:e}");
        }
    }

    #[test]
    fn ln_near_one_is_accurate_absolutely() {
        let mut rng = ChaCha8Rng::seed_from_u64(16);
        let mut worst: f64 = 0.0;
        for _ in 0..SAMPLES {
            let x = random_dd(&mut rng, -60.0, -4.4, true).add_f64(1.0);
            let reference = x.to_float(REF_BITS).ln();
            let d = Float::with_val(REF_BITS, &x.ln().to_float(REF_BITS) - &reference);
            worst = worst.max(d.to_f64().abs());
        }
        assert!(worst < 1e-31, "max absolute error {worst:e}");
    }

    #[test]
    fn atan2_is_accurate_in_every_quadrant() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut worst: f64 = 0.0;
        for _ in 0..SAMPLES {
            let y = random_dd(&mut rng, -20.0, 20.0, true);
            let x = random_dd(&mut rng, -20.0, 20.0, true);
            let reference = y.to_float(REF_BITS).atan2(&x.to_float(REF_BITS));
            worst = worst.max(rel_err(&y.atan2(&x), &reference));
        }
        assert!(worst < TOL, "atan2: max relative error {worst:e}");
        assert_eq!(Dd::ZERO.atan2(&Dd::from_f64_exact(-1.0)), Dd::PI);
        assert_eq!(Dd::ONE.atan2(&Dd::ZERO), Dd::PI.mul_f64(0.5));
    }

    #[test]
    fn constants_match_mpfr() {
        use rug::float::Constant;
        let pi = Float::with_val(400, Constant::Pi);
        let ln2 = Float::with_val(400, Constant::Log2);
        for (parts, reference) in [(PI, pi.clone()), (LN2, ln2)] {
            let mut sum = Float::with_val(400, 0);
            for p in parts {
                sum += p;
            }
            let err = Float::with_val(400, &sum - &reference) / &reference;
            assert!(err.to_f64().abs() < 1e-48, "{parts:?}");
        }
        let eps = Dd::ONE.epsilon();
        assert!(Dd::ONE + eps > Dd::ONE);
        assert_eq!(eps.hi, 2f64.powi(-105));
    }

    #[test]
    fn decimal_text_round_trips_to_full_precision() {
        let x = <Dd as Real>::parse("0.1", 0).unwrap();
        let tenth = Float::with_val(REF_BITS, Float::parse("0.1").unwrap());
        assert!(rel_err(&x, &tenth) < 2f64.powi(-106), "{x:?}");
        let third = Dd::ONE / Dd::from_f64_exact(3.0);
        let s = third.to_decimal(32);
        assert_eq!(s.matches('3').count(), 32, "{s}");
        let back = <Dd as Real>::parse(&s, 0).unwrap();
        assert!((back - third).abs().hi < 1e-32);
        assert!(<Dd as Real>::parse("not a number", 0).is_none());
        assert_eq!(Dd::from_f64_exact(-2.5).floor().hi, -3.0);
        assert_eq!(Dd::new(3.0, -1e-20).floor(), Dd::from_f64_exact(2.0));
    }

    /// The accuracy check is not vacuous: a "double-double" that multiplies in plain f64 fails it.
    #[test]
    fn accuracy_check_rejects_f64_arithmetic() {
        let err = max_err_binary(3, |a, b| Dd::from_f64_exact(a.hi * b.hi), |a, b| a * b);
        assert!(err > 1e-20, "f64 product passed as 106-bit: {err:e}");
        let err = max_err_unary(
            12,
            |rng| random_dd(rng, -20.0, 7.0, true),
            |x| Dd::from_f64_exact(x.hi.sin()),
            |x| x.sin(),
        );
        assert!(err > 1e-20, "f64 sine passed as 106-bit: {err:e}");
    }
}
