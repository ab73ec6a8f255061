//! The nearest point of N to a state near a known motion, cheaply enough for every sample of a
//! run (issue 11: the error of an integrated motion split into drift along N and departure from
//! it).
//!
//! Near the torus (m, h) of the exact motion, N is parametrised by (ψ₁, ψ₂, m + δm, h + δh) and,
//! to first order in (δm, δh),
//!
//! ```text
//!   C(ψ, m + δm, h + δh) ≈ C(ψ) + ∂C/∂m(ψ)·δm + ∂C/∂h(ψ)·δh
//! ```
//!
//! with the derivatives from the closed form built once over dual numbers. Gauss–Newton over
//! (ψ₁, ψ₂, δm, δh) from a guess of the angles (the exact ones) gives the nearest point: its
//! angles (the phases of the state on its own torus), its (δm, δh) (the drift of the on-N
//! integrals) and the departure |state − nearest point| from N, in the units of the state. The
//! first-order model is exact to O(δm², δh²): an integrator's drift of the integrals (≤ 1e-6 in
//! practice) makes it negligible.

use rsts_dynamics::dual::Dual;
use rsts_dynamics::state::DIM;
use rsts_dynamics::Real;

use crate::error::ClosedFormError;
use crate::manifold::torus_map::{gauss_newton_step, max_gap, seeded, wrap, TorusMap};
use crate::motion::ExplicitMotion;

/// The torus of a motion with the derivatives of its points in m and h.
#[derive(Clone, Debug)]
pub struct Projector<T> {
    map: TorusMap<T>,
    in_m: TorusMap<Dual<T>>,
    in_h: TorusMap<Dual<T>>,
}

/// The nearest point of N to a state.
#[derive(Clone, Debug)]
pub struct Projection<T> {
    /// Its angles (ψ₁, ψ₂) ∈ [0, 2π)².
    pub phases: [T; 2],
    /// Its (m, h) minus the motion's.
    pub dm: T,
    pub dh: T,
    /// The point (ω, α, β).
    pub point: [T; DIM],
    /// max over the components of |state − point|: the departure from N.
    pub departure: T,
}

impl<T: Real> Projector<T> {
    /// The projector for the torus of `motion`.
    pub fn new(motion: &ExplicitMotion<T>) -> Result<Self, ClosedFormError> {
        let c = &motion.constants;
        let at = [&c.a, &c.b, &c.m, &c.h];
        let torus = motion.choice.torus;
        Ok(Self {
            map: TorusMap::of_motion(motion),
            in_m: seeded(at, torus, true)?,
            in_h: seeded(at, torus, false)?,
        })
    }

    /// The nearest point of N to `target`, from the angles `guess`. `None` when the Gauss–Newton
    /// system is singular (a state far from the torus).
    pub fn project(&self, target: &[T; DIM], guess: &[T; 2]) -> Option<Projection<T>> {
        let zero = target[0].zero_like();
        let quiet = target[0].epsilon().sqrt() * target[0].lit(1e-2);
        let mut psi = guess.clone();
        let (mut dm, mut dh) = (zero.clone(), zero);
        let mut point = self.model(&psi, &dm, &dh).0;
        for _ in 0..8 {
            let (value, jac, jm, jh) = self.model(&psi, &dm, &dh);
            point = value;
            let r: [T; DIM] = std::array::from_fn(|k| point[k].clone() - &target[k]);
            let [d1, d2, ddm, ddh] = gauss_newton_step([&jac[0], &jac[1], &jm, &jh], &r)?;
            let step = d1.abs().max_of(d2.abs());
            psi = [psi[0].clone() + d1, psi[1].clone() + d2];
            dm += ddm;
            dh += ddh;
            // Quadratic convergence: after a step of √ε the angles are good to ε.
            if step <= quiet {
                point = self.model(&psi, &dm, &dh).0;
                break;
            }
        }
        let two_pi = T::pi(target[0].prec()) * target[0].lit(2.0);
        Some(Projection {
            phases: psi.map(|p| wrap(p, &two_pi)),
            departure: max_gap(&point, target),
            point,
            dm,
            dh,
        })
    }

    /// The first-order point C(ψ) + ∂C/∂m·δm + ∂C/∂h·δh, its ψ-derivatives and ∂C/∂m, ∂C/∂h.
    #[allow(clippy::type_complexity)]
    fn model(&self, psi: &[T; 2], dm: &T, dh: &T) -> ([T; DIM], [[T; DIM]; 2], [T; DIM], [T; DIM]) {
        let (x, jac) = self.map.state_and_jacobian(psi);
        let dual_psi = psi.clone().map(Dual::constant);
        let jm = self.in_m.state_at(&dual_psi).map(|d| d.eps);
        let jh = self.in_h.state_at(&dual_psi).map(|d| d.eps);
        let value = std::array::from_fn(|k| x[k].clone() + jm[k].clone() * dm + jh[k].clone() * dh);
        (value, jac, jm, jh)
    }
}
