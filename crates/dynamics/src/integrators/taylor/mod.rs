//! Taylor-series integrator of adaptive order and step, generic over the scalar (`f64`,
//! [`DoubleDouble`](crate::scalar::DoubleDouble), `rug::Float`), after Jorba & Zou,
//! *Experimental Mathematics* 14 (2005), and heyoka (Biscani & Izzo, MNRAS 504 (2021)).
//!
//! * **Coefficients**: x₀ = x(tₙ), x_{k+1} = f(x)ₖ/(k+1), with f(x)ₖ from
//!   [`VectorField::taylor_coefficient_orders`] (Cauchy products over the one table of the
//!   equations, series stored order by order): O(p²) per step for order p.
//! * **Order** from the tolerance ε: p = ⌈−ln(ε)/2⌉ + 1 (fixed for the run), with
//!   ε = min(rtol, atol) but not below the unit round-off of the scalar.
//! * **Step**: ρₘ = (X/‖xₘ‖∞)^{1/m} for m = p−1, p, h = min(ρ_{p−1}, ρ_p)·e^{−0.7/(p−1)}/e²,
//!   with X = ‖x₀‖∞ (relative control) when rtol·‖x₀‖∞ > atol, else X = 1 (absolute control).
//!   Steps are never shortened to hit output times.
//! * **Dense output**: the Taylor polynomial of the step, evaluated by Horner at each grid time
//!   inside the step.
//! * **Compensated state**: the state is kept as an unevaluated sum hi + lo per component (and
//!   the time likewise); the step update hi + (lo + Σₖ xₖhᵏ) is done with an error-free
//!   `two_sum`, so the round-off of the state does not grow like plain summation. The lo part
//!   enters the coefficients at first order: x₁ = f(hi) + J(hi)·lo.
//!
//! **Cost counted in [`Stats::rhs_evals`]**: p + 1 per step, one per Taylor coefficient order
//! f(x)₀ … f(x)_{p−1} computed (each costs at most one right-hand side evaluation's worth of
//! products; f(x)ₖ costs k + 1 times that, so this count understates the flops by ~p/2; it is
//! the convention of heyoka-style comparisons) plus one for the Jacobian–vector product of the
//! compensation. No step is ever rejected.
//!
//! **Files**: `mod.rs` (this: the method's settings, order rule, dispatch by scalar),
//! `stepping.rs` (the stepping loop written once: grid, dense samples, step checks, statistics),
//! `generic.rs` (the stepper over any [`Real`]: the path of every scalar without a dedicated
//! kernel), `mp.rs` (the limb-level coefficient kernel of taylor-mp, which the generic stepper
//! calls for MPFR scalars), `fast.rs` (the stepper of taylor-f64 and taylor-dd on the lane
//! kernel), `lanes.rs` (those two methods on it: code path, extended orders, the
//! state in f64 parts, the solution), `layout.rs`, `series.rs`, `expansion.rs` (the lane layout generated
//! from the table, the lane Cauchy sums, f64 expansion arithmetic) and `simd/` (the code paths
//! picked at run time: AVX-512, AVX2+FMA, portable; `RSTS_SIMD`).

mod expansion;
mod fast;
mod generic;
mod lanes;
mod layout;
mod mp;
mod series;
pub mod simd;
mod stepping;
#[cfg(test)]
mod tests;

pub use lanes::LANE_EXTRA_BITS;
pub use mp::{MpfrKernel, MpfrKernelChoice, MAX_DEFAULT_LIMBS as MPFR_MAX_DEFAULT_LIMBS};
pub use simd::{SimdPath, SIMD_ENV};

use crate::equations::VectorField;
use crate::error::DynamicsError;
use crate::scalar::Real;

use super::dense::StepSamples;
use super::{OutputGrid, Problem, Propagator, Solution, Tolerances};

/// Largest Taylor order accepted (a tolerance of about 1e-170).
pub const MAX_ORDER: usize = 400;

/// Maximum number of steps of one run.
pub(crate) const MAX_STEPS: u64 = 100_000_000;

/// The Taylor method; the scalar (and so the precision) is that of the [`Problem`].
#[derive(Clone, Copy, Debug)]
pub struct Taylor {
    pub tolerances: Tolerances,
    /// Keep the state and the time as compensated sums hi + lo (default). `false`: plain
    /// summation x ← x + Σₖ xₖhᵏ, for comparison (see the tests and docs/taylor.md).
    pub compensated: bool,
    /// The coefficient kernel in MPFR (`taylor-mp`); `None`: from the environment variable
    /// [`MpfrKernelChoice::ENV`], default the limb-level kernel.
    pub mpfr_kernel: Option<MpfrKernelChoice>,
    /// The code path of the lane kernels (taylor-f64, taylor-dd); `None`: the one `RSTS_SIMD`
    /// names, else the best this CPU has ([`SimdPath`]).
    pub simd: Option<SimdPath>,
    /// A fixed order p and step h instead of the Jorba–Zou rule (convergence studies: the
    /// global error is then O(hᵖ)); the tolerances are not used. Runs on the generic stepper.
    pub fixed: Option<FixedOrderStep>,
}

/// Order and step of a [`Taylor`] run without step-size control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedOrderStep {
    /// Degree p of the Taylor polynomial of each step (1 to [`MAX_ORDER`]).
    pub order: usize,
    /// The step h > 0, the same for every step.
    pub step: f64,
}

impl Taylor {
    pub const NAME_F64: &'static str = "taylor-f64";
    pub const NAME_DD: &'static str = "taylor-dd";
    pub const NAME_MP: &'static str = "taylor-mp";

