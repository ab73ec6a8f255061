//! Jets x + Σᵢ εᵢ·dxᵢ (εᵢεⱼ = 0): forward-mode differentiation along N directions at once — a
//! gradient in one evaluation instead of N evaluations over [`Dual`] numbers. Each direction's
//! derivative is computed by the very operations of [`Dual`] (same formulas, same order), so a
//! gradient from a jet equals, bit for bit, the N dual derivatives (test below).

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::dual::Dual;
use crate::scalar::Real;

/// x + Σᵢ εᵢ·dxᵢ over N directions.
#[derive(Clone, Debug)]
pub struct Jet<T, const N: usize> {
    pub re: T,
    pub eps: [T; N],
}

impl<T: Real, const N: usize> Jet<T, N> {
    /// The variable of direction `k` (derivative 1 along it, 0 along the others).
    pub fn variable(re: T, k: usize) -> Self {
        let eps = std::array::from_fn(|j| re.lit(if j == k { 1.0 } else { 0.0 }));
        Self { re, eps }
    }
    /// A constant (zero derivatives).
    pub fn constant(re: T) -> Self {
        let eps = std::array::from_fn(|_| re.zero_like());
        Self { re, eps }
    }
    /// Chain rule: f(x) with f'(x) = `d` (as [`Dual`]'s).
    fn chain(&self, value: T, d: T) -> Self {
        Self {
            re: value,
            eps: std::array::from_fn(|i| d.clone() * &self.eps[i]),
        }
    }
    /// The dual number of direction `k`.
    pub fn along(&self, k: usize) -> Dual<T> {
        Dual::new(self.re.clone(), self.eps[k].clone())
    }
}

impl<T: Real, const N: usize> PartialEq for Jet<T, N> {
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}
impl<T: Real, const N: usize> PartialOrd for Jet<T, N> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<T: Real, const N: usize> Neg for Jet<T, N> {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

impl<T: Real, const N: usize> Add<&Jet<T, N>> for Jet<T, N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: &Self) -> Self {
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e += d;
        }
        Self {
            re: self.re + &o.re,
            eps,
        }
    }
}
impl<T: Real, const N: usize> Sub<&Jet<T, N>> for Jet<T, N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: &Self) -> Self {
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e -= d;
        }
        Self {
            re: self.re - &o.re,
            eps,
        }
    }
}
// The derivative rules of [`Dual`], direction by direction.
#[allow(clippy::suspicious_arithmetic_impl)]
impl<T: Real, const N: usize> Mul<&Jet<T, N>> for Jet<T, N> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, o: &Self) -> Self {
        for (e, d) in self.eps.iter_mut().zip(&o.eps) {
            let x = std::mem::replace(e, o.re.zero_like());
            *e = x * &o.re + self.re.clone() * d;
        }
        self.re *= &o.re;
        self
    }
}
#[allow(clippy::suspicious_arithmetic_impl)]
impl<T: Real, const N: usize> Div<&Jet<T, N>> for Jet<T, N> {
    type Output = Self;
    #[inline(always)]
    fn div(mut self, o: &Self) -> Self {
        let re = self.re / &o.re;
        for (e, d) in self.eps.iter_mut().zip(&o.eps) {
            let x = std::mem::replace(e, o.re.zero_like());
            *e = (x - re.clone() * d) / &o.re;
        }
        Self { re, eps: self.eps }
    }
}

