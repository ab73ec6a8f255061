//! The phase state (ω, α, β) ∈ R⁹ and the orientation it defines.
//!
//! α, β are the unit vectors of the two fields written in the body frame (seed sec. 1), so they
//! are the first two rows of the orientation matrix Q (seed eq. 2.1, nᵢ = Qᵢₖ eₖ), whose third row
//! is γ = α×β. The angular velocity in the fixed frame is Ω = Qω (seed eq. 2.2).

use serde::{Deserialize, Serialize};

use crate::error::DynamicsError;
use crate::scalar::Real;
use crate::vec3::{cross, dot, mat_vec, Mat3, Vec3};

/// Dimension of the phase vector.
pub const DIM: usize = 9;

/// Tolerance on the geometric constraints of a user-given state.
pub const CONSTRAINT_TOLERANCE: f64 = 1e-9;

/// Largest magnitude of a state component read from outside (an option, a file, an adapter's
/// answer): |ωᵢ|, |αᵢ|, |βᵢ| ≤ 1e8. Beyond it the integrals (≈ ω²) pass 1e16 and the root
/// searches of N's geometry lose every digit; the bound is stated in docs/output.md.
pub const MAX_COMPONENT: f64 = 1e8;

/// Angular velocity ω and field directions α, β, all in the body frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State<T> {
    pub omega: Vec3<T>,
    pub alpha: Vec3<T>,
    pub beta: Vec3<T>,
}

impl<T: Real> State<T> {
    /// The state as a phase vector (ω₁, ω₂, ω₃, α₁, α₂, α₃, β₁, β₂, β₃). Written out, without
    /// a closure, so that it inlines into a caller built with other CPU features (FMA).
    #[inline(always)]
    pub fn to_array(&self) -> [T; DIM] {
        let (w, a, b) = (&self.omega, &self.alpha, &self.beta);
        [
            w[0].clone(),
            w[1].clone(),
            w[2].clone(),
            a[0].clone(),
            a[1].clone(),
            a[2].clone(),
            b[0].clone(),
            b[1].clone(),
            b[2].clone(),
        ]
    }

    pub fn from_slice(x: &[T]) -> Self {
        Self {
            omega: std::array::from_fn(|i| x[i].clone()),
            alpha: std::array::from_fn(|i| x[3 + i].clone()),
            beta: std::array::from_fn(|i| x[6 + i].clone()),
        }
    }

    /// γ = α×β (seed eq. 2.5).
    pub fn gamma(&self) -> Vec3<T> {
        cross(&self.alpha, &self.beta)
    }

    /// Orientation matrix Q with rows α, β, γ (seed, sec. 2).
    pub fn orientation(&self) -> Mat3<T> {
        [self.alpha.clone(), self.beta.clone(), self.gamma()]
    }

    /// Angular velocity in the fixed frame, Ω = Qω (seed eq. 2.2).
    pub fn omega_fixed(&self) -> Vec3<T> {
        mat_vec(&self.orientation(), &self.omega)
    }

    /// Residuals of the geometric integrals: (|α|² − 1, |β|² − 1, α·β).
    pub fn constraint_residuals(&self) -> [T; 3] {
        let one = self.alpha[0].one_like();
        [
            dot(&self.alpha, &self.alpha) - &one,
            dot(&self.beta, &self.beta) - &one,
            dot(&self.alpha, &self.beta),
        ]
    }

    /// Largest absolute constraint residual.
    pub fn constraint_error(&self) -> T {
        let [x, y, z] = self.constraint_residuals();
        x.abs().max_of(y.abs()).max_of(z.abs())
    }

    /// The state converted to another scalar type (through f64 when narrowing).
    pub fn map<U, F: Fn(&T) -> U>(&self, f: F) -> State<U> {
        State {
            omega: std::array::from_fn(|i| f(&self.omega[i])),
            alpha: std::array::from_fn(|i| f(&self.alpha[i])),
            beta: std::array::from_fn(|i| f(&self.beta[i])),
        }
    }

    /// Check a user-given state: finite numbers of magnitude at most [`MAX_COMPONENT`],
    /// |α| = |β| = 1 and α·β = 0 within [`CONSTRAINT_TOLERANCE`].
    pub fn validate(&self) -> Result<(), DynamicsError> {
        for (name, v) in [
            ("omega", &self.omega),
            ("alpha", &self.alpha),
            ("beta", &self.beta),
        ] {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(DynamicsError::State(format!(
                    "{name} has a component that is not a finite number"
                )));
            }
            if let Some(i) = v.iter().position(|x| x.to_f64().abs() > MAX_COMPONENT) {
                return Err(DynamicsError::State(format!(
                    "{name}{} = {:e} is outside the range of a state component (|x| <= {MAX_COMPONENT:e})",
                    i + 1,
                    v[i].to_f64()
                )));
            }
        }
        let [na, nb, ab] = self.constraint_residuals();
        let tol = self.alpha[0].lit(CONSTRAINT_TOLERANCE);
        // |v|² − 1 ≈ 2(|v| − 1): compare the norm itself with the tolerance.
        let norm_a = dot(&self.alpha, &self.alpha).sqrt();
        let norm_b = dot(&self.beta, &self.beta).sqrt();
        let one = norm_a.one_like();
        if (norm_a.clone() - &one).abs() > tol {
            return Err(DynamicsError::State(format!(
                "|alpha| must be 1 within {CONSTRAINT_TOLERANCE:e}, got |alpha| = {} (|alpha|^2 - 1 = {:e})",
                norm_a.to_f64(),
                na.to_f64()
            )));
        }
        if (norm_b.clone() - &one).abs() > tol {
            return Err(DynamicsError::State(format!(
                "|beta| must be 1 within {CONSTRAINT_TOLERANCE:e}, got |beta| = {} (|beta|^2 - 1 = {:e})",
                norm_b.to_f64(),
                nb.to_f64()
            )));
        }
        if ab.abs() > tol {
            return Err(DynamicsError::State(format!(
                "alpha and beta must be orthogonal within {CONSTRAINT_TOLERANCE:e}, got alpha.beta = {:e}",
                ab.to_f64()
            )));
        }
        Ok(())
    }
}

impl State<f64> {
    /// Exact widening of an f64 state to any scalar at `bits` bits.
    pub fn to_scalar<U: Real>(&self, bits: u32) -> State<U> {
        self.map(|x| U::from_f64(*x, bits))
    }
}
