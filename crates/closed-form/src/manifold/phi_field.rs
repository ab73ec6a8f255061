//! ∇Φ and the derivative of X_Φ written out (stop 28): the geometry of `rsts check` evaluates
//! them at every sample, and forward differentiation of the integrals over a jet of nine
//! directions costs ~10× the closed formulas below. They differentiate the one definition of H,
//! K, G in `rsts_dynamics::integrals` (A = aα, B = bβ, M = (2ω₁, 2ω₂, ω₃)):
//!
//! ```text
//!   ∇H = (2ω₁, 2ω₂, ω₃; −a, 0, 0; 0, −b, 0)
//!   K = X² + Y²,  X = ω₁² − ω₂² + A₁ − B₂,  Y = 2ω₁ω₂ + A₂ + B₁,  ∇K = 2X∇X + 2Y∇Y
//!   G = (P² + Q²)/4 + ω₃R/2 − b²A₁ − a²B₂,  P = M·A, Q = M·B, R = M·(A×B):
//!     ∂G/∂M = (PA + QB + ω₃ A×B)/2,  ∂G/∂ω₃ += R/2,
//!     ∂G/∂A = (PM + ω₃ B×M)/2 − b²e₁,  ∂G/∂B = (QM + ω₃ M×A)/2 − a²e₂
//!   ∇Φ = r⁴∇K − 2L∇L,  L = 2G − p²H,  ∇L = 2∇G − p²∇H
//! ```
//!
//! A test (crates/closed-form/tests/closed_form/phi_field.rs) compares each gradient with the jet gradient of
//! the definitions at random states, in f64 and at 200 bits.

use rsts_dynamics::integrals::{energy, third};
use rsts_dynamics::jet::Jet;
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::{cross, dot, scale};
use rsts_dynamics::{Fields, Real, State};

use crate::manifold::distance::hamiltonian_field;

/// ∇H, ∇K and ∇G in (ω, α, β) at one state.
#[derive(Clone, Debug)]
pub struct IntegralGradients<T> {
    pub h: [T; DIM],
    pub k: [T; DIM],
    pub g: [T; DIM],
}

/// ∇H, ∇K, ∇G at a state (the formulas of the module doc).
pub fn integral_gradients<T: Real>(fields: &Fields<T>, s: &State<T>) -> IntegralGradients<T> {
    let [w1, w2, w3] = &s.omega;
    let (a, b) = (&fields.a, &fields.b);
    let zero = w1.zero_like();
    let two = w1.lit(2.0);
    let half = w1.lit(0.5);
    let big_a = scale(a, &s.alpha);
    let big_b = scale(b, &s.beta);
    let h = [
        two.clone() * w1,
        two.clone() * w2,
        w3.clone(),
        -a.clone(),
        zero.clone(),
        zero.clone(),
        zero.clone(),
        -b.clone(),
        zero.clone(),
    ];
    let x = w1.square() - w2.square() + &big_a[0] - &big_b[1];
    let y = two.clone() * w1 * w2 + &big_a[1] + &big_b[0];
    let (x2, y2) = (two.clone() * &x, two.clone() * &y);
    let k = [
        x2.clone() * &two * w1 + y2.clone() * &two * w2,
        y2.clone() * &two * w1 - x2.clone() * &two * w2,
        zero.clone(),
        x2.clone() * a,
        y2.clone() * a,
        zero.clone(),
        y2 * b,
        -(x2 * b),
        zero,
    ];
    let m = [two.clone() * w1, two.clone() * w2, w3.clone()];
    let p = dot(&m, &big_a);
    let q = dot(&m, &big_b);
    let axb = cross(&big_a, &big_b);
    let r = dot(&m, &axb);
    let d_m: [T; 3] = std::array::from_fn(|i| {
        (p.clone() * &big_a[i] + q.clone() * &big_b[i] + w3.clone() * &axb[i]) * &half
    });
    let (bxm, mxa) = (cross(&big_b, &m), cross(&m, &big_a));
    let mut d_a: [T; 3] =
        std::array::from_fn(|i| (p.clone() * &m[i] + w3.clone() * &bxm[i]) * &half);
    let mut d_b: [T; 3] =
        std::array::from_fn(|i| (q.clone() * &m[i] + w3.clone() * &mxa[i]) * &half);
    d_a[0] -= &b.square();
    d_b[1] -= &a.square();
    let g = [
        two.clone() * &d_m[0],
        two * &d_m[1],
        d_m[2].clone() + r * &half,
        a.clone() * &d_a[0],
        a.clone() * &d_a[1],
        a.clone() * &d_a[2],
        b.clone() * &d_b[0],
        b.clone() * &d_b[1],
        b.clone() * &d_b[2],
    ];
    IntegralGradients { h, k, g }
}

/// ∇Φ = r⁴∇K − 2L∇L at a state, L = 2G − p²H from the integrals' definition.
pub fn phi_gradient<T: Real>(fields: &Fields<T>, s: &State<T>) -> [T; DIM] {
    let d = integral_gradients(fields, s);
    let two = s.omega[0].lit(2.0);
    let p2 = fields.p2();
    let r4 = fields.r2().square();
    let l = two.clone() * &third(fields, s) - p2.clone() * &energy(fields, s);
    let two_l = two.clone() * &l;
    std::array::from_fn(|i| {
        let dl = two.clone() * &d.g[i] - p2.clone() * &d.h[i];
        r4.clone() * &d.k[i] - two_l.clone() * &dl
    })
}

/// X_Φ at a state from [`phi_gradient`].
pub fn phi_field<T: Real>(fields: &Fields<T>, s: &State<T>) -> [T; DIM] {
    hamiltonian_field(s, &phi_gradient(fields, s))
}

/// The derivative of X_Φ along six directions (δω, δα, δβ) of the phase space at a state: one
/// evaluation of [`phi_field`] over a jet of six directions (column j of the 9×6 matrix is the
/// derivative along direction j, bit for bit that of a dual number seeded along it). The gain
/// uses the written-out [`crate::manifold::field_derivative::phi_field_derivative`]; a test
/// compares the two.
pub fn phi_field_derivative_jet(
    fields: &Fields<f64>,
    s: &State<f64>,
    directions: &[[f64; DIM]; 6],
) -> [[f64; 6]; DIM] {
    let jet_fields = Fields {
        a: Jet::constant(fields.a),
        b: Jet::constant(fields.b),
    };
    let x = s.to_array();
    let seeded: [Jet<f64, 6>; DIM] = std::array::from_fn(|k| Jet {
        re: x[k],
        eps: std::array::from_fn(|j| directions[j][k]),
    });
    phi_field(&jet_fields, &State::from_slice(&seeded)).map(|c| c.eps)
}
