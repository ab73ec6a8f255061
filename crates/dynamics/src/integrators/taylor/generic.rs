//! The generic Taylor stepper: one code over any scalar [`Real`] (f64, double-double, MPFR),
//! coefficients from [`VectorField::taylor_coefficient_orders`], state and time kept as
//! compensated sums hi + lo (see the module [`super`] for the method).

use std::any::Any;

use rug::Float;

use crate::equations::{CauchyScratch, VectorField};
use crate::error::DynamicsError;
use crate::integrators::dense::StepSamples;
use crate::integrators::{OutputGrid, Problem, Solution, Tolerances};
use crate::scalar::Real;
use crate::state::{State, DIM};

use super::mp::{MpfrKernel, MpfrKernelChoice};
use super::stepping::{run_steps, Stepper};
use super::Taylor;

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

/// The same loop sampling its own steps, `k` times inside each
/// ([`polynomial_step`](crate::integrators::dense::polynomial_step)): the
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

/// The generic stepper over [`run_steps`]: the states at the grid times, or with `dense` =
/// `Some(k)` the run's own steps with k samples inside each.
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
    let mut stepper = GenericStepper {
        work: Workspace::new(field, order, &like, kernel),
        taylor,
        safety: (-0.7 / (order as f64 - 1.0)).exp() / std::f64::consts::E.powi(2),
        state: x0
            .into_iter()
            .map(|x| Compensated::new(x, taylor.compensated))
            .collect(),
        t: Compensated::new(like.zero_like(), taylor.compensated),
        inc: std::array::from_fn(|_| like.zero_like()),
        like,
    };
    // SAFETY: the generic stepper needs no CPU feature beyond the build's.
    let out = unsafe { run_steps(&mut stepper, name, order, &grid, dense)? };
    let solution = Solution {
        method: name,
        times: out.times,
        states: out.states,
        stats: out.stats,
    };
    Ok((solution, out.steps))
}

/// The state and the time of a generic run, kept as compensated sums.
struct GenericStepper<'a, T> {
    work: Workspace<T>,
    taylor: &'a Taylor,
    /// e^(−0.7/(p − 1))/e², Jorba–Zou's safety factor.
    safety: f64,
    state: Vec<Compensated<T>>,
    t: Compensated<T>,
    /// Σ_{k≥1} x_k τ^k of the last evaluation.
    inc: [T; DIM],
    /// A number of the run's precision (for constants).
    like: T,
}

impl<T: Real> GenericStepper<'_, T> {
    /// The polynomial's increment at time `t` (τ = t − (t.hi + t.lo)) into `inc`.
    fn increment_at(&mut self, t: f64) {
        let tau = (self.like.lit(t) - &self.t.hi) - &self.t.lo;
        self.work.increment(&tau, &mut self.inc);
    }
}

impl<T: Real> Stepper for GenericStepper<'_, T> {
    type State = State<T>;

    fn now(&self) -> f64 {
        self.t.value().to_f64()
    }

    unsafe fn coefficients(&mut self) {
        self.work.coefficients(&self.state);
    }

    /// Jorba–Zou's step (or the fixed one).
    unsafe fn step(&self) -> f64 {
        if let Some(fixed) = self.taylor.fixed {
            return fixed.step;
        }
        let Tolerances { rtol, atol } = self.taylor.tolerances;
        let ln_x = {
            let mut norm = self.state[0].hi.abs();
            for x in &self.state[1..] {
                norm = norm.max_of(x.hi.abs());
            }
            let n = norm.to_f64();
            if rtol * n > atol {
                n.ln()
            } else {
                0.0
            }
        };
        let order = self.work.order;
        let rho = [order - 1, order]
            .into_iter()
            .map(|m| ((ln_x - self.work.ln_norm(m)) / m as f64).exp())
            .fold(f64::INFINITY, f64::min);
        rho * self.safety
    }

    fn least_step(&self) -> f64 {
        f64::MIN_POSITIVE
    }

    fn rounded(&self, h: f64) -> f64 {
        h
    }

    unsafe fn state_at(&mut self, t: f64) -> State<T> {
        self.increment_at(t);
        let x: Vec<T> = self
            .state
            .iter()
            .zip(&self.inc)
            .map(|(s, d)| s.hi.clone() + (s.lo.clone() + d))
            .collect();
        State::from_slice(&x)
    }

    /// Each sample at its f64 time (t is kept to more than f64: at the step end τ differs
    /// from h by the rounding of t + h to f64).
    unsafe fn state_at_f64(&mut self, t: f64) -> [f64; DIM] {
        self.increment_at(t);
        let (state, inc) = (&self.state, &self.inc);
        std::array::from_fn(|i| (state[i].hi.clone() + (state[i].lo.clone() + &inc[i])).to_f64())
    }

    fn is_finite(x: &State<T>) -> bool {
        let mut all = x.omega.iter().chain(&x.alpha).chain(&x.beta);
        all.all(|v| v.is_finite())
    }

    /// The compensated update of the state and the time.
    unsafe fn advance(&mut self, h: f64) {
        let h_t = self.like.lit(h);
        self.work.increment(&h_t, &mut self.inc);
        for (s, d) in self.state.iter_mut().zip(&self.inc) {
            s.add(d);
        }
        self.t.add(&h_t);
    }
}
