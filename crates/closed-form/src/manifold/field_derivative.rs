//! The derivative of X_Φ along a direction δ = (δω, δα, δβ), written out (stop 30): the gain of
//! every saturated sample of `rsts check` needs it along six directions, and one evaluation of
//! [`phi_field`] over a jet of six directions ([`phi_field_derivative_jet`]) costs 1.6× the
//! instructions of these formulas (camera V's saturated samples, stop 30). X_Φ = 𝔅(x)∇Φ(x) with 𝔅 the Lie–Poisson structure, linear in x, so
//!
//! ```text
//!   DX_Φ·δ = 𝔅(δ)∇Φ + 𝔅(x)(∇²Φ·δ)
//!   ∇²Φ·δ = r⁴ ∇²K·δ − 2(∇L·δ)∇L − 2L ∇²L·δ,   ∇²L·δ = 2∇²G·δ − p² ∇²H·δ
//!   ∇²H·δ = (2δω₁, 2δω₂, δω₃; 0; 0)
//!   ∇²K·δ = 2(∇X·δ)∇X + 2X ∇²X·δ + 2(∇Y·δ)∇Y + 2Y ∇²Y·δ,
//!     ∇²X·δ = (2δω₁, −2δω₂, 0; 0; 0),  ∇²Y·δ = (2δω₂, 2δω₁, 0; 0; 0)
//!   ∇²G·δ: the product rule on ∇G of [`super::phi_field`] (δM = (2δω₁, 2δω₂, δω₃), δA = aδα,
//!     δB = bδβ, δP = δM·A + M·δA, δQ = δM·B + M·δB, δR = δM·(A×B) + M·(δA×B + A×δB)):
//!     δ∂G/∂M = (δP A + P δA + δQ B + Q δB + δω₃ A×B + ω₃ (δA×B + A×δB))/2,  δ∂G/∂ω₃ += δR/2,
//!     δ∂G/∂A = (δP M + P δM + δω₃ B×M + ω₃ (δB×M + B×δM))/2,
//!     δ∂G/∂B = (δQ M + Q δM + δω₃ M×A + ω₃ (δM×A + M×δA))/2
//! ```
//!
//! in the notation of [`super::phi_field`] (X = ω₁² − ω₂² + A₁ − B₂, Y = 2ω₁ω₂ + A₂ + B₁,
//! L = 2G − p²H). A test (crates/closed-form/tests/closed_form/phi_field.rs) compares it with the jet
//! derivative at random states.
//!
//! [`phi_field`]: super::phi_field::phi_field
//! [`phi_field_derivative_jet`]: super::phi_field::phi_field_derivative_jet

use rsts_dynamics::integrals::{energy, third};
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::{cross, dot};
use rsts_dynamics::{Fields, State};

use crate::manifold::lanes::{self, Lanes};
use crate::manifold::phi_field::integral_gradients;

/// What DX_Φ·δ needs of the state, computed once for every direction.
pub struct PhiFieldDerivative {
    state: State<f64>,
    fields: [f64; 2],
    /// ∇Φ, ∇L, L, r⁴, p².
    grad_phi: [f64; DIM],
    grad_l: [f64; DIM],
    l: f64,
    r4: f64,
    p2: f64,
    /// X, Y and their gradients.
    x: f64,
    y: f64,
    grad_x: [f64; DIM],
    grad_y: [f64; DIM],
    /// M, A, B, P = M·A, Q = M·B, A×B.
    m: [f64; 3],
    big_a: [f64; 3],
    big_b: [f64; 3],
    p: f64,
    q: f64,
    axb: [f64; 3],
    /// B×M, M×A.
    bxm: [f64; 3],
    mxa: [f64; 3],
}

/// ∇²G·δ from (δ∂G/∂M, δ∂G/∂A, δ∂G/∂B, δR) of the module doc and (a/2, b/2).
#[inline(always)]
fn hessian_g_of(
    [half_a, half_b]: [f64; 2],
    g_m: [Lanes; 3],
    g_a: [Lanes; 3],
    g_b: [Lanes; 3],
    dr: Lanes,
) -> [Lanes; DIM] {
    [
        g_m[0],
        g_m[1],
        0.5 * (g_m[2] + dr),
        half_a * g_a[0],
        half_a * g_a[1],
        half_a * g_a[2],
        half_b * g_b[0],
        half_b * g_b[1],
        half_b * g_b[2],
    ]
}

