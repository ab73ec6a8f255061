//! The regular distance from N, d(x) = |X_Φ(x)| (issue 11), derived from the first integrals.
//!
//! Φ = r⁴K − (2G − p²H)² is a function of the integrals, so it is itself an integral, and it
//! vanishes on N together with its gradient (on N, K = r⁴m² and 2G − p²H = r⁴m, and dK = 2m·dL
//! there: N is where the integrals are dependent). Its Hamiltonian vector field
//!
//! ```text
//!   X_F = (M×∂F/∂M + α×∂F/∂α + β×∂F/∂β,  α×∂F/∂M,  β×∂F/∂M),   M = (2ω₁, 2ω₂, ω₃)
//! ```
//!
//! (the Lie–Poisson bracket of the rigid body in two fields; X_H is the Euler–Poisson field) is
//! therefore zero on N, of the order of the displacement off N, polynomial in the state (so
//! regular where s₁ passes through infinity, unlike F₁, F₂ of [`super::relations`]), and, Φ being
//! an integral, transported by the flow of H like a tangent vector: the growth of d along a
//! motion is the growth of its departure from N. Gradients come from the one definition of the
//! integrals in `rsts_dynamics::integrals`, differentiated with dual numbers.

use rsts_dynamics::integrals::integrals;
use rsts_dynamics::jet::Jet;
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::cross;
use rsts_dynamics::{Fields, Real, State};

use crate::manifold::field_derivative::PhiFieldDerivative;
use crate::manifold::phi_field::phi_gradient;
use crate::manifold::spectral::largest_eigenvalue;

/// A function on the phase space, written once over any scalar (so it can be differentiated).
pub trait PhaseFunction {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S;
    /// ∂F/∂(ω, α, β): by default the jet [`gradient`] of [`PhaseFunction::eval`].
    fn grad<T: Real>(&self, fields: &Fields<T>, s: &State<T>) -> [T; DIM]
    where
        Self: Sized,
    {
        gradient(self, fields, s)
    }
}

/// The energy H.
pub struct Energy;
/// K = |Z|².
pub struct Kowalevski;
/// L = 2G − p²H (= r⁴m on N).
pub struct LevelL;
/// Φ = r⁴K − (2G − p²H)².
pub struct Phi;

impl PhaseFunction for Energy {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S {
        integrals(fields, s).h
    }
}
impl PhaseFunction for Kowalevski {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S {
        integrals(fields, s).k
    }
}
impl PhaseFunction for LevelL {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S {
        let i = integrals(fields, s);
        i.g.lit(2.0) * &i.g - fields.p2() * &i.h
    }
}
impl PhaseFunction for Phi {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S {
        let i = integrals(fields, s);
        let r2 = fields.r2();
        let l = i.g.lit(2.0) * &i.g - fields.p2() * &i.h;
        r2.square() * &i.k - l.square()
    }
    /// The gradient written out ([`phi_gradient`]; a test checks it against the jet gradient).
    fn grad<T: Real>(&self, fields: &Fields<T>, s: &State<T>) -> [T; DIM] {
        phi_gradient(fields, s)
    }
}

/// ∂F/∂(ω, α, β) at a state, by nine forward derivatives in one evaluation over a [`Jet`]
/// (each the dual-number derivative of its direction, bit for bit).
pub fn gradient<T: Real, F: PhaseFunction>(f: &F, fields: &Fields<T>, s: &State<T>) -> [T; DIM] {
    let lift = |x: &T| Jet::constant(x.clone());
    let jet_fields = Fields {
        a: lift(&fields.a),
        b: lift(&fields.b),
    };
    let x = s.to_array();
    let seeded: [Jet<T, DIM>; DIM] = std::array::from_fn(|k| Jet::variable(x[k].clone(), k));
    f.eval(&jet_fields, &State::from_slice(&seeded)).eps
}

