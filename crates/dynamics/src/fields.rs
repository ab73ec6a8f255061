//! The two constant force fields: strengths `a` (along α, applied at e₁) and `b` (along β,
//! applied at e₂). The seed (sec. 1) takes a > b > 0; b = 0 is the classical Kovalevskaya top and
//! b = a the Yehia case. This crate accepts a > 0, 0 ≤ b ≤ a.

use crate::error::DynamicsError;
use crate::scalar::Real;

/// Field strengths (a, b).
#[derive(Clone, Debug, PartialEq)]
pub struct Fields<T> {
    pub a: T,
    pub b: T,
}

impl<T: Real> Fields<T> {
    /// Checked constructor: a > 0, 0 ≤ b ≤ a, both finite.
    pub fn new(a: T, b: T) -> Result<Self, DynamicsError> {
        if !a.is_finite() {
            return Err(DynamicsError::NotFinite("a"));
        }
        if !b.is_finite() {
            return Err(DynamicsError::NotFinite("b"));
        }
        if a <= a.zero_like() {
            return Err(DynamicsError::Fields(format!(
                "a must be positive, got a = {}",
                a.to_f64()
            )));
        }
        if b < b.zero_like() {
            return Err(DynamicsError::Fields(format!(
                "b must be non-negative, got b = {}",
                b.to_f64()
            )));
        }
        if b > a {
            return Err(DynamicsError::Fields(format!(
                "need b <= a (a is the stronger field), got a = {}, b = {}",
                a.to_f64(),
                b.to_f64()
            )));
        }
        Ok(Self { a, b })
    }

    /// p² = a² + b² (seed sec. 1).
    pub fn p2(&self) -> T {
        self.a.square() + self.b.square()
    }
    /// r² = a² − b² (seed sec. 1).
    pub fn r2(&self) -> T {
        self.a.square() - self.b.square()
    }
}

impl Fields<f64> {
    /// The same fields in another scalar type at `bits` bits (an f64 converts exactly).
    pub fn to_scalar<U: Real>(&self, bits: u32) -> Fields<U> {
        Fields {
            a: U::from_f64(self.a, bits),
            b: U::from_f64(self.b, bits),
        }
    }
}
