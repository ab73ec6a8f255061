//! The Euler–Poisson equations of the Kowalevski top in two constant fields, written **once**, as
//! data: each component of the right-hand side is a sum of quadratic terms `c·xᵢ·xⱼ` and linear
//! terms `c·xᵢ`, with coefficients that are numbers times 1, `a` or `b`.
//!
//! Everything else is derived from this one table: the right-hand side in any scalar
//! ([`VectorField::eval`]), the Taylor coefficients of a solution (Cauchy products,
//! [`VectorField::taylor_coefficient`]), the Jacobian ([`VectorField::jacobian`]).
//!
//! With inertia I = diag(2, 2, 1), M = Iω, the equations (seed sec. 1; Kharlamov, RCD 10 (2005))
//!
//! ```text
//!   dM/dt = M×ω + a e₁×α + b e₂×β,   dα/dt = α×ω,   dβ/dt = β×ω,
//! ```
//!
//! written out component by component (M×ω = (ω₂ω₃, −ω₁ω₃, 0)):
//!
//! ```text
//!   ω̇₁ =  ½ ω₂ω₃ + ½ b β₃        α̇₁ = α₂ω₃ − α₃ω₂      β̇₁ = β₂ω₃ − β₃ω₂
//!   ω̇₂ = −½ ω₁ω₃ − ½ a α₃        α̇₂ = α₃ω₁ − α₁ω₃      β̇₂ = β₃ω₁ − β₁ω₃
//!   ω̇₃ =  a α₂ − b β₁            α̇₃ = α₁ω₂ − α₂ω₁      β̇₃ = β₁ω₂ − β₂ω₁
//! ```

use crate::fields::Fields;
use crate::scalar::Real;
use crate::state::DIM;

/// Which parameter multiplies a coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    One,
    A,
    B,
}

/// Index of each coordinate in the state vector (ω, α, β).
pub mod idx {
    pub const W1: usize = 0;
    pub const W2: usize = 1;
    pub const W3: usize = 2;
    pub const A1: usize = 3;
    pub const A2: usize = 4;
    pub const A3: usize = 5;
    pub const B1: usize = 6;
    pub const B2: usize = 7;
    pub const B3: usize = 8;
}
use idx::*;

/// `c · param · x[i] · x[j]`.
#[derive(Clone, Copy, Debug)]
pub struct Quadratic {
    pub c: f64,
    pub param: Param,
    pub i: usize,
    pub j: usize,
}
/// `c · param · x[i]`.
#[derive(Clone, Copy, Debug)]
pub struct Linear {
    pub c: f64,
    pub param: Param,
    pub i: usize,
}

/// One component of the right-hand side.
#[derive(Clone, Copy, Debug)]
pub struct Component {
    pub quadratic: &'static [Quadratic],
    pub linear: &'static [Linear],
}

const fn q(c: f64, i: usize, j: usize) -> Quadratic {
    Quadratic {
        c,
        param: Param::One,
        i,
        j,
    }
}
const fn l(c: f64, param: Param, i: usize) -> Linear {
    Linear { c, param, i }
}

/// Poisson equation dv/dt = v×ω for the unit vector whose components start at `v`.
const fn poisson(v: usize, k: usize) -> [Quadratic; 2] {
    // (v×ω)_k = v_{k+1} ω_{k+2} − v_{k+2} ω_{k+1}  (indices mod 3)
    let k1 = (k + 1) % 3;
    let k2 = (k + 2) % 3;
    [q(1.0, v + k1, W1 + k2), q(-1.0, v + k2, W1 + k1)]
}

const ALPHA_DOT: [[Quadratic; 2]; 3] = [poisson(A1, 0), poisson(A1, 1), poisson(A1, 2)];
const BETA_DOT: [[Quadratic; 2]; 3] = [poisson(B1, 0), poisson(B1, 1), poisson(B1, 2)];

