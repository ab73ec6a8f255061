//! L double-doubles side by side ([`DoubleDoubleLanes`]; [`DoubleDouble4`] is four of them):
//! every operation is the scalar [`DoubleDouble`] operation applied to each lane, written as a
//! loop over the lanes of `hi` and `lo` arrays so that a build with AVX2 and FMA
//! (`#[target_feature]` on the caller, everything here `#[inline(always)]`) runs four lanes in
//! one 256-bit register. Each lane performs the same IEEE operations as the scalar code — the
//! same roundings, the same fused multiply-adds (Rust never contracts or reorders
//! floating-point operations) — so each lane is the scalar result bit for bit (tested); without
//! AVX2 the loops run lane after lane.
//!
//! Kernels that choose per value (sin and cos in turns here; the errors kernel of f64 samples
//! in the harness) are written once over the lane count, as heyoka writes its kernels over the
//! batch size: one lane is the scalar function ([`DoubleDouble::sin_cos_turns`] is
//! [`DoubleDoubleLanes::sin_cos_turns`] at L = 1), four lanes the batch, with the same bits.
//!
//! The [`Real`] implementation lets the closed form's generic formulas run on four samples at
//! once. A value has no single f64 ([`Real::to_f64`] panics unless all lanes are equal), so
//! generic code that branches on a value must not receive one; comparisons order the lanes
//! together (`None` unless they agree).

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use super::functions::{sin_cos_tables, TWO_PI};
use super::{DoubleDouble, Real, DD_BITS};

/// Lanes of a [`DoubleDouble4`].
pub const LANES: usize = 4;

/// L double-doubles: lane i is `hi[i] + lo[i]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleDoubleLanes<const L: usize> {
    pub hi: [f64; L],
    pub lo: [f64; L],
}

/// Four double-doubles, the lanes of one AVX2 register.
pub type DoubleDouble4 = DoubleDoubleLanes<LANES>;

/// A [`DoubleDoubleLanes`] whose lane `$i` is the [`DoubleDouble`] expression `$e`.
macro_rules! each_lane {
    (|$i:ident| $e:expr) => {{
        let mut out = DoubleDoubleLanes::default();
        for $i in 0..L {
            let r: DoubleDouble = $e;
            out.hi[$i] = r.hi;
            out.lo[$i] = r.lo;
        }
        out
    }};
}

impl<const L: usize> Default for DoubleDoubleLanes<L> {
    #[inline(always)]
    fn default() -> Self {
        Self {
            hi: [0.0; L],
            lo: [0.0; L],
        }
    }
}

impl<const L: usize> DoubleDoubleLanes<L> {
    /// The same number in every lane.
    #[inline(always)]
    pub fn splat(x: DoubleDouble) -> Self {
        Self {
            hi: [x.hi; L],
            lo: [x.lo; L],
        }
    }

    /// L f64, exactly (low parts 0).
    #[inline(always)]
    pub fn from_f64_exact(x: [f64; L]) -> Self {
        Self {
            hi: x,
            lo: [0.0; L],
        }
    }

    /// L numbers as lanes.
    #[inline(always)]
    pub fn from_lanes(x: [DoubleDouble; L]) -> Self {
        each_lane!(|i| x[i])
    }

