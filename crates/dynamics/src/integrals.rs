//! First integrals of the Euler–Poisson equations in Kharlamov's normalisation
//! A = aα, B = bβ, M = (2ω₁, 2ω₂, ω₃) (Kharlamov, RCD 10 (2005), eqs. (1.3); issue 2):
//!
//! ```text
//!   H = ω₁² + ω₂² + ω₃²/2 − (A₁ + B₂)
//!   K = (ω₁² − ω₂² + A₁ − B₂)² + (2ω₁ω₂ + A₂ + B₁)²
//!   G = ((M·A)² + (M·B)²)/4 + ω₃ M·(A×B)/2 − b² A₁ − a² B₂
//! ```
//!
//! On the invariant manifold N of the seed, K = r⁴m² and G = (p²h + r⁴m)/2.

use serde::Serialize;

use crate::fields::Fields;
use crate::scalar::Real;
use crate::state::State;
use crate::vec3::{cross, dot, scale};

/// The three first integrals at one state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Integrals<T> {
    #[serde(rename = "H")]
    pub h: T,
    #[serde(rename = "K")]
    pub k: T,
    #[serde(rename = "G")]
    pub g: T,
}

/// Energy H = ω₁² + ω₂² + ω₃²/2 − (aα₁ + bβ₂) (seed sec. 1).
pub fn energy<T: Real>(f: &Fields<T>, s: &State<T>) -> T {
    let [w1, w2, w3] = &s.omega;
    w1.square() + w2.square() + w3.square() / w3.lit(2.0)
        - (f.a.clone() * &s.alpha[0] + f.b.clone() * &s.beta[1])
}

/// Kowalevski-type integral K.
pub fn kowalevski<T: Real>(f: &Fields<T>, s: &State<T>) -> T {
    let [w1, w2, _] = &s.omega;
    let big_a = scale(&f.a, &s.alpha);
    let big_b = scale(&f.b, &s.beta);
    let two = w1.lit(2.0);
    let x = w1.square() - w2.square() + &big_a[0] - &big_b[1];
    let y = two * w1 * w2 + &big_a[1] + &big_b[0];
    x.square() + y.square()
}

/// Third integral G.
pub fn third<T: Real>(f: &Fields<T>, s: &State<T>) -> T {
    let [w1, w2, w3] = &s.omega;
    let two = w1.lit(2.0);
    let m = [two.clone() * w1, two.clone() * w2, w3.clone()];
    let big_a = scale(&f.a, &s.alpha);
    let big_b = scale(&f.b, &s.beta);
    let ma = dot(&m, &big_a);
    let mb = dot(&m, &big_b);
    let mab = dot(&m, &cross(&big_a, &big_b));
    (ma.square() + mb.square()) / w1.lit(4.0) + w3.clone() * mab / &two
        - f.b.square() * &big_a[0]
        - f.a.square() * &big_b[1]
}

/// H, K and G at a state.
pub fn integrals<T: Real>(f: &Fields<T>, s: &State<T>) -> Integrals<T> {
    Integrals {
        h: energy(f, s),
        k: kowalevski(f, s),
        g: third(f, s),
    }
}
