//! Four double-doubles side by side ([`DoubleDouble4`]): every operation is the scalar
//! [`DoubleDouble`] operation applied to each lane, written as a loop over the four lanes of
//! `hi` and `lo` arrays so that a build with AVX2 and FMA (`#[target_feature]` on the caller,
//! everything here `#[inline(always)]`) runs the four lanes in one 256-bit register. Each lane
//! performs the same IEEE operations as the scalar code — the same roundings, the same fused
//! multiply-adds (Rust never contracts or reorders floating-point operations) — so each lane
//! is the scalar result bit for bit (tested); without AVX2 the loops run lane after lane.
//!
//! The [`Real`] implementation lets the closed form's generic formulas run on four samples at
//! once. A value has no single f64 ([`Real::to_f64`] panics unless all lanes are equal), so
//! generic code that branches on a value must not receive one; comparisons order the four
//! lanes together (`None` unless they agree).

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use super::functions::{sin_cos_tables, TWO_PI};
use super::{DoubleDouble, Real, DD_BITS};

/// Lanes of a [`DoubleDouble4`].
pub const LANES: usize = 4;

/// Four double-doubles: lane i is `hi[i] + lo[i]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DoubleDouble4 {
    pub hi: [f64; LANES],
    pub lo: [f64; LANES],
}

/// A [`DoubleDouble4`] whose lane `$i` is the [`DoubleDouble`] expression `$e`.
macro_rules! each_lane {
    (|$i:ident| $e:expr) => {{
        let mut out = DoubleDouble4::default();
        for $i in 0..LANES {
            let r: DoubleDouble = $e;
            out.hi[$i] = r.hi;
            out.lo[$i] = r.lo;
        }
        out
    }};
}

impl DoubleDouble4 {
    /// The same number in every lane.
    #[inline(always)]
    pub fn splat(x: DoubleDouble) -> Self {
        Self {
            hi: [x.hi; LANES],
            lo: [x.lo; LANES],
        }
    }

