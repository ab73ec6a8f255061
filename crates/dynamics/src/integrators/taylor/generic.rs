//! The generic Taylor stepper: one code over any scalar [`Real`] (f64, double-double, MPFR),
//! coefficients from [`VectorField::taylor_coefficient_orders`], state and time kept as
//! compensated sums hi + lo (see the module [`super`] for the method).

use std::any::Any;
use std::time::Instant;

use rug::Float;

use crate::equations::{CauchyScratch, VectorField};
use crate::error::DynamicsError;
use crate::integrators::dense::{polynomial_step, StepSamples};
use crate::integrators::{OutputGrid, Problem, Solution, Stats, Tolerances};
use crate::scalar::Real;
use crate::state::{State, DIM};

use super::mp::{MpfrKernel, MpfrKernelChoice};
use super::{Taylor, MAX_STEPS};

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

/// Everything one run needs, allocated once.
struct Workspace<T> {
    field: VectorField<T>,
    order: usize,
    /// `series[k][i]`: coefficient k of component i in the current step (order by order, so
    /// the Cauchy products and Horner's rule run over contiguous `[T; DIM]` rows).
    series: Vec<[T; DIM]>,
    out: [T; DIM],
    scratch: CauchyScratch<T>,
    /// The limb-level kernel when `T` is MPFR (`mp.rs`).
    mpfr: Option<MpfrKernel>,
}