/// The right-hand side of the Euler–Poisson equations: the single definition of the dynamics.
pub const EULER_POISSON: [Component; DIM] = [
    Component {
        quadratic: &[q(0.5, W2, W3)],
        linear: &[l(0.5, Param::B, B3)],
    },
    Component {
        quadratic: &[q(-0.5, W1, W3)],
        linear: &[l(-0.5, Param::A, A3)],
    },
    Component {
        quadratic: &[],
        linear: &[l(1.0, Param::A, A2), l(-1.0, Param::B, B1)],
    },
    Component {
        quadratic: &ALPHA_DOT[0],
        linear: &[],
    },
    Component {
        quadratic: &ALPHA_DOT[1],
        linear: &[],
    },
    Component {
        quadratic: &ALPHA_DOT[2],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[0],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[1],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[2],
        linear: &[],
    },
];

/// A term with its coefficient evaluated in the scalar type.
#[derive(Clone, Debug)]
struct Term<T> {
    c: T,
    i: usize,
    j: Option<usize>,
}

/// The Euler–Poisson vector field for given field strengths, ready to evaluate in scalar `T`.
#[derive(Clone, Debug)]
pub struct VectorField<T> {
    terms: Vec<Vec<Term<T>>>,
}

fn coefficient<T: Real>(fields: &Fields<T>, c: f64, param: Param) -> T {
    let c = fields.a.lit(c);
    match param {
        Param::One => c,
        Param::A => c * &fields.a,
        Param::B => c * &fields.b,
    }
}

impl<T: Real> VectorField<T> {
    /// Build the field from the table [`EULER_POISSON`].
    pub fn new(fields: &Fields<T>) -> Self {
        Self::from_table(fields, &EULER_POISSON)
    }

    /// Build a field from any table of the same shape (tests use it to break the equations).
    pub fn from_table(fields: &Fields<T>, table: &[Component; DIM]) -> Self {
        let terms = table
            .iter()
            .map(|comp| {
                let quad = comp.quadratic.iter().map(|t| Term {
                    c: coefficient(fields, t.c, t.param),
                    i: t.i,
                    j: Some(t.j),
                });
                let lin = comp.linear.iter().map(|t| Term {
                    c: coefficient(fields, t.c, t.param),
                    i: t.i,
                    j: None,
                });
                quad.chain(lin).collect()
            })
            .collect();
        Self { terms }
    }

    /// dx/dt = f(x).
    pub fn eval(&self, x: &[T; DIM]) -> [T; DIM] {
        std::array::from_fn(|k| self.eval_component(k, x))
    }