impl PhiFieldDerivative {
    /// The shared terms at the state `s`.
    pub fn new(fields: &Fields<f64>, s: &State<f64>) -> Self {
        let (a, b) = (fields.a, fields.b);
        let d = integral_gradients(fields, s);
        let p2 = a * a + b * b;
        let r2 = a * a - b * b;
        let r4 = r2 * r2;
        let l = 2.0 * third(fields, s) - p2 * energy(fields, s);
        let grad_l: [f64; DIM] = std::array::from_fn(|i| 2.0 * d.g[i] - p2 * d.h[i]);
        let grad_phi = std::array::from_fn(|i| r4 * d.k[i] - 2.0 * l * grad_l[i]);
        let [w1, w2, w3] = s.omega;
        let big_a = s.alpha.map(|v| a * v);
        let big_b = s.beta.map(|v| b * v);
        let m = [2.0 * w1, 2.0 * w2, w3];
        Self {
            state: s.clone(),
            fields: [a, b],
            grad_phi,
            grad_l,
            l,
            r4,
            p2,
            x: w1 * w1 - w2 * w2 + big_a[0] - big_b[1],
            y: 2.0 * w1 * w2 + big_a[1] + big_b[0],
            grad_x: [2.0 * w1, -2.0 * w2, 0.0, a, 0.0, 0.0, 0.0, -b, 0.0],
            grad_y: [2.0 * w2, 2.0 * w1, 0.0, 0.0, a, 0.0, b, 0.0, 0.0],
            p: dot(&m, &big_a),
            q: dot(&m, &big_b),
            axb: cross(&big_a, &big_b),
            bxm: cross(&big_b, &m),
            mxa: cross(&m, &big_a),
            m,
            big_a,
            big_b,
        }
    }

    /// DX_Φ·δ = 𝔅(δ)∇Φ + 𝔅(x)(∇²Φ·δ): lane 0 of [`PhiFieldDerivative::along_six`] with `delta`
    /// there and 0 in the other lanes (each lane is computed apart from the others, so it is the
    /// number of `delta` alone; the formulas are written once, lane by lane).
    pub fn along(&self, delta: &[f64; DIM]) -> [f64; DIM] {
        let mut directions = [[0.0; DIM]; 6];
        directions[0] = *delta;
        self.along_six(&directions).map(|lane| lane.0[0])
    }
}

impl PhiFieldDerivative {
    /// DX_Φ·δ along six directions at once (stop 31), lane j along `directions[j]`, as
    /// `out[k]` = component k: the same operations in the same order on each lane, the blocks of
    /// δ that vanish not skipped (their products are exact zeros, which leave every non-zero sum
    /// unchanged: stop 31 checked each lane bit for bit against the one-direction formulas that
    /// skipped them). Inlined into its caller, with the caller's vector instructions.
    #[inline(always)]
    pub fn along_six(&self, directions: &[[f64; DIM]; 6]) -> [Lanes; DIM] {
        let delta: [Lanes; DIM] = std::array::from_fn(|k| Lanes(directions.map(|d| d[k])));
        let moved = self.moved_six(&delta);
        let turned = self.turn_six(&self.hessian_phi_six(&delta));
        std::array::from_fn(|k| moved[k] + turned[k])
    }

    /// ∇²G·δ (the product rule of the module doc) lane by lane, as the sum of its parts linear
    /// in δω and in (δα, δβ).
    #[inline(always)]
    fn hessian_g_six(&self, delta: &[Lanes; DIM]) -> [Lanes; DIM] {
        let [a, b] = self.fields;
        let w3 = self.state.omega[2];
        let (m, big_a, big_b) = (&self.m, &self.big_a, &self.big_b);
        let (p, q, axb) = (self.p, self.q, &self.axb);
        // The part linear in δω.
        let dw3 = delta[2];
        let dm = [2.0 * delta[0], 2.0 * delta[1], dw3];
        let (dp, dq) = (lanes::dot(&dm, big_a), lanes::dot(&dm, big_b));
        let mut dr = lanes::dot(&dm, axb);
        let (bxdm, dmxa) = (lanes::cross(big_b, &dm), lanes::cross(&dm, big_a));
        let mut g_m: [Lanes; 3] =
            std::array::from_fn(|i| dp * big_a[i] + dq * big_b[i] + dw3 * axb[i]);
        let mut g_a: [Lanes; 3] =
            std::array::from_fn(|i| dp * m[i] + p * dm[i] + dw3 * self.bxm[i] + w3 * bxdm[i]);
        let mut g_b: [Lanes; 3] =
            std::array::from_fn(|i| dq * m[i] + q * dm[i] + dw3 * self.mxa[i] + w3 * dmxa[i]);
        // The part linear in (δα, δβ).
        let da = [a * delta[3], a * delta[4], a * delta[5]];
        let db = [b * delta[6], b * delta[7], b * delta[8]];
        let (dp, dq) = (lanes::dot(m, &da), lanes::dot(m, &db));
        let d_axb: [Lanes; 3] = {
            let (u, v) = (lanes::cross(&da, big_b), lanes::cross(big_a, &db));
            [u[0] + v[0], u[1] + v[1], u[2] + v[2]]
        };
        dr = dr + lanes::dot(m, &d_axb);
        let (dbxm, mxda) = (lanes::cross(&db, m), lanes::cross(m, &da));
        for i in 0..3 {
            g_m[i] =
                g_m[i] + (dp * big_a[i] + p * da[i] + dq * big_b[i] + q * db[i] + w3 * d_axb[i]);
            g_a[i] = g_a[i] + (dp * m[i] + w3 * dbxm[i]);
            g_b[i] = g_b[i] + (dq * m[i] + w3 * mxda[i]);
        }
        hessian_g_of([0.5 * a, 0.5 * b], g_m, g_a, g_b, dr)
    }

