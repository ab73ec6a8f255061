//! The normal type of N at a point (m, h) (issue 11).
//!
//! N is where the integrals are dependent: on N, dK = 2m·dL (L = 2G − p²H), so the Hamiltonian
//! field of F = K − 2m·L vanishes on the level (m, h) of N. Its linearisation there has exactly
//! one non-zero pair of eigenvalues ±λ, transverse to N, with
//!
//! ```text
//!   λ² = −4 r⁴ m ℓ²        (ℓ² = 2p²m² + 2hm + 1)
//! ```
//!
//! (tests/closed_form/manifold.rs computes the linearisation by nested dual numbers and checks tr J² = 2λ²,
//! J³ = λ²J and rank J = 2 at 50 digits in every camera). m > 0: λ imaginary, N is **normally
//! elliptic** (a perturbation off N stays near it); m < 0: λ real, N is **normally
//! hyperbolic** (a perturbation off N grows exponentially); m = 0 or ℓ = 0: degenerate.
//! λ is a rate of the flow of K − 2mL, not of the motion (the flow of H): the growth rate of a
//! departure from N along a motion is measured by the harness (docs/stability.md).

use std::fmt;

use rsts_dynamics::dual::Dual;
use rsts_dynamics::state::DIM;
use rsts_dynamics::{Fields, Real, State};
use serde::{Deserialize, Serialize};

use crate::constants::IntegralConstants;
use crate::manifold::distance::{gradient, hamiltonian_field, Kowalevski, LevelL};

/// Elliptic (normally stable), hyperbolic (normally unstable) or degenerate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NormalType {
    Elliptic,
    Hyperbolic,
    Degenerate,
}

impl NormalType {
    pub fn as_str(&self) -> &'static str {
        match self {
            NormalType::Elliptic => "elliptic",
            NormalType::Hyperbolic => "hyperbolic",
            NormalType::Degenerate => "degenerate",
        }
    }
}

impl fmt::Display for NormalType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The normal type with λ² (and |λ|).
#[derive(Clone, Debug, PartialEq)]
pub struct Normal<T> {
    pub kind: NormalType,
    /// λ² = −4r⁴mℓ².
    pub lambda2: T,
    /// |λ| = 2r²ℓ√|m|: the rate (hyperbolic) or the frequency (elliptic) of the normal motion
    /// under the flow of K − 2mL.
    pub lambda: T,
}

/// λ² = −4r⁴mℓ² and the normal type at the constants (m, h).
pub fn normal_type<T: Real>(c: &IntegralConstants<T>) -> Normal<T> {
    let r4 = c.r2.square();
    let ell2 = c.ell.square();
    let lambda2 = -(c.m.lit(4.0) * &r4 * &c.m * &ell2);
    let zero = c.m.zero_like();
    let kind = if lambda2 > zero {
        NormalType::Hyperbolic
    } else if lambda2 < zero {
        NormalType::Elliptic
    } else {
        NormalType::Degenerate
    };
    let lambda = lambda2.abs().sqrt();
    Normal {
        kind,
        lambda2,
        lambda,
    }
}

/// The Jacobian J of the field of K − 2mL at a state (9×9 in (ω, α, β)), by differentiating the
/// field (itself from first derivatives by dual numbers) once more with dual numbers.
pub fn linearisation<T: Real>(fields: &Fields<T>, s: &State<T>, m: &T) -> [[T; DIM]; DIM] {
    let lift = |x: &T| Dual::constant(x.clone());
    let dual_fields = Fields {
        a: lift(&fields.a),
        b: lift(&fields.b),
    };
    let x = s.to_array();
    // Column k: d/dε of X(x + ε e_k).
    let columns: [[T; DIM]; DIM] = std::array::from_fn(|k| {
        let seeded: [Dual<T>; DIM] = std::array::from_fn(|j| {
            let one = if j == k { 1.0 } else { 0.0 };
            Dual::new(x[j].clone(), x[j].lit(one))
        });
        let st = State::from_slice(&seeded);
        let xk = hamiltonian_field(&st, &gradient(&Kowalevski, &dual_fields, &st));
        let xl = hamiltonian_field(&st, &gradient(&LevelL, &dual_fields, &st));
        let two_m = m.lit(2.0) * m;
        std::array::from_fn(|i| xk[i].eps.clone() - two_m.clone() * &xl[i].eps)
    });
    std::array::from_fn(|i| std::array::from_fn(|j| columns[j][i].clone()))
}
