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

use std::time::Instant;

use crate::equations::{CauchyScratch, VectorField};
use crate::error::DynamicsError;
use crate::scalar::Real;
use crate::state::{State, DIM};

use super::{OutputGrid, Problem, Propagator, Solution, Stats, Tolerances};

/// Largest Taylor order accepted (a tolerance of about 1e-170).
pub const MAX_ORDER: usize = 400;

/// Maximum number of steps of one run.
pub(super) const MAX_STEPS: u64 = 100_000_000;

/// The Taylor method; the scalar (and so the precision) is that of the [`Problem`].
#[derive(Clone, Copy, Debug)]
pub struct Taylor {
    pub tolerances: Tolerances,
    /// Keep the state and the time as compensated sums hi + lo (default). `false`: plain
    /// summation x ← x + Σₖ xₖhᵏ, for comparison (see the tests and docs/taylor.md).
    pub compensated: bool,
}

/// Error-free (in f64 and MPFR) sum: s + e = a + b, s = fl(a + b).
fn two_sum<T: Real>(a: &T, b: &T) -> (T, T) {
    let s = a.clone() + b;
    let bb = s.clone() - a;
    let e = (a.clone() - (s.clone() - &bb)) + (b.clone() - &bb);
    (s, e)
}

/// A number kept as an unevaluated sum `hi + lo` (lo stays 0 without compensation).
#[derive(Clone, Debug)]
struct Compensated<T> {
    hi: T,
    lo: T,
    on: bool,
}

impl<T: Real> Compensated<T> {
    fn new(x: T, on: bool) -> Self {
        let lo = x.zero_like();
        Self { hi: x, lo, on }
    }
    /// self += d (d small compared with self).
    fn add(&mut self, d: &T) {
        if !self.on {
            self.hi += d;
            return;
        }
        let (s, e) = two_sum(&self.hi, &(self.lo.clone() + d));
        self.hi = s;
        self.lo = e;
    }
    fn value(&self) -> T {
        self.hi.clone() + &self.lo
    }
}

impl Taylor {
    pub const NAME_F64: &'static str = "taylor-f64";
    pub const NAME_DD: &'static str = "taylor-dd";
    pub const NAME_MP: &'static str = "taylor-mp";