    /// Lane i.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> DoubleDouble {
        DoubleDouble {
            hi: self.hi[i],
            lo: self.lo[i],
        }
    }

    /// Replaces lane i.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, x: DoubleDouble) {
        self.hi[i] = x.hi;
        self.lo[i] = x.lo;
    }

    /// The lanes.
    #[inline(always)]
    pub fn lanes(&self) -> [DoubleDouble; L] {
        let mut out = [DoubleDouble::ZERO; L];
        for (i, x) in out.iter_mut().enumerate() {
            *x = self.lane(i);
        }
        out
    }

    /// −x in the lanes of `mask`, x in the others.
    #[inline(always)]
    fn negate_where(mask: [bool; L], x: Self) -> Self {
        each_lane!(|i| if mask[i] { -x.lane(i) } else { x.lane(i) })
    }

    /// Lane by lane: `a` where `mask`, else `b`.
    #[inline(always)]
    pub fn select(mask: [bool; L], a: Self, b: Self) -> Self {
        each_lane!(|i| if mask[i] { a.lane(i) } else { b.lane(i) })
    }

    /// Lane i times the f64 `b[i]` ([`DoubleDouble::mul_f64`]).
    #[inline(always)]
    pub fn mul_f64(self, b: [f64; L]) -> Self {
        each_lane!(|i| self.lane(i).mul_f64(b[i]))
    }

    /// Lane i plus the f64 `b[i]` ([`DoubleDouble::add_f64`]).
    #[inline(always)]
    pub fn add_f64(self, b: [f64; L]) -> Self {
        each_lane!(|i| self.lane(i).add_f64(b[i]))
    }

    /// The products a[i]·b[i] of f64, exactly ([`DoubleDouble::prod_f64`]).
    #[inline(always)]
    pub fn prod_f64(a: [f64; L], b: [f64; L]) -> Self {
        each_lane!(|i| DoubleDouble::prod_f64(a[i], b[i]))
    }

    /// self·f for a power of two f, exactly (barring underflow): both parts times f.
    #[inline(always)]
    pub fn scale_exact(self, f: f64) -> Self {
        let mut out = self;
        for i in 0..L {
            out.hi[i] = self.hi[i] * f;
            out.lo[i] = self.lo[i] * f;
        }
        out
    }

    /// self², lane by lane ([`DoubleDouble::sqr`]).
    #[inline(always)]
    pub fn sqr(self) -> Self {
        each_lane!(|i| self.lane(i).sqr())
    }

    /// self + b for addends that do not cancel, lane by lane (as `DoubleDouble`'s).
    #[inline(always)]
    pub fn add_no_cancel(self, b: Self) -> Self {
        each_lane!(|i| self.lane(i).add_no_cancel(b.lane(i)))
    }

    /// (sin 2πx, cos 2πx) of each lane: x = n/32 + r with n = round(32x) and |r| ≤ 1/64
    /// exactly (x.hi − n/32 is exact: both are multiples of x.hi's ulp, Sterbenz), t = 2π·r
    /// by one product (|t| ≤ π/32, relative error a few units of 2⁻¹⁰⁶), then as
    /// [`DoubleDouble::sin_cos`]. No multiple of π is subtracted: for an angle known in turns
    /// (a phase reduced modulo its period) this replaces the three-part reduction by one
    /// product. A lane that is not finite gives NaN.
    #[inline(always)]
    pub fn sin_cos_turns(&self) -> (Self, Self) {
        let finite = self.hi.map(f64::is_finite);
        let all = every_lane(finite);
        // A lane that is not finite from 0 (no table index from a NaN), then NaN: one copy of
        // the kernel for both cases.
        let x = if all {
            *self
        } else {
            Self::select(finite, *self, Self::default())
        };
        let (s, c) = x.sin_cos_turns_finite();
        if all {
            return (s, c);
        }
        let nan = Self::splat(DoubleDouble::nan());
        (Self::select(finite, s, nan), Self::select(finite, c, nan))
    }

    /// [`Self::sin_cos_turns`] of finite lanes.
    #[inline(always)]
    fn sin_cos_turns_finite(&self) -> (Self, Self) {
        let mut n = [0.0; L];
        for (n, h) in n.iter_mut().zip(&self.hi) {
            *n = (h * 32.0).round();
        }
        let r = each_lane!(|i| DoubleDouble::sum_f64(self.hi[i] - n[i] / 32.0, self.lo[i]));
        Self::sin_cos_sixteenths(r * Self::splat(TWO_PI), n)
    }

    /// (sin, cos) of n[i]·π/16 + t[i] for |t| ≤ π/32: n = 8j + k with |k| ≤ 4, the quadrant
    /// j mod 4 by symmetry, chosen per lane: (s, c), (c, −s), (−s, −c), (−c, s) as selects.
    #[inline(always)]
    pub(super) fn sin_cos_sixteenths(t: Self, n: [f64; L]) -> (Self, Self) {
        let (mut j, mut k) = ([0.0; L], [0.0; L]);
        for ((j, k), n) in j.iter_mut().zip(&mut k).zip(n) {
            *j = (n / 8.0).round();
            *k = n - 8.0 * *j;
        }
        let (s, c) = Self::sin_cos_reduced(t, k);
        let q = j.map(|j| (j.rem_euclid(4.0)) as u32);
        let odd = q.map(|q| q & 1 == 1);
        let sin = Self::negate_where(q.map(|q| q >= 2), Self::select(odd, c, s));
        let cos = Self::negate_where(q.map(|q| q == 1 || q == 2), Self::select(odd, s, c));
        (sin, cos)
    }

    /// (sin t, cos t) for |t| ≤ π/32, rotated by k[i]·π/16 (|k| ≤ 4) in lane i: sin t and cos t
    /// by their Taylor polynomials to t¹⁹ and t¹⁸ (Horner in t², coefficients 1/n! to 106 bits,
    /// the terms from t¹¹ and t¹⁰ on in f64; two independent chains, no square root), then the
    /// angle-sum formulas with sin, cos of kπ/16 from a table (QD's method). No sum here
    /// cancels (each one's smaller addend is below half the larger: |sin(π/16)cos(π/32)| >
    /// 2·|cos(π/16)sin(π/32)|), so they are [`DoubleDouble::add_no_cancel`].
    #[inline(always)]
    fn sin_cos_reduced(t: Self, k: [f64; L]) -> (Self, Self) {
        let tables = sin_cos_tables();
        let t2 = t.sqr();
        let (s, c) = (&tables.inverse_factorials, &tables.inverse_even_factorials);
        // The terms from t¹¹ on are below 1.3e-15 of the first (t⁸·3!/11! for |t| ≤ π/32):
        // their sum in plain f64 errs by ~1e-31 of the series (t³/6), ~1e-33 of sin t; those
        // of cos from t¹⁰ on, below 5e-15 of t²/2: ~1e-33 of cos t.
        let (mut tail_s, mut tail_c) = ([s[8].hi; L], [c[8].hi; L]);
        for (sk, ck) in s[4..8].iter().zip(&c[4..8]).rev() {
            for i in 0..L {
                tail_s[i] = tail_s[i] * t2.hi[i] + sk.hi;
                tail_c[i] = tail_c[i] * t2.hi[i] + ck.hi;
            }
        }
        let mut ps = t2.mul_f64(tail_s).add_no_cancel(Self::splat(s[3]));
        let mut pc = t2.mul_f64(tail_c).add_no_cancel(Self::splat(c[3]));
        for (sk, ck) in s[..3].iter().zip(&c[..3]).rev() {
            ps = (ps * t2).add_no_cancel(Self::splat(*sk));
            pc = (pc * t2).add_no_cancel(Self::splat(*ck));
        }
        let sin_t = t.add_no_cancel(t * t2 * ps);
        let cos_t = Self::splat(DoubleDouble::ONE).add_no_cancel(t2 * pc);
        let turned = k.map(|k| k != 0.0);
        if every_lane(turned.map(|x| !x)) {
            return (sin_t, cos_t);
        }
        // sin, cos of k·π/16 per lane (0 and 1 where k = 0: those lanes keep sin t, cos t).
        let (mut sk, mut ck) = (
            Self::splat(DoubleDouble::ZERO),
            Self::splat(DoubleDouble::ONE),
        );
        for i in 0..L {
            if turned[i] {
                let (s, c) = tables.sin_cos_k16[k[i].abs() as usize - 1];
                sk.set_lane(i, if k[i] < 0.0 { -s } else { s });
                ck.set_lane(i, c);
            }
        }
        let sin = (sk * cos_t).add_no_cancel(ck * sin_t);
        let cos = (ck * cos_t).add_no_cancel(-(sk * sin_t));
        (
            Self::select(turned, sin, sin_t),
            Self::select(turned, cos, cos_t),
        )
    }
}

