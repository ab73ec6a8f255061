//! Dual numbers x + ε·dx (ε² = 0) over any [`Real`]: forward-mode differentiation of code that is
//! written once over [`Real`]. Evaluating a function at `x + ε·v` gives its value and its
//! directional derivative along v. Used for derivatives along the vector field (dI/dt = ∇I·f) and
//! for the chain rule through the separated variables in the closed-form checks.

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::scalar::Real;

/// x + ε·dx.
#[derive(Clone, Debug)]
pub struct Dual<T> {
    pub re: T,
    pub eps: T,
}

impl<T: Real> Dual<T> {
    pub fn new(re: T, eps: T) -> Self {
        Self { re, eps }
    }
    /// A constant (zero derivative).
    pub fn constant(re: T) -> Self {
        let eps = re.zero_like();
        Self { re, eps }
    }
    /// Chain rule: f(x) with f'(x) = `d`.
    fn chain(&self, value: T, d: T) -> Self {
        Self {
            re: value,
            eps: d * &self.eps,
        }
    }
}

impl<T: Real> PartialEq for Dual<T> {
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}
impl<T: Real> PartialOrd for Dual<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<T: Real> Neg for Dual<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            re: -self.re,
            eps: -self.eps,
        }
    }
}

impl<T: Real> Add<&Dual<T>> for Dual<T> {
    type Output = Self;
    fn add(self, o: &Self) -> Self {
        Self {
            re: self.re + &o.re,
            eps: self.eps + &o.eps,
        }
    }
}
impl<T: Real> Sub<&Dual<T>> for Dual<T> {
    type Output = Self;
    fn sub(self, o: &Self) -> Self {
        Self {
            re: self.re - &o.re,
            eps: self.eps - &o.eps,
        }
    }
}
impl<T: Real> Mul<&Dual<T>> for Dual<T> {
    type Output = Self;
    fn mul(self, o: &Self) -> Self {
        Self {
            eps: self.eps * &o.re + self.re.clone() * &o.eps,
            re: self.re * &o.re,
        }
    }
}
impl<T: Real> Div<&Dual<T>> for Dual<T> {
    type Output = Self;
    fn div(self, o: &Self) -> Self {
        let re = self.re / &o.re;
        let eps = (self.eps - re.clone() * &o.eps) / &o.re;
        Self { re, eps }
    }
}

macro_rules! by_value_and_assign {
    ($($tr:ident $m:ident $atr:ident $am:ident),*) => {$(
        impl<T: Real> $tr<Dual<T>> for Dual<T> {
            type Output = Self;
            fn $m(self, o: Self) -> Self {
                $tr::<&Dual<T>>::$m(self, &o)
            }
        }
        impl<T: Real> $atr<Dual<T>> for Dual<T> {
            fn $am(&mut self, o: Self) {
                let s = std::mem::replace(self, Dual::constant(o.re.zero_like()));
                *self = $tr::<&Dual<T>>::$m(s, &o);
            }
        }
        impl<'a, T: Real> $atr<&'a Dual<T>> for Dual<T> {
            fn $am(&mut self, o: &Self) {
                let s = std::mem::replace(self, Dual::constant(o.re.zero_like()));
                *self = $tr::<&Dual<T>>::$m(s, o);
            }
        }
    )*};
}
by_value_and_assign!(Add add AddAssign add_assign, Sub sub SubAssign sub_assign,
                     Mul mul MulAssign mul_assign, Div div DivAssign div_assign);

impl<T: Real> Real for Dual<T> {
    const NAME: &'static str = "dual";

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
        // d atan2(y, x) = (x dy − y dx)/(x² + y²)
        let r2 = self.re.square() + x.re.square();
        Self {
            re: self.re.atan2(&x.re),
            eps: (x.re.clone() * &self.eps - self.re.clone() * &x.eps) / r2,
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
        self.re.is_finite() && self.eps.is_finite()
    }
    fn to_decimal(&self, digits: u32) -> String {
        self.re.to_decimal(digits)
    }
}

impl<T: Real> From<T> for Dual<T> {
    /// A constant embedded as a dual number.
    fn from(re: T) -> Self {
        Self::constant(re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_elementary_functions() {
        let x = Dual::new(0.7_f64, 1.0);
        let y = (x.sin() * x.exp() / (x.clone() + &Dual::constant(1.0))).sqrt();
        // Central difference of the same expression.
        let f = |t: f64| (t.sin() * t.exp() / (t + 1.0)).sqrt();
        let h = 1e-6;
        let fd = (f(0.7 + h) - f(0.7 - h)) / (2.0 * h);
        assert!((y.eps - fd).abs() < 1e-8, "{} vs {}", y.eps, fd);
        let a = Dual::new(0.3_f64, 1.0).atan2(&Dual::constant(-0.4));
        let g = |t: f64| t.atan2(-0.4);
        assert!((a.eps - (g(0.3 + h) - g(0.3 - h)) / (2.0 * h)).abs() < 1e-8);
    }
}
