//! Observed order of convergence (issue 18, `rsts convergence`): methods run at fixed steps
//! along one motion, their error against the closed form per step, and the order p of
//! error ≈ C·hᵖ fitted by least squares over the asymptotic window, found automatically.
//!
//! The fit ([`fit_order`], module `fit`; issue 33): the local slopes between neighbouring steps
//! (log error against log step) are computed; a window is a run of at least two neighbouring
//! slopes that all lie within max(0.15, 0.05·|m|) of their median m (m ≥ 0.5: the error
//! falls). The longest window is taken first (ties: the smaller steps), then the longest in
//! what is left, and so on: each window with a point above round-off is a regime with its own
//! order, and the order of the fit is that of the regime of the smallest steps. Below it, the
//! floor is judged against the round-off the method's precision allows after that many steps
//! ([`RoundOff`]: u·|x|·√n to u·|x|·n); above it, the steps are pre-asymptotic, or noise when
//! the error does not fall with the step — each listed with why.
//!
//! A step h is used as Δ/⌈Δ/h⌉ (Δ = T/(N−1), the sample spacing), so every sample is the end of
//! a step; a row's `step` is the step used.

use rug::Float;
use serde::{Deserialize, Serialize};

use rsts_dynamics::integrators::{
    map_problem, map_solution, DormandPrince, FixedStepDormandPrince, MethodName, OutputGrid,
    Problem, Propagator, Rk4, Taylor,
};
use rsts_dynamics::scalar::DoubleDouble;

use crate::bench::{max_state_error, Reference};
use crate::case::Case;
use crate::compare::reference_bits_for;
use crate::integrator::{Integrator, Propagated, Trajectory};
use crate::HarnessError;

/// An integrator that can be run at a fixed step (built-in: [`FixedStepMethod`]; an external
/// process with `"step"` in its request).
pub trait FixedStepIntegrator {
    /// Name in the rows and fits.
    fn name(&self) -> String;
    /// How messages name it (default: its name; an external one adds its command).
    fn label(&self) -> String {
        self.name()
    }
    /// Bits of its scalar (the reference is evaluated beyond them).
    fn working_bits(&self) -> u32;
    /// Bits of the arithmetic it rounds in, for the round-off it may accumulate (default: its
    /// working bits; an external one the precision it answered in).
    fn round_off_bits(&self) -> u32 {
        self.working_bits()
    }
    /// The states at `times` (an even grid whose spacing is a whole multiple of `step`),
    /// every step of length `step`.
    fn integrate_at(
        &mut self,
        step: f64,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError>;
}

/// A built-in method at fixed steps: rk4, dopri5 and dop853 with the step control off, the
/// Taylor methods at a fixed order.
#[derive(Clone, Copy, Debug)]
pub struct FixedStepMethod {
    pub method: MethodName,
    /// Order of the Taylor methods (required for them, refused for the others).
    pub order: Option<usize>,
    /// Digits of taylor-mp.
    pub digits: u32,
}

impl FixedStepMethod {
    /// Checked: the Taylor methods need an order (else an error naming `methods` and
    /// `order`), the others take none.
    pub fn new(
        method: MethodName,
        order: Option<usize>,
        digits: u32,
    ) -> Result<Self, HarnessError> {
        let taylor = matches!(
            method,
            MethodName::TaylorF64 | MethodName::TaylorDd | MethodName::TaylorMp
        );
        match (taylor, order) {
            (true, None) => Err(HarnessError::setting(
                &["methods", "order"],
                format!(
                    "{method} at fixed steps needs a fixed order (--order P); try --order {} \
                 (its error then reaches the {} round-off within a sweep of 8 halvings from 0.5)",
                    suggested_order(method),
                    if method == MethodName::TaylorF64 {
                        "f64"
                    } else {
                        "working precision's"
                    }
                ),
            )),
            (true, Some(p)) => {
                Taylor::fixed(p, 1.0)
                    .map_err(|e| HarnessError::setting(&["order"], e.to_string()))?;
                Ok(Self {
                    method,
                    order,
                    digits,
                })
            }
            (false, _) => Ok(Self {
                method,
                order: None,
                digits,
            }),
        }
    }
}

/// The order suggested to a Taylor method given none: 8 in f64, 16 in double-double, 24 in MPFR.
pub fn suggested_order(method: MethodName) -> usize {
    match method {
        MethodName::TaylorF64 => 8,
        MethodName::TaylorDd => 16,
        _ => 24,
    }
}

impl FixedStepIntegrator for FixedStepMethod {
    fn name(&self) -> String {
        match self.order {
            Some(p) => format!("{}-p{p}", self.method),
            None => self.method.to_string(),
        }
    }

    fn working_bits(&self) -> u32 {
        self.method.working_bits(self.digits)
    }