/// All lanes are true (without the short cut of `Iterator::all`: no branch per lane).
#[inline(always)]
pub fn every_lane<const L: usize>(x: [bool; L]) -> bool {
    let mut all = true;
    for x in x {
        all &= x;
    }
    all
}

impl<const L: usize> From<DoubleDouble> for DoubleDoubleLanes<L> {
    #[inline(always)]
    fn from(x: DoubleDouble) -> Self {
        Self::splat(x)
    }
}

impl<const L: usize> PartialOrd for DoubleDoubleLanes<L> {
    /// The order of the lanes when all agree.
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        let first = self.lane(0).partial_cmp(&other.lane(0))?;
        (1..L)
            .all(|i| self.lane(i).partial_cmp(&other.lane(i)) == Some(first))
            .then_some(first)
    }
}

impl<const L: usize> Neg for DoubleDoubleLanes<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        each_lane!(|i| -self.lane(i))
    }
}

macro_rules! lane_ops {
    ($($tr:ident $m:ident $atr:ident $am:ident),*) => {$(
        impl<const L: usize> $tr for DoubleDoubleLanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: Self) -> Self {
                each_lane!(|i| $tr::$m(self.lane(i), o.lane(i)))
            }
        }
        impl<'a, const L: usize> $tr<&'a Self> for DoubleDoubleLanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: &'a Self) -> Self {
                $tr::$m(self, *o)
            }
        }
        impl<const L: usize> $atr for DoubleDoubleLanes<L> {
            #[inline(always)]
            fn $am(&mut self, o: Self) {
                *self = $tr::$m(*self, o);
            }
        }
        impl<'a, const L: usize> $atr<&'a Self> for DoubleDoubleLanes<L> {
            #[inline(always)]
            fn $am(&mut self, o: &'a Self) {
                *self = $tr::$m(*self, *o);
            }
        }
    )*};
}
lane_ops!(
    Add add AddAssign add_assign,
    Sub sub SubAssign sub_assign,
    Mul mul MulAssign mul_assign,
    Div div DivAssign div_assign
);

