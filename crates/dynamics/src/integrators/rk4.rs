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
            // ode_solvers takes ceil((t1 − t0)/h) steps: make sure that is `per_interval` (a
            // rounded-down h gave one step too many, ending past t1 by h).
            let mut h = (t1 - t0) / per_interval;
            while ((t1 - t0) / h).ceil() > per_interval {
                h = f64::from_bits(h.to_bits() + 1);
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fields::Fields;
    use crate::state::State;

    /// Every grid interval takes exactly the steps it needs: with step 1e-3 and spacing 0.1,
    /// 0.1/1e-3 rounds to 100.00000000000001 and a rounded-down step used to add a 101st step
    /// (ending 1e-3 past the sample: an error of 1e-3 instead of 1e-13).
    #[test]
    fn each_interval_ends_on_its_grid_time() {
        let problem = Problem {
            fields: Fields::new(1.0, 0.5).unwrap(),
            initial: State {
                omega: [0.3, -0.2, 0.5],
                alpha: [1.0, 0.0, 0.0],
                beta: [0.0, 1.0, 0.0],
            },
        };
        let grid = OutputGrid::new(2.0, 21).unwrap();
        let sol = Rk4::new(1e-3).propagate_grid(&problem, &grid).unwrap();
        assert!((2000..=2020).contains(&sol.stats.accepted_steps));
        let fine = Rk4::new(2.5e-4).propagate_grid(&problem, &grid).unwrap();
        let last = |s: &Solution<f64>| s.states.last().unwrap().to_array();
        let diff = last(&sol)
            .iter()
            .zip(last(&fine).iter())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(diff < 1e-10, "rk4 at 1e-3 vs 2.5e-4 differ by {diff:e}");
    }
}
