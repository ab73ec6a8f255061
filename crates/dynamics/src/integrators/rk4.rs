//! The classical fourth-order Runge–Kutta method with a fixed step, from `ode_solvers`.
//!
//! Each interval between two grid times is covered by a whole number of equal steps, so the grid
//! is hit exactly. Without a given step, the step comes from the tolerance: the local error of
//! RK4 is ~ h⁵, so h = rtol^(1/4) (error per unit time ~ h⁴ = rtol), capped at 0.01.

use std::time::Instant;

use crate::equations::VectorField;
use crate::error::DynamicsError;

use super::ode_solvers_adapter::{
    convert_stats, initial_only, to_state, to_vector, EulerPoissonSystem,
};
use super::{OutputGrid, Problem, Propagator, Solution, Stats, Tolerances};

/// Classical RK4 with fixed step `step`.
#[derive(Clone, Copy, Debug)]
pub struct Rk4 {
    pub step: f64,
}

impl Rk4 {
    pub const NAME: &'static str = "rk4";
    pub const ORDER: u32 = 4;
    /// Right-hand-side evaluations per step.
    pub const STAGES: u64 = 4;

    pub fn new(step: f64) -> Self {
        Self { step }
    }

    /// A step from the tolerance when none is given (see the module doc).
    pub fn from_tolerances(tol: Tolerances, step: Option<f64>) -> Self {
        Self::new(step.unwrap_or_else(|| tol.rtol.powf(0.25).min(0.01)))
    }
}

impl Propagator<f64> for Rk4 {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn propagate_grid(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
    ) -> Result<Solution<f64>, DynamicsError> {
        if grid.samples <= 1 || grid.t_end == 0.0 {
            return Ok(initial_only(Self::NAME, &problem.initial));
        }
        let dx = grid.spacing();
        let per_interval = (dx / self.step).ceil().max(1.0);
        if per_interval * (grid.samples as f64) > 1e10 {
            return Err(DynamicsError::Settings(format!(
                "rk4 step {} is too small for t-end {} ({} steps)",
                self.step,
                grid.t_end,
                per_interval * grid.samples as f64
            )));
        }
        let field = VectorField::new(&problem.fields);
        let mut y = to_vector(&problem.initial);
        let mut times = vec![0.0];
        let mut states = vec![problem.initial.clone()];
        let mut stats = Stats::default();
        let start = Instant::now();
        for k in 1..grid.samples {
            let (t0, t1) = (grid.time(k - 1), grid.time(k));
            let h = (t1 - t0) / per_interval;
            let mut solver = ode_solvers::Rk4::new(EulerPoissonSystem(field.clone()), t0, y, t1, h);
            let s = solver
                .integrate()
                .map_err(|e| DynamicsError::Integration(format!("{}: {e}", Self::NAME)))?;
            let s = convert_stats(s, 0.0);
            stats.accepted_steps += s.accepted_steps;
            stats.rhs_evals += s.rhs_evals;
            y = *solver
                .y_out()
                .last()
                .expect("rk4 returns at least the initial point");
            times.push(t1);
            states.push(to_state(&y));
        }
        stats.integration_seconds = start.elapsed().as_secs_f64();
        Ok(Solution {
            method: Self::NAME,
            times,
            states,
            stats,
        })
    }
}