impl<const L: usize> Real for DoubleDoubleLanes<L> {
    const NAME: &'static str = match L {
        1 => "dd×1",
        4 => "dd×4",
        _ => "dd×L",
    };

    fn from_f64(x: f64, _bits: u32) -> Self {
        Self::splat(DoubleDouble::from_f64_exact(x))
    }
    fn parse(s: &str, bits: u32) -> Option<Self> {
        DoubleDouble::parse(s, bits).map(Self::splat)
    }
    fn prec(&self) -> u32 {
        DD_BITS
    }
    /// The value when all lanes hold the same one (lanes that differ have no single f64).
    fn to_f64(&self) -> f64 {
        let x = self.lane(0);
        assert!(
            self.lanes().iter().all(|y| y == &x),
            "to_f64 of lanes that differ"
        );
        Real::to_f64(&x)
    }
    fn pi(_bits: u32) -> Self {
        Self::splat(DoubleDouble::PI)
    }
    fn epsilon(&self) -> Self {
        Self::splat(DoubleDouble::EPSILON)
    }
    /// Karp's step in the lanes when all are positive and finite (the scalar code's
    /// common case), else lane by lane.
    #[inline(always)]
    fn sqrt(&self) -> Self {
        if every_lane(self.hi.map(|h| h > 0.0 && h.is_finite())) {
            each_lane!(|i| self.lane(i).karp_step())
        } else {
            each_lane!(|i| self.lane(i).sqrt_karp())
        }
    }
    #[inline(always)]
    fn recip_sqrt(&self) -> Self {
        each_lane!(|i| self.lane(i).recip_sqrt_newton())
    }
    #[inline(always)]
    fn add_same_sign(self, other: &Self) -> Self {
        self.add_no_cancel(*other)
    }
    /// The scalar [`Real::abs`] lane by lane, branch-free: both parts negated where the sign
    /// of the high part is set and it is no NaN.
    #[inline(always)]
    fn abs(&self) -> Self {
        let mut out = *self;
        for i in 0..L {
            let h = self.hi[i];
            let flip = u64::from(h.is_sign_negative() & !h.is_nan()) << 63;
            out.hi[i] = f64::from_bits(h.to_bits() ^ flip);
            out.lo[i] = f64::from_bits(self.lo[i].to_bits() ^ flip);
        }
        out
    }
    fn sin(&self) -> Self {
        each_lane!(|i| Real::sin(&self.lane(i)))
    }
    fn cos(&self) -> Self {
        each_lane!(|i| Real::cos(&self.lane(i)))
    }
    fn sin_cos(&self) -> (Self, Self) {
        let sc = self.lanes().map(|x| Real::sin_cos(&x));
        (
            Self::from_lanes(sc.map(|p| p.0)),
            Self::from_lanes(sc.map(|p| p.1)),
        )
    }
    #[inline(always)]
    fn square(&self) -> Self {
        self.sqr()
    }
    fn atan2(&self, x: &Self) -> Self {
        each_lane!(|i| self.lane(i).atan2(&x.lane(i)))
    }
    fn exp(&self) -> Self {
        each_lane!(|i| Real::exp(&self.lane(i)))
    }
    fn ln(&self) -> Self {
        each_lane!(|i| Real::ln(&self.lane(i)))
    }
    fn floor(&self) -> Self {
        each_lane!(|i| Real::floor(&self.lane(i)))
    }
    fn is_finite(&self) -> bool {
        self.lanes().iter().all(Real::is_finite)
    }
    /// The scalar [`Real::max_of`] lane by lane, branch-free: `other` where it is greater in
    /// the order of (hi, lo), else `self`.
    #[inline(always)]
    fn max_of(self, other: Self) -> Self {
        let (u, v) = (self, other);
        let mut out = u;
        for i in 0..L {
            let greater = (v.hi[i] > u.hi[i]) | ((v.hi[i] == u.hi[i]) & (v.lo[i] > u.lo[i]));
            let mask = 0u64.wrapping_sub(u64::from(greater));
            out.hi[i] = f64::from_bits((v.hi[i].to_bits() & mask) | (u.hi[i].to_bits() & !mask));
            out.lo[i] = f64::from_bits((v.lo[i].to_bits() & mask) | (u.lo[i].to_bits() & !mask));
        }
        out
    }
    fn min_of(self, other: Self) -> Self {
        each_lane!(|i| self.lane(i).min_of(other.lane(i)))
    }
    fn to_decimal(&self, digits: u32) -> String {
        let lanes: Vec<String> = self
            .lanes()
            .iter()
            .map(|x| Real::to_decimal(x, digits))
            .collect();
        format!("[{}]", lanes.join(", "))
    }
}

#[cfg(test)]
mod tests;
