//! Roots of the separated polynomials, kept in homogeneous form ρ = [n : d] so that a root at
//! infinity (d = 0) or near it costs no precision, each with the name of the s-value it stands for.

use std::fmt;

use rsts_dynamics::Real;
use serde::Serialize;

/// Which value of the separated variable s a root stands for (seed sec. 3). For the first
/// variable the coordinate is x = 1/s₁, so the root `PlusA` is x = 1/a.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum RootLabel {
    #[serde(rename = "a")]
    PlusA,
    #[serde(rename = "-a")]
    MinusA,
    #[serde(rename = "b")]
    PlusB,
    #[serde(rename = "-b")]
    MinusB,
    #[serde(rename = "theta1")]
    Theta1,
    #[serde(rename = "theta2")]
    Theta2,
}

impl fmt::Display for RootLabel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RootLabel::PlusA => "a",
            RootLabel::MinusA => "-a",
            RootLabel::PlusB => "b",
            RootLabel::MinusB => "-b",
            RootLabel::Theta1 => "θ1",
            RootLabel::Theta2 => "θ2",
        })
    }
}

/// A root [n : d] of a radicand, in the coordinate of its variable.
#[derive(Clone, Debug)]
pub struct Root<T> {
    pub label: RootLabel,
    pub n: T,
    pub d: T,
}

impl<T: Real> Root<T> {
    pub fn new(label: RootLabel, n: T, d: T) -> Self {
        Self { label, n, d }
    }

    /// The same root in another scalar.
    pub fn map<U: Real>(&self, f: &impl Fn(&T) -> U) -> Root<U> {
        Root {
            label: self.label,
            n: f(&self.n),
            d: f(&self.d),
        }
    }

    /// The linear form L(v) = d·v − n that vanishes at the root.
    pub fn lin(&self, v: &T) -> T {
        self.d.clone() * v - &self.n
    }

    pub fn is_infinite(&self) -> bool {
        self.d == self.d.zero_like()
    }

    /// The value n/d (±∞ for d = 0), as f64 for display and ordering of finite roots.
    pub fn value_f64(&self) -> f64 {
        self.n.to_f64() / self.d.to_f64()
    }

    /// The value n/d in T (only for finite roots).
    pub fn value(&self) -> T {
        self.n.clone() / &self.d
    }

    /// Is the root strictly greater than the finite value v?
    pub fn above(&self, v: &T) -> bool {
        // n/d > v  ⇔  (n − d v)·d > 0
        let s = (self.n.clone() - self.d.clone() * v) * &self.d;
        s > s.zero_like()
    }
}