    /// dx/dt = f(x), into an existing buffer (no allocation for Copy scalars).
    pub fn eval_into(&self, x: &[T], out: &mut [T]) {
        for (k, o) in out.iter_mut().enumerate().take(DIM) {
            let mut acc = x[0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => acc += t.c.clone() * &x[t.i] * &x[j],
                    None => acc += t.c.clone() * &x[t.i],
                }
            }
            *o = acc;
        }
    }

    fn eval_component(&self, k: usize, x: &[T; DIM]) -> T {
        let mut acc = x[0].zero_like();
        for t in &self.terms[k] {
            match t.j {
                Some(j) => acc += t.c.clone() * &x[t.i] * &x[j],
                None => acc += t.c.clone() * &x[t.i],
            }
        }
        acc
    }

    /// Coefficient `n` of the Taylor series of f(x(t)), given the coefficients `0..=n` of x(t)
    /// (`series[i][k]` is the k-th coefficient of xᵢ). Quadratic terms are Cauchy products:
    /// (xᵢxⱼ)ₙ = Σₖ xᵢ,ₖ xⱼ,ₙ₋ₖ. The Taylor recursion is then x_{n+1} = f(x)ₙ / (n+1).
    pub fn taylor_coefficient(&self, series: &[Vec<T>], n: usize) -> [T; DIM] {
        std::array::from_fn(|k| {
            let mut acc = series[0][0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => {
                        let (xi, xj) = (&series[t.i], &series[j]);
                        let mut cauchy = acc.zero_like();
                        for m in 0..=n {
                            cauchy += xi[m].clone() * &xj[n - m];
                        }
                        acc += t.c.clone() * cauchy;
                    }
                    None => acc += t.c.clone() * &series[t.i][n],
                }
            }
            acc
        })
    }

    /// Buffered form of [`taylor_coefficient`](Self::taylor_coefficient) for the Taylor
    /// integrators: writes coefficient `n` of f(x(t)) into `out[..DIM]`, reusing the values in
    /// `out` and `scratch` (no allocation for MPFR numbers; products are fused where the scalar
    /// can: [`Real::mul_add_assign`]). `series[i]` needs the coefficients `0..=n` of xᵢ. Cost:
    /// one Cauchy product of length n + 1 per quadratic term of the table.
    pub fn taylor_coefficient_into(
        &self,
        series: &[Vec<T>],
        n: usize,
        out: &mut [T],
        scratch: &mut T,
    ) {
        for (k, o) in out.iter_mut().enumerate().take(DIM) {
            let mut first = true;
            for t in &self.terms[k] {
                let term_value: &T = match t.j {
                    Some(j) => {
                        let (xi, xj) = (&series[t.i], &series[j]);
                        // (xᵢxⱼ)ₙ = Σₘ xᵢ,ₘ xⱼ,ₙ₋ₘ
                        // Two interleaved partial sums (even and odd m): two independent
                        // dependency chains, about twice the throughput in f64.
                        let (xi, xj) = (&xi[..=n], &xj[..=n]);
                        scratch.clone_from(&xi[0]);
                        *scratch *= &xj[n];
                        if n >= 1 {
                            let mut odd = xi[1].clone();
                            odd *= &xj[n - 1];
                            let mut m = 2;
                            while m < n {
                                scratch.mul_add_assign(&xi[m], &xj[n - m]);
                                odd.mul_add_assign(&xi[m + 1], &xj[n - m - 1]);
                                m += 2;
                            }
                            if m == n {
                                scratch.mul_add_assign(&xi[n], &xj[0]);
                            }
                            *scratch += &odd;
                        }
                        scratch
                    }
                    None => &series[t.i][n],
                };
                if first {
                    o.clone_from(&t.c);
                    *o *= term_value;
                    first = false;
                } else {
                    o.mul_add_assign(&t.c, term_value);
                }
            }
            if first {
                // A component with no terms (never in the Euler–Poisson table).
                *o = series[0][0].zero_like();
            }
        }
    }

    /// The Jacobian–vector product J(x)·v, from the table (one pass over the terms: the cost of
    /// about one right-hand-side evaluation).
    pub fn jacobian_vector_product(&self, x: &[T], v: &[T]) -> [T; DIM] {
        std::array::from_fn(|k| {
            let mut acc = x[0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    // ∂(c xᵢ xⱼ)·v = c (vᵢ xⱼ + xᵢ vⱼ)
                    Some(j) => {
                        acc += t.c.clone() * (v[t.i].clone() * &x[j] + x[t.i].clone() * &v[j])
                    }
                    None => acc += t.c.clone() * &v[t.i],
                }
            }
            acc
        })
    }

    /// The Jacobian ∂fₖ/∂xᵢ at x.
    pub fn jacobian(&self, x: &[T; DIM]) -> [[T; DIM]; DIM] {
        let zero = x[0].zero_like();
        let mut jac: [[T; DIM]; DIM] =
            std::array::from_fn(|_| std::array::from_fn(|_| zero.clone()));
        for (k, row) in jac.iter_mut().enumerate() {
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => {
                        row[t.i] += t.c.clone() * &x[j];
                        row[j] += t.c.clone() * &x[t.i];
                    }
                    None => row[t.i] += t.c.clone(),
                }
            }
        }
        jac
    }
}