impl<T: Real> Workspace<T> {
    fn new(field: VectorField<T>, order: usize, like: &T, kernel: MpfrKernelChoice) -> Self {
        let zero = like.zero_like();
        let row: [T; DIM] = std::array::from_fn(|_| zero.clone());
        let mpfr = match kernel {
            MpfrKernelChoice::Limbs => (&field as &dyn Any)
                .downcast_ref::<VectorField<Float>>()
                .and_then(|f| MpfrKernel::by_default(f, like.prec())),
            MpfrKernelChoice::Generic => None,
        };
        Self {
            mpfr,
            field,
            order,
            series: vec![row.clone(); order + 1],
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
            match self.mpfr.as_mut() {
                Some(kernel) => {
                    let series = (&self.series as &dyn Any)
                        .downcast_ref::<Vec<[Float; DIM]>>()
                        .expect("the MPFR kernel runs on MPFR series");
                    let out = (&mut self.out as &mut dyn Any)
                        .downcast_mut::<[Float; DIM]>()
                        .expect("the MPFR kernel runs on MPFR series");
                    kernel.coefficient(&series[..=n], n, out);
                }
                None => self.field.taylor_coefficient_orders(
                    &self.series[..=n],
                    n,
                    &mut self.out,
                    &mut self.scratch,
                ),
            }
            if n == 0 {
                // First-order effect of the low parts: f(hi + lo) ≈ f(hi) + J(hi)·lo.
                let lo: [T; DIM] = std::array::from_fn(|i| state[i].lo.clone());
                let jl = self.field.jacobian_vector_product(&self.series[0], &lo);
                for (o, d) in self.out.iter_mut().zip(jl.iter()) {
                    *o += d;
                }
            }
            // The divisor n + 1 as an integer: the same rounding as dividing by the scalar
            // n + 1, without one (MPFR: mpfr_div_ui); in f64 the nine divisions vectorise.
            let div = n as u32 + 1;
            let row = &mut self.series[n + 1];
            for (s, o) in row.iter_mut().zip(&self.out) {
                s.clone_from(o);
                s.div_small(div);
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

/// The generic stepping loop of [`Taylor::propagate_field`].
pub(super) fn propagate<T: Real>(
    taylor: &Taylor,
    field: VectorField<T>,
    problem: &Problem<T>,
    grid: &OutputGrid,
) -> Result<Solution<T>, DynamicsError> {
    run(taylor, field, problem, grid, None).map(|(solution, _)| solution)
}

/// The same loop sampling its own steps, `k` times inside each ([`polynomial_step`]): the
/// samples (rounded to f64, the start left out) appended to `out`.
pub(super) fn propagate_steps<T: Real>(
    taylor: &Taylor,
    field: VectorField<T>,
    problem: &Problem<T>,
    grid: &OutputGrid,
    k: usize,
) -> Result<StepSamples, DynamicsError> {
    run(taylor, field, problem, grid, Some(k)).map(|(_, steps)| steps)
}

/// The stepping loop: the states at the grid times, or with `dense` = `Some(k)` the run's own
/// steps with k samples inside each.
fn run<T: Real>(
    taylor: &Taylor,
    field: VectorField<T>,
    problem: &Problem<T>,
    grid: &OutputGrid,
    dense: Option<usize>,
) -> Result<(Solution<T>, StepSamples), DynamicsError> {
    let name = Taylor::name_for::<T>();
    let grid = OutputGrid::new(grid.t_end, grid.samples)?;
    let like = problem.initial.omega[0].clone();
    let bits = like.prec();
    let order = match taylor.fixed {
        Some(fixed) => fixed.order,
        None => Taylor::order_for(taylor.effective_tolerance(bits)?),
    };
    let x0 = problem.initial.to_array();
    if x0.iter().any(|x| !x.is_finite()) {
        return Err(DynamicsError::State(
            "initial state has a component that is not a finite number".into(),
        ));
    }
    let kernel = match taylor.mpfr_kernel {
        Some(k) => k,
        None => MpfrKernelChoice::from_env().map_err(DynamicsError::Settings)?,
    };
    let mut work = Workspace::new(field, order, &like, kernel);
    let Tolerances { rtol, atol } = taylor.tolerances;
    let safety = (-0.7 / (order as f64 - 1.0)).exp() / std::f64::consts::E.powi(2);

    let start = Instant::now();
    let mut state: Vec<Compensated<T>> = x0
        .into_iter()
        .map(|x| Compensated::new(x, taylor.compensated))
        .collect();
    let mut t = Compensated::new(like.zero_like(), taylor.compensated);
    let mut stats = Stats::default();
    let mut times = Vec::with_capacity(grid.samples);
    let mut states = Vec::with_capacity(grid.samples);
    let mut steps = StepSamples::default();
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

        // Jorba–Zou step (or the fixed one).
        let t_now = t.value().to_f64();
        let mut h = match taylor.fixed {
            Some(fixed) => fixed.step,
            None => {
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
                rho * safety
            }
        };
        if !h.is_finite() {
            // All coefficients vanish (an equilibrium): one step to the end.
            h = (grid.t_end - t_now).max(f64::MIN_POSITIVE);
        }
        if h.is_nan() || h <= 1e-15 * t_now.abs() || h <= 0.0 {
            return Err(DynamicsError::Integration(format!(
                "{name}: step size {h:e} too small at t = {t_now} (singular solution?)"
            )));
        }

        if let Some(k) = dense {
            // The step's own samples, each at its f64 time (t is kept to more than f64: at
            // the step end τ differs from h by the rounding of t + h to f64).
            let (samples, last) = polynomial_step(t_now, h, grid.t_end, k);
            for (ts, end) in samples {
                let tau = (like.lit(ts) - &t.hi) - &t.lo;
                work.increment(&tau, &mut inc);
                let y: [f64; DIM] = std::array::from_fn(|i| {
                    (state[i].hi.clone() + (state[i].lo.clone() + &inc[i])).to_f64()
                });
                steps.push_step_sample(name, ts, y, end)?;
            }
            steps.check_size(name)?;
            if last {
                break;
            }
        }
        // Dense output at the grid times inside [t, t + h].
        let t_step_end = t_now + h;
        while dense.is_none() && next < grid.samples && grid.time(next) <= t_step_end {
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
    let solution = Solution {
        method: name,
        times,
        states,
        stats,
    };
    Ok((solution, steps))
}