    pub fn new(tolerances: Tolerances) -> Self {
        Self {
            tolerances,
            compensated: true,
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
                "rtol = {rtol:e} is below the unit round-off {unit:.2e} of a {bits}-bit scalar; \
                 use a wider scalar (taylor-dd: 106 bits, taylor-mp with more digits)"
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

/// Everything one run needs, allocated once.
struct Workspace<T> {
    field: VectorField<T>,
    order: usize,
    /// `series[k][i]`: coefficient k of component i in the current step (order by order, so
    /// the Cauchy products and Horner's rule run over contiguous `[T; DIM]` rows).
    series: Vec<[T; DIM]>,
    /// 1, 2, …, order as scalars.
    ints: Vec<T>,
    out: [T; DIM],
    scratch: CauchyScratch<T>,
}

impl<T: Real> Workspace<T> {
    fn new(field: VectorField<T>, order: usize, like: &T) -> Self {
        let zero = like.zero_like();
        let row: [T; DIM] = std::array::from_fn(|_| zero.clone());
        Self {
            field,
            order,
            series: vec![row.clone(); order + 1],
            ints: (1..=order).map(|k| like.lit(k as f64)).collect(),
            out: row,
            scratch: CauchyScratch::new(like),
        }
    }

    /// Taylor coefficients 0..=order at the state hi + lo.
    fn coefficients(&mut self, state: &[Compensated<T>]) {
        for (s, x) in self.series[0].iter_mut().zip(state) {
            s.clone_from(&x.hi);
        }
        for n in 0..self.order {
            self.field.taylor_coefficient_orders(
                &self.series[..=n],
                n,
                &mut self.out,
                &mut self.scratch,
            );
            if n == 0 {
                // First-order effect of the low parts: f(hi + lo) ≈ f(hi) + J(hi)·lo.
                let lo: [T; DIM] = std::array::from_fn(|i| state[i].lo.clone());
                let jl = self.field.jacobian_vector_product(&self.series[0], &lo);
                for (o, d) in self.out.iter_mut().zip(jl.iter()) {
                    *o += d;
                }
            }
            // A local copy of the divisor: the row and the divisor then provably do not alias,
            // and in f64 the nine divisions vectorise.
            let div = self.ints[n].clone();
            let row = &mut self.series[n + 1];
            for (s, o) in row.iter_mut().zip(&self.out) {
                s.clone_from(o);
                *s /= &div;
            }
        }
    }

    /// ln ‖x_m‖∞ as f64 (−∞ when the coefficients vanish).
    fn ln_norm(&self, m: usize) -> f64 {
        let row = &self.series[m];
        let mut norm = row[0].abs();
        for s in &row[1..] {
            norm = norm.max_of(s.abs());
        }
        if norm.to_f64() == 0.0 && norm <= norm.zero_like() {
            f64::NEG_INFINITY
        } else {
            norm.ln().to_f64()
        }
    }

    /// Σ_{k≥1} x_k τ^k for every component (Horner), into `acc`.
    fn increment(&self, tau: &T, acc: &mut [T; DIM]) {
        acc.clone_from(&self.series[self.order]);
        for row in self.series[1..self.order].iter().rev() {
            for (a, s) in acc.iter_mut().zip(row) {
                *a *= tau;
                *a += s;
            }
        }
        for a in acc.iter_mut() {
            *a *= tau;
        }
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
        let name = Self::name_for::<T>();
        let grid = OutputGrid::new(grid.t_end, grid.samples)?;
        let like = problem.initial.omega[0].clone();
        let bits = like.prec();
        let eps = self.effective_tolerance(bits)?;
        let order = Self::order_for(eps);
        let x0 = problem.initial.to_array();
        if x0.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::State(
                "initial state has a component that is not a finite number".into(),
            ));
        }
        let mut work = Workspace::new(field, order, &like);
        let Tolerances { rtol, atol } = self.tolerances;
        let safety = (-0.7 / (order as f64 - 1.0)).exp() / std::f64::consts::E.powi(2);

        let start = Instant::now();
        let mut state: Vec<Compensated<T>> = x0
            .into_iter()
            .map(|x| Compensated::new(x, self.compensated))
            .collect();
        let mut t = Compensated::new(like.zero_like(), self.compensated);
        let mut stats = Stats::default();
        let mut times = Vec::with_capacity(grid.samples);
        let mut states = Vec::with_capacity(grid.samples);
        let mut next = 0;
        let mut inc: [T; DIM] = std::array::from_fn(|_| like.zero_like());
        while next < grid.samples {
            if stats.accepted_steps >= MAX_STEPS {
                return Err(DynamicsError::Integration(format!(
                    "{name}: more than {MAX_STEPS} steps before t = {}",
                    grid.time(next)
                )));
            }
            work.coefficients(&state);
            stats.accepted_steps += 1;
            stats.rhs_evals += order as u64 + 1;

            // Jorba–Zou step.
            let ln_x = {
                let mut norm = state[0].hi.abs();
                for x in &state[1..] {
                    norm = norm.max_of(x.hi.abs());
                }
                let n = norm.to_f64();
                if rtol * n > atol {
                    n.ln()
                } else {
                    0.0
                }
            };
            let rho = [order - 1, order]
                .into_iter()
                .map(|m| ((ln_x - work.ln_norm(m)) / m as f64).exp())
                .fold(f64::INFINITY, f64::min);
            let t_now = t.value().to_f64();
            let mut h = rho * safety;
            if !h.is_finite() {
                // All coefficients vanish (an equilibrium): one step to the end.
                h = (grid.t_end - t_now).max(f64::MIN_POSITIVE);
            }
            if h.is_nan() || h <= 1e-15 * t_now.abs() || h <= 0.0 {
                return Err(DynamicsError::Integration(format!(
                    "{name}: step size {h:e} too small at t = {t_now} (singular solution?)"
                )));
            }

            // Dense output at the grid times inside [t, t + h].
            let t_step_end = t_now + h;
            while next < grid.samples && grid.time(next) <= t_step_end {
                let tg = grid.time(next);
                let tau = (like.lit(tg) - &t.hi) - &t.lo;
                work.increment(&tau, &mut inc);
                let x: Vec<T> = state
                    .iter()
                    .zip(&inc)
                    .map(|(s, d)| s.hi.clone() + (s.lo.clone() + d))
                    .collect();
                if x.iter().any(|v| !v.is_finite()) {
                    return Err(DynamicsError::Integration(format!(
                        "{name}: solution not finite at t = {tg}"
                    )));
                }
                times.push(tg);
                states.push(State::from_slice(&x));
                next += 1;
            }
            if next == grid.samples {
                break;
            }

            // Compensated update of the state and the time.
            let h_t = like.lit(h);
            work.increment(&h_t, &mut inc);
            for (s, d) in state.iter_mut().zip(&inc) {
                s.add(d);
            }
            t.add(&h_t);
        }
        stats.integration_seconds = start.elapsed().as_secs_f64();
        Ok(Solution {
            method: name,
            times,
            states,
            stats,
        })
    }
}