    /// Four numbers as lanes.
    #[inline(always)]
    pub fn from_lanes(x: [DoubleDouble; LANES]) -> Self {
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

    /// The four lanes.
    #[inline(always)]
    pub fn lanes(&self) -> [DoubleDouble; LANES] {
        std::array::from_fn(|i| self.lane(i))
    }

    /// −x in the lanes of `mask`, x in the others.
    #[inline(always)]
    fn negate_where(mask: [bool; LANES], x: Self) -> Self {
        each_lane!(|i| if mask[i] { -x.lane(i) } else { x.lane(i) })
    }

    /// Lane by lane: `a` where `mask`, else `b`.
    #[inline(always)]
    pub fn select(mask: [bool; LANES], a: Self, b: Self) -> Self {
        each_lane!(|i| if mask[i] { a.lane(i) } else { b.lane(i) })
    }

    /// Lane i times the f64 `b[i]` ([`DoubleDouble::mul_f64`]).
    #[inline(always)]
    pub fn mul_f64(self, b: [f64; LANES]) -> Self {
        each_lane!(|i| self.lane(i).mul_f64(b[i]))
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

    /// (sin 2πx, cos 2πx) of each lane: [`DoubleDouble::sin_cos_turns`] bit for bit, the
    /// reduction, the Taylor polynomials and the rotation by kπ/16 in the four lanes at once,
    /// the sixteenth k and the quadrant chosen per lane.
    #[inline(always)]
    pub fn sin_cos_turns(&self) -> (Self, Self) {
        if !every_lane(self.hi.map(f64::is_finite)) {
            let sc = self.lanes().map(|x| x.sin_cos_turns());
            return (
                Self::from_lanes(sc.map(|p| p.0)),
                Self::from_lanes(sc.map(|p| p.1)),
            );
        }
        let mut n = [0.0; LANES];
        for (n, h) in n.iter_mut().zip(&self.hi) {
            *n = (h * 32.0).round();
        }
        let r = each_lane!(|i| DoubleDouble::sum_f64(self.hi[i] - n[i] / 32.0, self.lo[i]));
        let t = r * Self::splat(TWO_PI);
        // As DoubleDouble::sin_cos_sixteenths: n = 8j + k.
        let (mut j, mut k) = ([0.0; LANES], [0.0; LANES]);
        for ((j, k), n) in j.iter_mut().zip(&mut k).zip(n) {
            *j = (n / 8.0).round();
            *k = n - 8.0 * *j;
        }
        let (s, c) = Self::sin_cos_reduced(t, k);
        // The quadrant q = j mod 4: (s, c), (c, −s), (−s, −c), (−c, s) as selects.
        let q = j.map(|j| (j.rem_euclid(4.0)) as u32);
        let odd = q.map(|q| q & 1 == 1);
        let sin = Self::negate_where(q.map(|q| q >= 2), Self::select(odd, c, s));
        let cos = Self::negate_where(q.map(|q| q == 1 || q == 2), Self::select(odd, s, c));
        (sin, cos)
    }

    /// [`DoubleDouble::sin_cos_reduced`] of each lane (|t| ≤ π/32, rotated by k[i]·π/16):
    /// the same operations in the same order.
    #[inline(always)]
    fn sin_cos_reduced(t: Self, k: [f64; LANES]) -> (Self, Self) {
        let tables = sin_cos_tables();
        let t2 = t.sqr();
        let (s, c) = (&tables.inverse_factorials, &tables.inverse_even_factorials);
        let (mut tail_s, mut tail_c) = ([s[8].hi; LANES], [c[8].hi; LANES]);
        for (sk, ck) in s[4..8].iter().zip(&c[4..8]).rev() {
            for i in 0..LANES {
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
        for i in 0..LANES {
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

/// All four are true (without the short cut of `Iterator::all`: no branch per lane).
#[inline(always)]
pub fn every_lane(x: [bool; LANES]) -> bool {
    (x[0] & x[1]) & (x[2] & x[3])
}

impl From<DoubleDouble> for DoubleDouble4 {
    #[inline(always)]
    fn from(x: DoubleDouble) -> Self {
        Self::splat(x)
    }
}

impl PartialOrd for DoubleDouble4 {
    /// The order of the lanes when all four agree.
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        let first = self.lane(0).partial_cmp(&other.lane(0))?;
        (1..LANES)
            .all(|i| self.lane(i).partial_cmp(&other.lane(i)) == Some(first))
            .then_some(first)
    }
}

impl Neg for DoubleDouble4 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        each_lane!(|i| -self.lane(i))
    }
}

macro_rules! lane_ops {
    ($($tr:ident $m:ident $atr:ident $am:ident),*) => {$(
        impl $tr for DoubleDouble4 {
            type Output = DoubleDouble4;
            #[inline(always)]
            fn $m(self, o: DoubleDouble4) -> DoubleDouble4 {
                each_lane!(|i| $tr::$m(self.lane(i), o.lane(i)))
            }
        }
        impl<'a> $tr<&'a DoubleDouble4> for DoubleDouble4 {
            type Output = DoubleDouble4;
            #[inline(always)]
            fn $m(self, o: &'a DoubleDouble4) -> DoubleDouble4 {
                $tr::$m(self, *o)
            }
        }
        impl $atr for DoubleDouble4 {
            #[inline(always)]
            fn $am(&mut self, o: DoubleDouble4) {
                *self = $tr::$m(*self, o);
            }
        }
        impl<'a> $atr<&'a DoubleDouble4> for DoubleDouble4 {
            #[inline(always)]
            fn $am(&mut self, o: &'a DoubleDouble4) {
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

impl Real for DoubleDouble4 {
    const NAME: &'static str = "dd×4";

    fn from_f64(x: f64, _bits: u32) -> Self {
        Self::splat(DoubleDouble::from_f64_exact(x))
    }
    fn parse(s: &str, bits: u32) -> Option<Self> {
        DoubleDouble::parse(s, bits).map(Self::splat)
    }
    fn prec(&self) -> u32 {
        DD_BITS
    }
    /// The value when all lanes hold the same one (four values have no single f64).
    fn to_f64(&self) -> f64 {
        let x = self.lane(0);
        assert!(
            self.lanes().iter().all(|y| y == &x),
            "to_f64 of four different double-doubles"
        );
        Real::to_f64(&x)
    }
    fn pi(_bits: u32) -> Self {
        Self::splat(DoubleDouble::PI)
    }
    fn epsilon(&self) -> Self {
        Self::splat(DoubleDouble::EPSILON)
    }
    /// Karp's step in the four lanes when all are positive and finite (the scalar code's
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
    #[inline(always)]
    fn abs(&self) -> Self {
        each_lane!(|i| Real::abs(&self.lane(i)))
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
    fn max_of(self, other: Self) -> Self {
        each_lane!(|i| self.lane(i).max_of(other.lane(i)))
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