    /// ∇²Φ·δ lane by lane.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // k indexes ∇L and δ alike
    fn hessian_phi_six(&self, delta: &[Lanes; DIM]) -> [Lanes; DIM] {
        let [a, b] = self.fields;
        let [w1, w2, _] = self.state.omega;
        let (d0, d1) = (delta[0], delta[1]);
        let dx = 2.0 * (w1 * d0 - w2 * d1) + a * delta[3] - b * delta[7];
        let dy = 2.0 * (w2 * d0 + w1 * d1) + a * delta[4] + b * delta[6];
        let mut dl = self.grad_l[0] * delta[0];
        for k in 1..DIM {
            dl = dl + self.grad_l[k] * delta[k];
        }
        let hg = self.hessian_g_six(delta);
        let zero = Lanes::splat(0.0);
        let hx = [2.0 * d0, -2.0 * d1, zero];
        let hy = [2.0 * d1, 2.0 * d0, zero];
        let hh = [2.0 * d0, 2.0 * d1, delta[2]];
        std::array::from_fn(|i| {
            let mut hk = 2.0 * (dx * self.grad_x[i] + dy * self.grad_y[i]);
            let mut hl = 2.0 * hg[i];
            if i < 3 {
                hk = hk + 2.0 * (self.x * hx[i] + self.y * hy[i]);
                hl = hl - self.p2 * hh[i];
            }
            self.r4 * hk - 2.0 * (dl * self.grad_l[i] + self.l * hl)
        })
    }

    /// 𝔅(δ)∇Φ lane by lane: [`hamiltonian_field`](super::distance::hamiltonian_field) with δ
    /// for the state (bilinear).
    #[inline(always)]
    fn moved_six(&self, delta: &[Lanes; DIM]) -> [Lanes; DIM] {
        let g = &self.grad_phi;
        let d_m = [0.5 * g[0], 0.5 * g[1], g[2]];
        let m = [2.0 * delta[0], 2.0 * delta[1], delta[2]];
        let c = lanes::cross(&m, &d_m);
        let da = [delta[3], delta[4], delta[5]];
        let db = [delta[6], delta[7], delta[8]];
        let (u, v) = (
            lanes::cross(&da, &[g[3], g[4], g[5]]),
            lanes::cross(&db, &[g[6], g[7], g[8]]),
        );
        let e = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
        let (ca, cb) = (lanes::cross(&da, &d_m), lanes::cross(&db, &d_m));
        [
            0.5 * c[0] + 0.5 * e[0],
            0.5 * c[1] + 0.5 * e[1],
            c[2] + e[2],
            ca[0],
            ca[1],
            ca[2],
            cb[0],
            cb[1],
            cb[2],
        ]
    }

    /// [`hamiltonian_field`](super::distance::hamiltonian_field) at the state of a gradient
    /// given lane by lane.
    #[inline(always)]
    fn turn_six(&self, grad: &[Lanes; DIM]) -> [Lanes; DIM] {
        let s = &self.state;
        let m = [2.0 * s.omega[0], 2.0 * s.omega[1], s.omega[2]];
        let d_m = [grad[0] * 0.5, grad[1] * 0.5, grad[2]];
        let d_alpha = [grad[3], grad[4], grad[5]];
        let d_beta = [grad[6], grad[7], grad[8]];
        let mut m_dot = lanes::cross(&m, &d_m);
        for (v, dv) in [(&s.alpha, &d_alpha), (&s.beta, &d_beta)] {
            let c = lanes::cross(v, dv);
            for i in 0..3 {
                m_dot[i] = m_dot[i] + c[i];
            }
        }
        let alpha_dot = lanes::cross(&s.alpha, &d_m);
        let beta_dot = lanes::cross(&s.beta, &d_m);
        [
            m_dot[0] * 0.5,
            m_dot[1] * 0.5,
            m_dot[2],
            alpha_dot[0],
            alpha_dot[1],
            alpha_dot[2],
            beta_dot[0],
            beta_dot[1],
            beta_dot[2],
        ]
    }
}

/// The derivative of X_Φ along six directions at a state (column j: along direction j), by the
/// formulas of the module doc.
pub fn phi_field_derivative(
    fields: &Fields<f64>,
    s: &State<f64>,
    directions: &[[f64; DIM]; 6],
) -> [[f64; 6]; DIM] {
    PhiFieldDerivative::new(fields, s)
        .along_six(directions)
        .map(|lane| lane.0)
}
