//! Integrators of the Euler–Poisson equations behind one interface.
//!
//! A [`Problem`] (fields and initial state), an integrator (a value of a type implementing
//! [`Propagator`], configured with its tolerances) and an [`OutputGrid`] are separate values;
//! [`Propagator::propagate_grid`] returns a [`Solution`]: the states at the grid times and the
//! [`Stats`] of the run. One file per method; the runtime choice is [`MethodConfig`].

pub mod dense;
mod dop853;
mod dopri5;
mod fixed_step;
mod ode_solvers_adapter;
mod rk4;
mod taylor;

pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use fixed_step::{DormandPrince, FixedStepDormandPrince};
pub use rk4::Rk4;
pub use taylor::{
    FixedOrderStep, MpfrKernel, MpfrKernelChoice, SimdPath, Taylor, LANE_EXTRA_BITS,
    MAX_ORDER as TAYLOR_MAX_ORDER, MPFR_MAX_DEFAULT_LIMBS, SIMD_ENV,
};

use std::fmt;
use std::str::FromStr;

use rug::Float;
use serde::Serialize;

use crate::error::DynamicsError;
use crate::fields::Fields;
use crate::scalar::{bits_for_digits, DoubleDouble, Real};
use crate::state::State;

/// An initial-value problem: the fields and the state at t = 0.
#[derive(Clone, Debug)]
pub struct Problem<T> {
    pub fields: Fields<T>,
    pub initial: State<T>,
}

/// N sample times evenly spaced on [0, T] (N = 1: t = 0 only).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OutputGrid {
    pub t_end: f64,
    pub samples: usize,
}

impl OutputGrid {
    /// Checked constructor: T finite and ≥ 0, N ≥ 1 (N ≥ 2 when T > 0 is not needed: N = 1
    /// samples t = 0 only).
    pub fn new(t_end: f64, samples: usize) -> Result<Self, DynamicsError> {
        if !t_end.is_finite() {
            return Err(DynamicsError::Settings(format!(
                "t-end must be a finite number, got {t_end}"
            )));
        }
        if t_end < 0.0 {
            return Err(DynamicsError::Settings(format!(
                "t-end must be non-negative, got {t_end}"
            )));
        }
        if samples == 0 {
            return Err(DynamicsError::Settings(
                "samples must be at least 1".to_string(),
            ));
        }
        Ok(Self { t_end, samples })
    }

    /// Spacing of the samples (0 for a single sample).
    pub fn spacing(&self) -> f64 {
        if self.samples <= 1 {
            0.0
        } else {
            self.t_end / (self.samples - 1) as f64
        }
    }

    /// The k-th sample time, k·T/(N−1), computed without accumulation.
    pub fn time(&self, k: usize) -> f64 {
        if self.samples <= 1 {
            0.0
        } else if k + 1 == self.samples {
            self.t_end
        } else {
            self.t_end * k as f64 / (self.samples - 1) as f64
        }
    }

    pub fn times(&self) -> Vec<f64> {
        (0..self.samples).map(|k| self.time(k)).collect()
    }
}

/// Error control of adaptive methods.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tolerances {
    pub rtol: f64,
    pub atol: f64,
}

impl Tolerances {
    /// Checked constructor: both finite, positive and at most 1 (the state is of order 1: a
    /// tolerance above 1 accepts any answer).
    pub fn new(rtol: f64, atol: f64) -> Result<Self, DynamicsError> {
        for (name, v) in [("rtol", rtol), ("atol", atol)] {
            if !v.is_finite() || v <= 0.0 {
                return Err(DynamicsError::Settings(format!(
                    "{name} must be a positive finite number, got {}",
                    crate::short(v)
                )));
            }
            if v > 1.0 {
                return Err(DynamicsError::Settings(format!(
                    "{name} must be at most 1 (the state is of order 1; a larger tolerance \
                     accepts any answer), got {}",
                    crate::short(v)
                )));
            }
        }
        Ok(Self { rtol, atol })
    }
}

/// Most steps one run may take, every method (the integrators stop there; a run whose estimate
/// exceeds it is refused before it starts, see [`MethodConfig::check_budget`]).
pub const MAX_STEPS: u64 = 200_000_000;

/// Unit round-off of f64, 2⁻⁵³: the smallest rtol the f64 methods accept.
pub const F64_UNIT_ROUNDOFF: f64 = 1.1102230246251565e-16;

/// What a run cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Stats {
    pub accepted_steps: u64,
    pub rejected_steps: u64,
    pub rhs_evals: u64,
    /// Wall time of the integration alone (no set-up, no output formatting).
    pub integration_seconds: f64,
}

/// States at the grid times.
#[derive(Clone, Debug)]
pub struct Solution<T> {
    pub method: &'static str,
    pub times: Vec<f64>,
    pub states: Vec<State<T>>,
    pub stats: Stats,
}