/// The Hamiltonian vector field of a function with gradient `grad` (in ω, α, β), written as the
/// time derivative of (ω, α, β).
pub fn hamiltonian_field<T: Real>(s: &State<T>, grad: &[T; DIM]) -> [T; DIM] {
    let two = s.omega[0].lit(2.0);
    let half = s.omega[0].lit(0.5);
    // M = (2ω₁, 2ω₂, ω₃), ∂F/∂M = (∂F/∂ω₁/2, ∂F/∂ω₂/2, ∂F/∂ω₃).
    let m = [
        two.clone() * &s.omega[0],
        two * &s.omega[1],
        s.omega[2].clone(),
    ];
    let d_m = [
        grad[0].clone() * &half,
        grad[1].clone() * &half,
        grad[2].clone(),
    ];
    let d_alpha = [grad[3].clone(), grad[4].clone(), grad[5].clone()];
    let d_beta = [grad[6].clone(), grad[7].clone(), grad[8].clone()];
    let mut m_dot = cross(&m, &d_m);
    for (v, dv) in [(&s.alpha, &d_alpha), (&s.beta, &d_beta)] {
        let c = cross(v, dv);
        for i in 0..3 {
            m_dot[i] += &c[i];
        }
    }
    let alpha_dot = cross(&s.alpha, &d_m);
    let beta_dot = cross(&s.beta, &d_m);
    [
        m_dot[0].clone() * &half,
        m_dot[1].clone() * &half,
        m_dot[2].clone(),
        alpha_dot[0].clone(),
        alpha_dot[1].clone(),
        alpha_dot[2].clone(),
        beta_dot[0].clone(),
        beta_dot[1].clone(),
        beta_dot[2].clone(),
    ]
}

/// X_F at a state.
pub fn field_of<T: Real, F: PhaseFunction>(f: &F, fields: &Fields<T>, s: &State<T>) -> [T; DIM] {
    hamiltonian_field(s, &f.grad(fields, s))
}

/// The distance from N at a state.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceFromN<T> {
    /// d(x) = |X_Φ(x)|, the Euclidean length of the field of Φ in (ω, α, β).
    pub field: T,
    /// The gain g(x): the largest singular value of the derivative of X_Φ along the constraint
    /// surface |α| = |β| = 1, α·β = 0 (an orthonormal basis of its six directions: ω₁, ω₂, ω₃
    /// and the rotations of (α, β) about α, β and γ), computed in f64.
    pub gain: f64,
    /// d(x)/g(x): for a state x = y + δ near a point y of N, |X_Φ(x)| ≈ |DX_Φ(y)·δ| ≤ g|δ|, so
    /// this is at most the displacement |δ| off N (to first order) and equals it for the normal
    /// direction X_Φ stretches most: the distance from N in the units of the state.
    pub distance: T,
    /// distance/|x|, |x|² = |ω|² + |α|² + |β|².
    pub relative: T,
}

/// d(x), the gain and the distance from N in state units.
pub fn distance<T: Real>(fields: &Fields<T>, s: &State<T>) -> DistanceFromN<T> {
    let field = field_norm(fields, s);
    let g = gain(&fields_f64(fields), &s.map(|x| x.to_f64()));
    let distance = if g > 0.0 {
        field.clone() / field.lit(g)
    } else {
        field.clone()
    };
    let size = s
        .to_array()
        .iter()
        .fold(field.zero_like(), |acc, c| acc + c.square())
        .sqrt();
    DistanceFromN {
        relative: distance.clone() / size,
        field,
        gain: g,
        distance,
    }
}

/// |X_Φ(x)|.
pub fn field_norm<T: Real>(fields: &Fields<T>, s: &State<T>) -> T {
    field_of(&Phi, fields, s)
        .iter()
        .fold(s.omega[0].zero_like(), |acc, c| acc + c.square())
        .sqrt()
}

fn fields_f64<T: Real>(fields: &Fields<T>) -> Fields<f64> {
    Fields {
        a: fields.a.to_f64(),
        b: fields.b.to_f64(),
    }
}