    pub fn new(tolerances: Tolerances) -> Self {
        Self {
            tolerances,
            compensated: true,
            mpfr_kernel: None,
            simd: None,
            fixed: None,
        }
    }

    /// The method at a fixed order p and step h (checked: 1 ≤ p ≤ [`MAX_ORDER`], h > 0
    /// finite); see [`Taylor::fixed`].
    pub fn fixed(order: usize, step: f64) -> Result<Self, DynamicsError> {
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(DynamicsError::Settings(format!(
                "order must be between 1 and {MAX_ORDER}, got {order}"
            )));
        }
        if !(step.is_finite() && step > 0.0) {
            return Err(DynamicsError::Settings(format!(
                "step must be a positive finite number, got {}",
                crate::short(step)
            )));
        }
        let tolerances = Tolerances::new(1e-10, 1e-10)?;
        Ok(Self {
            fixed: Some(FixedOrderStep { order, step }),
            ..Self::new(tolerances)
        })
    }

    /// The same method with the given MPFR coefficient kernel (ignored by other scalars).
    pub fn with_mpfr_kernel(self, kernel: MpfrKernelChoice) -> Self {
        Self {
            mpfr_kernel: Some(kernel),
            ..self
        }
    }

    /// The same method on a given code path (tests force each one).
    pub fn with_simd(self, path: SimdPath) -> Self {
        Self {
            simd: Some(path),
            ..self
        }
    }

    /// The same method with plain (uncompensated) summation of the state and the time.
    pub fn uncompensated(self) -> Self {
        Self {
            compensated: false,
            ..self
        }
    }

    /// The name of the method in scalar `T`.
    pub fn name_for<T: Real>() -> &'static str {
        match T::NAME {
            "f64" => Self::NAME_F64,
            "dd" => Self::NAME_DD,
            "mpfr" => Self::NAME_MP,
            _ => "taylor",
        }
    }

    /// Jorba–Zou order for tolerance ε: ⌈−ln(ε)/2⌉ + 1 (at least 2).
    pub fn order_for(tolerance: f64) -> usize {
        (((-tolerance.ln()) / 2.0).ceil().max(1.0) as usize) + 1
    }

    /// The tolerance that sets the order in a scalar of `bits` bits: min(rtol, atol), but not
    /// below the unit round-off 2^-bits. Errors: non-positive or non-finite tolerances, an rtol
    /// below the unit round-off (the scalar cannot deliver it), an order above [`MAX_ORDER`].
    pub fn effective_tolerance(&self, bits: u32) -> Result<f64, DynamicsError> {
        let Tolerances { rtol, atol } = self.tolerances;
        Tolerances::new(rtol, atol)?;
        let unit = 2f64.powi(-(bits.min(1000) as i32));
        if rtol < unit {
            return Err(DynamicsError::Settings(format!(
                "rtol = {rtol:e} is below {unit:.2e} = 2^-{bits}, the unit round-off this method \
                 can deliver; use a wider scalar (taylor-dd, taylor-mp with more digits)"
            )));
        }
        let eps = rtol.min(atol).max(unit);
        let order = Self::order_for(eps);
        if order > MAX_ORDER {
            return Err(DynamicsError::Settings(format!(
                "tolerance {eps:e} needs Taylor order {order} > {MAX_ORDER}"
            )));
        }
        Ok(eps)
    }
}

impl<T: Real> Propagator<T> for Taylor {
    fn name(&self) -> &'static str {
        Self::name_for::<T>()
    }

    fn propagate_grid(
        &self,
        problem: &Problem<T>,
        grid: &OutputGrid,
    ) -> Result<Solution<T>, DynamicsError> {
        self.propagate_field(VectorField::new(&problem.fields), problem, grid)
    }
}

impl Taylor {
    /// [`Propagator::propagate_grid`] with a given vector field instead of the one built from
    /// `problem.fields` (tests use it to feed a broken table of equations).
    pub fn propagate_field<T: Real>(
        &self,
        field: VectorField<T>,
        problem: &Problem<T>,
        grid: &OutputGrid,
    ) -> Result<Solution<T>, DynamicsError> {
        if let Some(sol) = self.propagate_lanes(&field, problem, grid)? {
            return Ok(sol);
        }
        generic::propagate(self, field, problem, grid)
    }
}

impl Taylor {
    /// The run of [`Propagator::propagate_grid`] on `grid` as its own steps — the same steps,
    /// the last one cut at T where the plain run takes its last sample — with `k` samples
    /// inside each from the step's Taylor polynomial (Horner at τ = j·h/(k + 1)): the method's
    /// dense output, of its full order ([`super::dense`]). The lane kernel (taylor-f64,
    /// taylor-dd) and the generic stepper (taylor-mp, a fixed order) both sample in their own
    /// loop, so a dense run takes exactly the plain run's steps.
    pub fn propagate_steps<T: Real>(
        &self,
        problem: &Problem<T>,
        grid: &OutputGrid,
        k: usize,
    ) -> Result<StepSamples, DynamicsError> {
        let y0 = problem.initial.to_array().map(|x| x.to_f64());
        let (mut out, scale) = super::dense::begin(k, y0, grid)?;
        if scale.is_none() {
            return Ok(out);
        }
        let field = VectorField::new(&problem.fields);
        let steps = match self.lane_run(&field, problem, grid, Some(k))? {
            Some(run) => run.steps(),
            None => generic::propagate_steps(self, field, problem, grid, k)?,
        };
        out.append(steps);
        out.check_size(Self::name_for::<T>())?;
        Ok(out)
    }
}