/// An integration method for the Euler–Poisson equations in scalar `T`.
pub trait Propagator<T: Real> {
    /// Name used on the command line and in reports.
    fn name(&self) -> &'static str;
    /// States at every time of `grid`, starting from `problem.initial` at t = 0.
    fn propagate_grid(
        &self,
        problem: &Problem<T>,
        grid: &OutputGrid,
    ) -> Result<Solution<T>, DynamicsError>;
}

/// The methods that can be chosen at run time.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MethodName {
    Rk4,
    Dopri5,
    Dop853,
    /// Taylor series in f64 with compensated state ([`Taylor`]).
    #[serde(rename = "taylor-f64")]
    TaylorF64,
    /// Taylor series in double-double (106 bits).
    #[serde(rename = "taylor-dd")]
    TaylorDd,
    /// Taylor series in MPFR at [`MethodConfig::digits`] digits.
    #[serde(rename = "taylor-mp")]
    TaylorMp,
}

impl MethodName {
    pub const ALL: [MethodName; 6] = [
        MethodName::Rk4,
        MethodName::Dopri5,
        MethodName::Dop853,
        MethodName::TaylorF64,
        MethodName::TaylorDd,
        MethodName::TaylorMp,
    ];

    pub fn as_str(&self) -> &'static str {
        match self {
            MethodName::Rk4 => Rk4::NAME,
            MethodName::Dopri5 => Dopri5::NAME,
            MethodName::Dop853 => Dop853::NAME,
            MethodName::TaylorF64 => Taylor::NAME_F64,
            MethodName::TaylorDd => Taylor::NAME_DD,
            MethodName::TaylorMp => Taylor::NAME_MP,
        }
    }

    /// Bits of the scalar the method computes in, given the digits of a `taylor-mp` run.
    pub fn working_bits(&self, digits: u32) -> u32 {
        match self {
            MethodName::TaylorDd => crate::scalar::double_double::DD_BITS,
            MethodName::TaylorMp => bits_for_digits(digits),
            _ => crate::scalar::F64_BITS,
        }
    }
}

impl fmt::Display for MethodName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for MethodName {
    type Err = DynamicsError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.as_str() == s.to_ascii_lowercase())
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|m| m.as_str()).collect();
                DynamicsError::Settings(format!(
                    "unknown method '{s}' (known: {})",
                    names.join(", ")
                ))
            })
    }
}

/// Decimal digits of `taylor-mp` when [`MethodConfig::digits`] is `None`.
pub const DEFAULT_MP_DIGITS: u32 = 50;
/// Largest accepted [`MethodConfig::digits`].
pub const MAX_MP_DIGITS: u32 = 10_000;

/// A method with its settings, chosen at run time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MethodConfig {
    pub method: MethodName,
    pub tolerances: Tolerances,
    /// Fixed step for non-adaptive methods (RK4); `None`: derived from the tolerance.
    pub step: Option<f64>,
    /// Decimal digits of the MPFR scalar of `taylor-mp` (ignored by the other methods);
    /// `None`: [`DEFAULT_MP_DIGITS`]. Its tolerance is the config's (rtol, atol), with rtol not
    /// below 2^-bits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub digits: Option<u32>,
}

impl MethodConfig {
    /// Checked: a positive finite step; for the adaptive f64 methods an rtol not below the unit
    /// round-off of f64 (2⁻⁵³ ≈ 1.1e-16; the Taylor methods check theirs against their scalar).
    pub fn new(
        method: MethodName,
        tolerances: Tolerances,
        step: Option<f64>,
    ) -> Result<Self, DynamicsError> {
        if let Some(h) = step {
            if !h.is_finite() || h <= 0.0 {
                return Err(DynamicsError::Settings(format!(
                    "step must be a positive finite number, got {}",
                    crate::short(h)
                )));
            }
        }
        if matches!(method, MethodName::Dopri5 | MethodName::Dop853)
            && tolerances.rtol < F64_UNIT_ROUNDOFF
        {
            return Err(DynamicsError::Settings(format!(
                "rtol = {} is below the unit round-off 1.1e-16 of f64: {method} cannot deliver \
                 it (its error estimate drowns in rounding and the step shrinks without end); \
                 use taylor-dd (to 1e-32) or taylor-mp",
                crate::short(tolerances.rtol)
            )));
        }
        Ok(Self {
            method,
            tolerances,
            step,
            digits: None,
        })
    }

