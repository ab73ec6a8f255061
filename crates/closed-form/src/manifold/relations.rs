//! The invariant relations of N in the phase variables (ω, α, β) (issue 11; the manifold of
//! Kharlamov's critical subsystem, seed sec. 1).
//!
//! With A = aα, B = bβ, ξ₁ = A₁ − B₂, ξ₂ = A₂ + B₁, ρ² = ξ₁² + ξ₂², U = ω₁ξ₁ + ω₂ξ₂,
//! V = ω₂ξ₁ − ω₁ξ₂, and in complex form χ = ξ₁ + iξ₂, w = ω₁ + iω₂, z = A₃ + iB₃, Z = w² + χ
//! (so that K = |Z|²):
//!
//! ```text
//!   Q  = Z·χ̄/χ,            ρ²Q = (U + iV)² + ρ²χ̄            (|Q|² = K)
//!   f₂ = ω₃ − 2 Re(z·w/χ)
//!   N  = {Im Q = 0, f₂ = 0} = {F₁ = 0, F₂ = 0},   F₁ = ρ² Im Q = 2UV − ρ²ξ₂,
//!                                                  F₂ = ρ² f₂ = ω₃ρ² − 2[(A₃ω₁ − B₃ω₂)ξ₁ + (A₃ω₂ + B₃ω₁)ξ₂]
//!   M  = Re Q / r² = [ξ₁ + (U² − V²)/ρ²]/r²          (the partial integral: M = m on N)
//! ```
//!
//! Along any motion dQ/dt = i·f₂·Q (tests/closed_form/manifold.rs checks it at random states), so |Q|² = K is
//! conserved everywhere and Q is frozen on N. Im Q, f₂ and M divide by ρ², which vanishes where
//! s₁ passes through infinity (on N when m < 0); the regular measure of the distance from N is
//! [`crate::manifold::distance`].

use rsts_dynamics::{Fields, Real, State};

/// The quantities of the relations at one state (polynomial ones and the quotients by ρ²).
#[derive(Clone, Debug)]
pub struct Relations<T> {
    /// ξ₁ = aα₁ − bβ₂, ξ₂ = aα₂ + bβ₁ (χ = ξ₁ + iξ₂).
    pub xi: [T; 2],
    /// ρ² = |χ|².
    pub rho2: T,
    /// U = ω₁ξ₁ + ω₂ξ₂, V = ω₂ξ₁ − ω₁ξ₂ (U + iV = w·χ̄).
    pub u: T,
    pub v: T,
    /// ρ²·Re Q = U² − V² + ρ²ξ₁.
    pub rho2_re_q: T,
    /// F₁ = ρ² Im Q = 2UV − ρ²ξ₂.
    pub big_f1: T,
    /// F₂ = ρ² f₂ = ω₃ρ² − 2[(aα₃ω₁ − bβ₃ω₂)ξ₁ + (aα₃ω₂ + bβ₃ω₁)ξ₂].
    pub big_f2: T,
}

impl<T: Real> Relations<T> {
    /// The relations at a state for the fields (a, b).
    pub fn at(fields: &Fields<T>, s: &State<T>) -> Self {
        let (a, b) = (&fields.a, &fields.b);
        let [w1, w2, w3] = &s.omega;
        let xi1 = a.clone() * &s.alpha[0] - b.clone() * &s.beta[1];
        let xi2 = a.clone() * &s.alpha[1] + b.clone() * &s.beta[0];
        let rho2 = xi1.square() + xi2.square();
        let u = w1.clone() * &xi1 + w2.clone() * &xi2;
        let v = w2.clone() * &xi1 - w1.clone() * &xi2;
        let two = w1.lit(2.0);
        let rho2_re_q = u.square() - v.square() + rho2.clone() * &xi1;
        let big_f1 = two.clone() * &u * &v - rho2.clone() * &xi2;
        // z·w = (A₃ + iB₃)(ω₁ + iω₂); Re(z·w·χ̄) = Re(zw)ξ₁ + Im(zw)ξ₂.
        let a3 = a.clone() * &s.alpha[2];
        let b3 = b.clone() * &s.beta[2];
        let zw_re = a3.clone() * w1 - b3.clone() * w2;
        let zw_im = a3 * w2 + b3 * w1;
        let big_f2 = w3.clone() * &rho2 - two * (zw_re * &xi1 + zw_im * &xi2);
        Self {
            xi: [xi1, xi2],
            rho2,
            u,
            v,
            rho2_re_q,
            big_f1,
            big_f2,
        }
    }

    /// Q = Z·χ̄/χ as (Re Q, Im Q) (singular at ρ = 0).
    pub fn q(&self) -> [T; 2] {
        [
            self.rho2_re_q.clone() / &self.rho2,
            self.big_f1.clone() / &self.rho2,
        ]
    }

    /// f₂ = ω₃ − 2 Re(z·w/χ) = F₂/ρ² (singular at ρ = 0).
    pub fn f2(&self) -> T {
        self.big_f2.clone() / &self.rho2
    }

    /// The partial integral M = Re Q / r² (equal to m on N; singular at ρ = 0).
    pub fn partial_integral(&self, fields: &Fields<T>) -> T {
        self.rho2_re_q.clone() / (self.rho2.clone() * fields.r2())
    }
}

/// L = 2G − p²H, the combination of the integrals that equals r⁴m on N (with K = r⁴m²).
pub fn level_l<T: Real>(fields: &Fields<T>, s: &State<T>) -> T {
    let i = rsts_dynamics::integrals(fields, s);
    i.g.lit(2.0) * &i.g - fields.p2() * &i.h
}

/// m from the integrals, (2G − p²H)/r⁴: regular everywhere, equal to M on N.
pub fn m_of_integrals<T: Real>(fields: &Fields<T>, s: &State<T>) -> T {
    let r2 = fields.r2();
    level_l(fields, s) / (r2.clone() * &r2)
}