    fn integrate_at(
        &mut self,
        step: f64,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        let dp = |m| -> Result<Trajectory, HarnessError> {
            Propagated::new(FixedStepDormandPrince::new(m, step)?).integrate(problem, times)
        };
        let taylor = || Taylor::fixed(self.order.unwrap_or(0), step);
        let bits = problem.initial.omega[0].prec();
        let grid = grid_of(times)?;
        match self.method {
            MethodName::Rk4 => Propagated::new(Rk4::new(step)).integrate(problem, times),
            MethodName::Dopri5 => dp(DormandPrince::Dopri5),
            MethodName::Dop853 => dp(DormandPrince::Dop853),
            MethodName::TaylorF64 => Propagated::new(taylor()?).integrate(problem, times),
            MethodName::TaylorDd => {
                let p = map_problem(problem, DoubleDouble::from_float);
                let sol = taylor()?.propagate_grid(&p, &grid)?;
                Ok(trajectory(map_solution(sol, |x| x.to_float(bits))))
            }
            MethodName::TaylorMp => {
                let w = self.working_bits();
                let p = map_problem(problem, |x| Float::with_val(w, x));
                let sol = taylor()?.propagate_grid(&p, &grid)?;
                Ok(trajectory(map_solution(sol, |x| Float::with_val(bits, x))))
            }
        }
    }
}

fn trajectory(sol: rsts_dynamics::integrators::Solution<Float>) -> Trajectory {
    Trajectory {
        times: sol.times,
        states: sol.states,
        stats: sol.stats,
        wall_seconds: None,
    }
}

/// The even grid `times` is (from [`ConvergencePlan`]).
fn grid_of(times: &[f64]) -> Result<OutputGrid, HarnessError> {
    Ok(OutputGrid::new(
        times.last().copied().unwrap_or(0.0),
        times.len(),
    )?)
}

/// Most steps of a whole sweep (every method and step).
pub const MAX_SWEEP_STEPS: f64 = 1e9;
/// Most samples of a convergence study (the reference keeps them all in high precision).
pub const MAX_CONVERGENCE_SAMPLES: usize = 100_000;

/// What to run: a motion and the fixed steps (largest first, each a whole fraction of the
/// sample spacing).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergencePlan {
    pub case: Case,
    pub steps: Vec<f64>,
}

impl ConvergencePlan {
    /// Checked: the case, T > 0, N ≥ 2, at least 3 distinct positive steps none above the
    /// sample spacing Δ; each step becomes Δ/⌈Δ/h⌉.
    pub fn new(case: Case, steps: &[f64]) -> Result<Self, HarnessError> {
        case.validate()?;
        let t_end = case.t_end_f64();
        if t_end <= 0.0 {
            return Err(HarnessError::setting(
                &["t-end"],
                format!(
                    "t-end must be positive for a convergence study, got {}",
                    case.t_end
                ),
            ));
        }
        if !(2..=MAX_CONVERGENCE_SAMPLES).contains(&case.samples) {
            return Err(HarnessError::setting(
                &["samples"],
                format!(
                    "samples must be between 2 and {MAX_CONVERGENCE_SAMPLES} for a convergence \
                     study (the error is measured there), got {}",
                    case.samples
                ),
            ));
        }
        let spacing = OutputGrid::new(t_end, case.samples)?.spacing();
        let mut used: Vec<f64> = Vec::new();
        for &h in steps {
            if !(h.is_finite() && h > 0.0) {
                return Err(HarnessError::setting(
                    &["steps"],
                    format!("steps must be positive finite numbers, got {h}"),
                ));
            }
            if h > spacing * (1.0 + 1e-12) {
                return Err(HarnessError::setting(
                    &["steps"],
                    format!(
                        "steps: {h} is larger than the sample spacing {} (t-end/(samples - 1)); \
                         use fewer samples or smaller steps",
                        rsts_dynamics::short(spacing)
                    ),
                ));
            }
            let e = spacing / (spacing / h).ceil().max(1.0);
            if !used.contains(&e) {
                used.push(e);
            }
        }
        used.sort_by(|a, b| b.total_cmp(a));
        if used.len() < 3 {
            return Err(HarnessError::setting(
                &["steps"],
                format!(
                    "steps: an order is fitted over at least 3 distinct steps, got {} \
                     (a step h is used as the sample spacing over a whole number of steps)",
                    used.len()
                ),
            ));
        }
        let per_method: f64 = used.iter().map(|h| t_end / h).sum();
        if per_method > MAX_SWEEP_STEPS {
            return Err(HarnessError::setting(
                &["t-end"],
                format!(
                    "t-end {} takes about {} steps per method at these steps, more than the \
                     limit of {}; use larger steps or a shorter t-end",
                    rsts_dynamics::short(t_end),
                    rsts_dynamics::short(per_method),
                    rsts_dynamics::short(MAX_SWEEP_STEPS)
                ),
            ));
        }
        Ok(Self { case, steps: used })
    }
}

/// Halvings of the default sweep ([`ConvergencePlan::default_steps`]).
pub const DEFAULT_HALVINGS: u32 = 8;

