//! The stepping loop of the Taylor methods, written once ([`run_steps`]): the generic stepper
//! (`generic.rs`, any [`Real`](crate::scalar::Real)) and the lane stepper (`fast.rs`,
//! taylor-f64 and taylor-dd on every code path) hand it their coefficients, step rule,
//! polynomial and update ([`Stepper`]); the loop keeps the grid, the dense samples, the step
//! checks and the statistics.

use std::time::Instant;

use crate::error::DynamicsError;
use crate::integrators::dense::{polynomial_step, StepSamples};
use crate::integrators::{OutputGrid, Stats};
use crate::state::DIM;

use super::MAX_STEPS;

/// A Taylor stepper as the loop sees it. The methods are `unsafe` for the lane stepper, whose
/// code needs its path's CPU features (it exists only inside a function compiled with them).
pub(super) trait Stepper {
    /// A state at a grid time, at the stepper's precision.
    type State;
    /// The time of the current state, as f64.
    fn now(&self) -> f64;
    /// The Taylor coefficients of the step from the current state.
    unsafe fn coefficients(&mut self);
    /// The next step: Jorba–Zou's from the coefficients, or the fixed one; not finite when
    /// the coefficients all vanish (an equilibrium).
    unsafe fn step(&self) -> f64;
    /// The smallest step taken to the end of the run at an equilibrium.
    fn least_step(&self) -> f64;
    /// A step as it is taken (the lane stepper keeps every time an exact f64).
    fn rounded(&self, h: f64) -> f64;
    /// The Taylor polynomial of the step at time t (grid output).
    unsafe fn state_at(&mut self, t: f64) -> Self::State;
    /// The same rounded to f64 (dense output).
    unsafe fn state_at_f64(&mut self, t: f64) -> [f64; DIM];
    /// Whether a state is finite (a run stops with an error where it is not).
    fn is_finite(x: &Self::State) -> bool;
    /// The state and the time at the end of the step h: the polynomial at h, compensated.
    unsafe fn advance(&mut self, h: f64);
}

/// What a run gives: the states at the grid times or, with `dense` = `Some(k)`, the run's own
/// steps with k samples inside each (rounded to f64, the start left out).
pub(crate) struct Steps<S> {
    pub times: Vec<f64>,
    pub states: Vec<S>,
    pub steps: StepSamples,
    pub stats: Stats,
}

/// The stepping loop: per step the coefficients, the step h (an equilibrium steps to the end;
/// a step below 1e-15·|t| is an error), the samples inside [t, t + h], the update.
///
/// # Safety
/// The CPU has the features `stepper`'s code needs.
#[inline(always)]
pub(super) unsafe fn run_steps<S: Stepper>(
    stepper: &mut S,
    name: &'static str,
    order: usize,
    grid: &OutputGrid,
    dense: Option<usize>,
) -> Result<Steps<S::State>, DynamicsError> {
    let start = Instant::now();
    let mut stats = Stats::default();
    let mut times = Vec::with_capacity(grid.samples);
    let mut states = Vec::with_capacity(grid.samples);
    let mut steps = StepSamples::default();
    let mut next = 0;
    while next < grid.samples {
        if stats.accepted_steps >= MAX_STEPS {
            return Err(DynamicsError::Integration(format!(
                "{name}: more than {MAX_STEPS} steps before t = {}",
                grid.time(next)
            )));
        }
        stepper.coefficients();
        stats.accepted_steps += 1;
        stats.rhs_evals += order as u64 + 1;

        let t = stepper.now();
        let mut h = stepper.step();
        if !h.is_finite() {
            // All coefficients vanish (an equilibrium): one step to the end.
            h = (grid.t_end - t).max(stepper.least_step());
        }
        h = stepper.rounded(h);
        if h.is_nan() || h <= 1e-15 * t.abs() || h <= 0.0 {
            return Err(DynamicsError::Integration(format!(
                "{name}: step size {h:e} too small at t = {t} (singular solution?)"
            )));
        }

        if let Some(k) = dense {
            // The step's own samples, each at its f64 time.
            let (samples, last) = polynomial_step(t, h, grid.t_end, k);
            for (ts, end) in samples {
                let y = stepper.state_at_f64(ts);
                steps.push_step_sample(name, ts, y, end)?;
            }
            steps.check_size(name)?;
            if last {
                break;
            }
        }
        // Dense output at the grid times inside [t, t + h].
        let t_step_end = t + h;
        while dense.is_none() && next < grid.samples && grid.time(next) <= t_step_end {
            let tg = grid.time(next);
            let x = stepper.state_at(tg);
            if !S::is_finite(&x) {
                return Err(DynamicsError::Integration(format!(
                    "{name}: solution not finite at t = {tg}"
                )));
            }
            times.push(tg);
            states.push(x);
            next += 1;
        }
        if next == grid.samples {
            break;
        }
        stepper.advance(h);
    }
    stats.integration_seconds = start.elapsed().as_secs_f64();
    Ok(Steps {
        times,
        states,
        steps,
        stats,
    })
}