macro_rules! by_value_and_assign {
    ($($tr:ident $m:ident $atr:ident $am:ident),*) => {$(
        impl<T: Real, const N: usize> $tr<Jet<T, N>> for Jet<T, N> {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: Self) -> Self {
                $tr::<&Jet<T, N>>::$m(self, &o)
            }
        }
        impl<T: Real, const N: usize> $atr<Jet<T, N>> for Jet<T, N> {
            fn $am(&mut self, o: Self) {
                let s = std::mem::replace(self, Jet::constant(o.re.zero_like()));
                *self = $tr::<&Jet<T, N>>::$m(s, &o);
            }
        }
        impl<'a, T: Real, const N: usize> $atr<&'a Jet<T, N>> for Jet<T, N> {
            fn $am(&mut self, o: &Self) {
                let s = std::mem::replace(self, Jet::constant(o.re.zero_like()));
                *self = $tr::<&Jet<T, N>>::$m(s, o);
            }
        }
    )*};
}
by_value_and_assign!(Add add AddAssign add_assign, Sub sub SubAssign sub_assign,
                     Mul mul MulAssign mul_assign, Div div DivAssign div_assign);

impl<T: Real, const N: usize> Real for Jet<T, N> {
    const NAME: &'static str = "jet";

    fn from_f64(x: f64, bits: u32) -> Self {
        Self::constant(T::from_f64(x, bits))
    }
    fn parse(s: &str, bits: u32) -> Option<Self> {
        T::parse(s, bits).map(Self::constant)
    }
    fn prec(&self) -> u32 {
        self.re.prec()
    }
    fn to_f64(&self) -> f64 {
        self.re.to_f64()
    }
    fn pi(bits: u32) -> Self {
        Self::constant(T::pi(bits))
    }
    fn sqrt(&self) -> Self {
        let s = self.re.sqrt();
        let d = s.lit(0.5) / &s;
        self.chain(s, d)
    }
    fn abs(&self) -> Self {
        if self.re < self.re.zero_like() {
            -self.clone()
        } else {
            self.clone()
        }
    }
    fn sin(&self) -> Self {
        self.chain(self.re.sin(), self.re.cos())
    }
    fn cos(&self) -> Self {
        self.chain(self.re.cos(), -self.re.sin())
    }
    fn atan2(&self, x: &Self) -> Self {
        let r2 = self.re.square() + x.re.square();
        Self {
            re: self.re.atan2(&x.re),
            eps: std::array::from_fn(|i| {
                (x.re.clone() * &self.eps[i] - self.re.clone() * &x.eps[i]) / r2.clone()
            }),
        }
    }
    fn exp(&self) -> Self {
        let e = self.re.exp();
        self.chain(e.clone(), e)
    }
    fn ln(&self) -> Self {
        let d = self.re.one_like() / &self.re;
        self.chain(self.re.ln(), d)
    }
    fn floor(&self) -> Self {
        Self::constant(self.re.floor())
    }
    fn is_finite(&self) -> bool {
        self.re.is_finite() && self.eps.iter().all(Real::is_finite)
    }
    fn to_decimal(&self, digits: u32) -> String {
        self.re.to_decimal(digits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every direction of a jet is the dual number of that direction, bit for bit, through
    /// sums, products, quotients and the elementary functions.
    #[test]
    fn each_direction_is_its_dual_number() {
        fn f<T: Real>(x: &[T; 3]) -> T {
            let [a, b, c] = x;
            let p = a.clone() * b - c.square() / a.lit(3.0);
            let q = (p.clone() + c).sin() * a.exp() + b.atan2(c) - p.abs().sqrt();
            q * c.cos() / (a.clone() * a + &b.ln().square())
        }
        let x = [0.7_f64, 1.3, -0.4];
        let jet = f(&std::array::from_fn::<Jet<f64, 3>, 3, _>(|k| {
            Jet::variable(x[k], k)
        }));
        for k in 0..3 {
            let dual = f(&std::array::from_fn(|j| {
                Dual::new(x[j], if j == k { 1.0 } else { 0.0 })
            }));
            assert_eq!(
                jet.along(k).eps.to_bits(),
                dual.eps.to_bits(),
                "direction {k}"
            );
            assert_eq!(jet.re.to_bits(), dual.re.to_bits());
        }
        assert!(jet.eps.iter().all(|e| *e != 0.0));
    }
}