impl ConvergencePlan {
    /// The default sweep when no steps are given: H, H/2, …, H/2⁸ with H = min(0.5, Δ), Δ =
    /// T/(N − 1) the sample spacing (T = 10, N = 11: 0.5 down to 0.00195).
    pub fn default_steps(case: &Case) -> Vec<f64> {
        let spacing = case.t_end_f64() / (case.samples.max(2) - 1) as f64;
        halvings(spacing.min(0.5), DEFAULT_HALVINGS)
    }
}

/// The steps H, H/2, …, H/2^K.
pub fn halvings(step: f64, k: u32) -> Vec<f64> {
    (0..=k).map(|j| step / 2f64.powi(j as i32)).collect()
}

/// One method at one step: a JSON row of `rsts convergence`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceRow {
    pub method: String,
    /// The step used.
    pub step: f64,
    /// max over samples and the nine components of |x − x_exact|.
    pub max_error: f64,
    /// The same at the last sample.
    pub final_error: f64,
    pub steps: u64,
    pub rhs_evals: u64,
}

/// The JSON document of `rsts convergence`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceReport {
    pub case: Case,
    pub rows: Vec<ConvergenceRow>,
    pub fits: Vec<OrderFit>,
}

/// Run every method at every step of `plan` and fit their orders. An integrator whose states do
/// not change with the step (it ignored it) is refused, naming it.
pub fn convergence(
    plan: &ConvergencePlan,
    methods: &mut [&mut dyn FixedStepIntegrator],
) -> Result<ConvergenceReport, HarnessError> {
    convergence_until(plan, methods, &mut || false)
}

/// [`convergence`], asking `stop` before every run (each method at each step): when it says
/// true the work ends with [`HarnessError::Observer`] (a face's Ctrl-C).
pub fn convergence_until(
    plan: &ConvergencePlan,
    methods: &mut [&mut dyn FixedStepIntegrator],
    stop: &mut dyn FnMut() -> bool,
) -> Result<ConvergenceReport, HarnessError> {
    let bits = methods
        .iter()
        .map(|m| reference_bits_for(m.working_bits()))
        .max()
        .ok_or_else(|| HarnessError::setting(&["methods"], "no method to run"))?;
    let reference = Reference::new(&plan.case, bits)?;
    let problem = Problem {
        fields: reference.fields().clone(),
        initial: reference.states()[0].clone(),
    };
    let last = reference.states().len() - 1;
    // |x| of the round-off model: the largest |component| along the motion.
    let size = reference
        .states()
        .iter()
        .flat_map(|x| x.to_array())
        .map(|c| c.to_f64().abs())
        .fold(0.0, f64::max);
    let t_end = plan.case.t_end_f64();
    let mut rows = Vec::new();
    let mut fits = Vec::new();
    for method in methods.iter_mut() {
        let label = method.label();
        let mut first: Option<Vec<_>> = None;
        let mut changed = false;
        let mut mine = Vec::new();
        for &h in &plan.steps {
            if stop() {
                return Err(HarnessError::Observer("interrupted".into()));
            }
            let traj = method
                .integrate_at(h, &problem, reference.times())
                .map_err(|e| {
                    HarnessError::Integrator(format!("{} at step {h}: {e}", method.name()))
                })?;
            match &first {
                None => first = Some(traj.states.clone()),
                Some(f) => changed |= *f != traj.states,
            }
            let max_error = max_state_error(reference.states(), &traj.states)?;
            let final_error = max_state_error(
                &reference.states()[last..],
                traj.states.get(last..).unwrap_or(&[]),
            )?;
            mine.push(ConvergenceRow {
                method: String::new(),
                step: h,
                max_error,
                final_error,
                steps: traj.stats.accepted_steps,
                rhs_evals: traj.stats.rhs_evals,
            });
        }
        // An external integrator names itself in its answers.
        let name = method.name();
        for r in &mut mine {
            r.method.clone_from(&name);
        }
        if !changed {
            return Err(HarnessError::Integrator(format!(
                "{label}: its answers do not change with the step (it ignores the fixed step \
                 asked); an order cannot be fitted"
            )));
        }
        let steps: Vec<f64> = mine.iter().map(|r| r.step).collect();
        let errors: Vec<f64> = mine.iter().map(|r| r.max_error).collect();
        let round_off = RoundOff {
            bits: method.round_off_bits(),
            size,
        };
        let expected: Vec<f64> = steps
            .iter()
            .map(|h| round_off.expected(t_end / h))
            .collect();
        let fit = fit_order(&steps, &errors, &expected)
            .map_err(|e| HarnessError::Integrator(format!("{label}: {e}")))?;
        fits.push(OrderFit {
            method: name,
            ..fit
        });
        rows.extend(mine);
    }
    Ok(ConvergenceReport {
        case: plan.case.clone(),
        rows,
        fits,
    })
}

pub mod diagram;
mod fit;

pub use fit::{
    fit_order, least_squares, order_with_error, two_digits, Excluded, ExcludedKind, Floor,
    FloorKind, OrderFit, Regime, RoundOff, MIN_WINDOW_SLOPE, NOISE_DECADE, ROUND_OFF_MARGIN,
};
#[cfg(test)]
mod floor_tests;
#[cfg(test)]
mod tests;