    /// The same config with `digits` decimal digits for `taylor-mp` (checked: 10 to
    /// [`MAX_MP_DIGITS`]).
    pub fn with_digits(self, digits: u32) -> Result<Self, DynamicsError> {
        if !(10..=MAX_MP_DIGITS).contains(&digits) {
            return Err(DynamicsError::Settings(format!(
                "digits must be between 10 and {MAX_MP_DIGITS}, got {digits}"
            )));
        }
        Ok(Self {
            digits: Some(digits),
            ..self
        })
    }

    /// Digits of `taylor-mp`: the configured ones or [`DEFAULT_MP_DIGITS`].
    pub fn mp_digits(&self) -> u32 {
        self.digits.unwrap_or(DEFAULT_MP_DIGITS)
    }

    /// Bits of the scalar this config computes in.
    pub fn working_bits(&self) -> u32 {
        self.method.working_bits(self.mp_digits())
    }

    /// The smallest tolerance this config accepts: the unit round-off 2^-bits of its scalar,
    /// 2^-(bits + 8) for taylor-f64 and taylor-dd, whose compensated state carries one f64 more
    /// ([`taylor::LANE_EXTRA_BITS`]).
    pub fn min_tolerance(&self) -> f64 {
        let extra = match self.method {
            MethodName::TaylorF64 | MethodName::TaylorDd => taylor::LANE_EXTRA_BITS,
            _ => 0,
        };
        2f64.powi(-((self.working_bits() + extra).min(1000) as i32))
    }

    /// The most steps a run of this method may take.
    pub fn step_limit(&self) -> u64 {
        match self.method {
            MethodName::Rk4 | MethodName::Dopri5 | MethodName::Dop853 => MAX_STEPS,
            _ => taylor::MAX_STEPS,
        }
    }

    /// An optimistic estimate of the steps a run over [0, `grid.t_end`] takes: exact for rk4;
    /// c·λ·T·tol^(−1/p) for the Dormand–Prince methods of order p and c·λ·T for the Taylor
    /// methods (whose order grows with the tolerance), with λ = |ω₀| + √(a + b) the rate of the
    /// motion and tol = max(rtol, atol). The constants c are a quarter of those measured on the
    /// default case (dop853 0.11, dopri5 0.13, Taylor 1.4 steps per unit of λT), so the estimate
    /// undercounts: only jobs that are hopeless are refused.
    pub fn estimate_steps(&self, problem: &Problem<f64>, grid: &OutputGrid) -> f64 {
        if grid.samples <= 1 || grid.t_end == 0.0 {
            return 0.0;
        }
        let w = &problem.initial.omega;
        let rate = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
            + (problem.fields.a + problem.fields.b).max(0.0).sqrt();
        let tol = self.tolerances.rtol.max(self.tolerances.atol).min(1.0);
        let work = rate * grid.t_end;
        match self.method {
            MethodName::Rk4 => Rk4::from_tolerances(self.tolerances, self.step).steps_for(grid),
            MethodName::Dopri5 => 0.13 / 4.0 * work * tol.powf(-1.0 / Dopri5::ORDER as f64),
            MethodName::Dop853 => 0.11 / 4.0 * work * tol.powf(-1.0 / Dop853::ORDER as f64),
            _ => 1.4 / 4.0 * work,
        }
    }

    /// Refuse at once a run whose [`estimate_steps`](Self::estimate_steps) exceeds its
    /// [`step_limit`](Self::step_limit), with the estimate.
    pub fn check_budget(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
    ) -> Result<(), DynamicsError> {
        let steps = self.estimate_steps(problem, grid);
        let limit = self.step_limit() as f64;
        if steps <= limit {
            return Ok(());
        }
        let how = match self.method {
            MethodName::Rk4 => format!(
                "rk4 with step {} takes",
                crate::short(Rk4::from_tolerances(self.tolerances, self.step).step)
            ),
            m => format!(
                "{m} at rtol {}, atol {} needs at least about",
                crate::short(self.tolerances.rtol),
                crate::short(self.tolerances.atol)
            ),
        };
        Err(DynamicsError::Settings(format!(
            "{how} {} steps over t-end {} (estimated from the tolerance, T and the method's \
             order), more than the limit of {} steps per run; shorten t-end or loosen the \
             tolerance{}",
            crate::short(steps),
            crate::short(grid.t_end),
            crate::short(limit),
            if self.method == MethodName::Rk4 {
                " (rk4: a larger step)"
            } else {
                ""
            }
        )))
    }