/// The gain g(x) of [`DistanceFromN`] (f64: it only scales the distance): the square root of
/// the largest eigenvalue of the 6×6 Gram matrix JᵀJ of the derivative J of X_Φ along the
/// constraint surface ([`largest_eigenvalue`]). The eigenvalue is accurate to a few ulps of |J|² (so the gain to a few
/// ulps of itself, being |J|₂); only the small singular values need the SVD of [`stretches`].
pub fn gain(fields: &Fields<f64>, s: &State<f64>) -> f64 {
    largest_eigenvalue(gram(fields, s)).max(0.0).sqrt()
}

/// The lower triangle of the Gram matrix JᵀJ of `constraint_derivative`: each entry the dot
/// product of two columns, summed in order. The six columns are computed lane by lane
/// ([`PhiFieldDerivative::along_six`], stop 31: the same numbers as one direction at a time,
/// [`constraint_columns`], in two thirds of the instructions).
#[allow(clippy::needless_range_loop)] // the index ranges are the triangle's
pub fn gram(fields: &Fields<f64>, s: &State<f64>) -> [[f64; 6]; 6] {
    let d = PhiFieldDerivative::new(fields, s);
    let j = d.along_six(&constraint_directions(s));
    let mut gram = [[0.0; 6]; 6];
    for p in 0..6 {
        for q in 0..=p {
            let mut sum = 0.0;
            for row in &j {
                sum += row.0[p] * row.0[q];
            }
            gram[p][q] = sum;
        }
    }
    gram
}

/// The derivative J (9×6) of X_Φ along six orthonormal directions of the constraint surface
/// |α| = |β| = 1, α·β = 0: δω = e₁, e₂, e₃, and (δα, δβ) = (θ×α, θ×β) for θ = α, β, γ/√2.
fn constraint_derivative(fields: &Fields<f64>, s: &State<f64>) -> [[f64; 6]; DIM] {
    let columns = constraint_columns(fields, s);
    std::array::from_fn(|k| std::array::from_fn(|j| columns[j][k]))
}

/// The six directions of `constraint_derivative`.
#[inline(always)]
fn constraint_directions(s: &State<f64>) -> [[f64; DIM]; 6] {
    let gamma = s.gamma();
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let rotations = [s.alpha, s.beta, gamma.map(|x| x * s2)];
    std::array::from_fn(|j| {
        let mut d = [0.0; DIM];
        if j < 3 {
            d[j] = 1.0;
        } else {
            let th = &rotations[j - 3];
            let (da, db) = (cross(th, &s.alpha), cross(th, &s.beta));
            d[3..6].copy_from_slice(&da);
            d[6..9].copy_from_slice(&db);
        }
        d
    })
}

/// The columns of `constraint_derivative` ([`PhiFieldDerivative::along_six`], column j
/// from lane j).
pub fn constraint_columns(fields: &Fields<f64>, s: &State<f64>) -> [[f64; DIM]; 6] {
    let j = PhiFieldDerivative::new(fields, s).along_six(&constraint_directions(s));
    std::array::from_fn(|i| std::array::from_fn(|k| j[k].0[i]))
}

/// The singular values (largest first) of the derivative of X_Φ along the six directions of
/// the constraint surface. On N exactly two are non-zero: the normal space of N in the
/// constraint surface is two-dimensional and X_Φ vanishes on N.
pub fn stretches(fields: &Fields<f64>, s: &State<f64>) -> [f64; 6] {
    let j = constraint_derivative(fields, s);
    let matrix = nalgebra::SMatrix::<f64, DIM, 6>::from_fn(|k, q| j[k][q]);
    let sv = matrix.singular_values();
    let mut values: [f64; 6] = std::array::from_fn(|k| sv[k]);
    values.sort_by(|x, y| y.total_cmp(x));
    values
}