    /// Run the configured method from a high-precision problem and return high-precision states
    /// (at the precision of `problem.initial`). The problem is rounded to the method's scalar
    /// (f64, double-double, MPFR at the configured digits) and the states are widened exactly
    /// (f64, double-double) or rounded (MPFR) to the problem's precision.
    pub fn propagate_mp(
        &self,
        problem: &Problem<Float>,
        grid: &OutputGrid,
    ) -> Result<Solution<Float>, DynamicsError> {
        let out_bits = problem.initial.omega[0].prec();
        self.check_budget(&map_problem(problem, Float::to_f64), grid)?;
        let widen = |x: &f64| Float::with_val(out_bits, *x);
        match self.method {
            MethodName::Rk4 | MethodName::Dopri5 | MethodName::Dop853 => {
                let p = map_problem(problem, Float::to_f64);
                Ok(map_solution(self.propagate_f64(&p, grid)?, widen))
            }
            // The start state and the fields enter with their low parts; the compensated
            // states come back whole.
            MethodName::TaylorF64 => {
                Taylor::new(self.tolerances).propagate_float(false, problem, grid)
            }
            MethodName::TaylorDd => {
                Taylor::new(self.tolerances).propagate_float(true, problem, grid)
            }
            MethodName::TaylorMp => {
                let bits = self.working_bits();
                let p = map_problem(problem, |x| Float::with_val(bits, x));
                let sol = Taylor::new(self.tolerances).propagate_grid(&p, grid)?;
                Ok(map_solution(sol, |x| Float::with_val(out_bits, x)))
            }
        }
    }

    /// Run the configured method in f64.
    pub fn propagate_f64(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
    ) -> Result<Solution<f64>, DynamicsError> {
        self.check_budget(problem, grid)?;
        match self.method {
            MethodName::Rk4 => {
                Rk4::from_tolerances(self.tolerances, self.step).propagate_grid(problem, grid)
            }
            MethodName::Dopri5 => Dopri5::new(self.tolerances).propagate_grid(problem, grid),
            MethodName::Dop853 => Dop853::new(self.tolerances).propagate_grid(problem, grid),
            MethodName::TaylorF64 => Taylor::new(self.tolerances).propagate_grid(problem, grid),
            MethodName::TaylorDd => {
                let p = map_problem(problem, |x| DoubleDouble::from_f64_exact(*x));
                let sol = Taylor::new(self.tolerances).propagate_grid(&p, grid)?;
                Ok(map_solution(sol, Real::to_f64))
            }
            MethodName::TaylorMp => {
                let bits = self.working_bits();
                let p = map_problem(problem, |x| Float::with_val(bits, x));
                let sol = Taylor::new(self.tolerances).propagate_grid(&p, grid)?;
                Ok(map_solution(sol, Real::to_f64))
            }
        }
    }
}

impl MethodConfig {
    /// The run of [`propagate_f64`](Self::propagate_f64) on `grid` as its own steps, with `k`
    /// samples of the method's dense output inside each ([`dense`]: how each method
    /// interpolates).
    pub fn propagate_steps(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
        k: usize,
    ) -> Result<dense::StepSamples, DynamicsError> {
        self.check_budget(problem, grid)?;
        match self.method {
            MethodName::Rk4 => {
                Rk4::from_tolerances(self.tolerances, self.step).propagate_steps(problem, grid, k)
            }
            MethodName::Dopri5 => Dopri5::new(self.tolerances).propagate_steps(problem, grid, k),
            MethodName::Dop853 => Dop853::new(self.tolerances).propagate_steps(problem, grid, k),
            MethodName::TaylorF64 => Taylor::new(self.tolerances).propagate_steps(problem, grid, k),
            MethodName::TaylorDd => {
                let p = map_problem(problem, |x| DoubleDouble::from_f64_exact(*x));
                Taylor::new(self.tolerances).propagate_steps(&p, grid, k)
            }
            MethodName::TaylorMp => {
                let bits = self.working_bits();
                let p = map_problem(problem, |x| Float::with_val(bits, x));
                Taylor::new(self.tolerances).propagate_steps(&p, grid, k)
            }
        }
    }
}

/// The problem in another scalar.
pub fn map_problem<T, U>(problem: &Problem<T>, f: impl Fn(&T) -> U) -> Problem<U> {
    Problem {
        fields: Fields {
            a: f(&problem.fields.a),
            b: f(&problem.fields.b),
        },
        initial: State {
            omega: std::array::from_fn(|i| f(&problem.initial.omega[i])),
            alpha: std::array::from_fn(|i| f(&problem.initial.alpha[i])),
            beta: std::array::from_fn(|i| f(&problem.initial.beta[i])),
        },
    }
}

/// The solution with its states in another scalar.
pub fn map_solution<T, U>(solution: Solution<T>, f: impl Fn(&T) -> U) -> Solution<U> {
    Solution {
        method: solution.method,
        times: solution.times,
        states: solution
            .states
            .iter()
            .map(|s| State {
                omega: std::array::from_fn(|i| f(&s.omega[i])),
                alpha: std::array::from_fn(|i| f(&s.alpha[i])),
                beta: std::array::from_fn(|i| f(&s.beta[i])),
            })
            .collect(),
        stats: solution.stats,
    }
}
