//! The classical fourth-order Runge–Kutta method with a fixed step.
//!
//! Each interval between two grid times is covered by a whole number of equal steps, so the grid
//! is hit exactly. Without a given step, the step comes from the tolerance: the local error of
//! RK4 is ~ h⁵, so h = rtol^(1/4) (error per unit time ~ h⁴ = rtol), capped at 0.01.
//!
//! The stepping loop keeps only the current state and the four stages: memory is bounded by the
//! number of samples, whatever the number of steps (`ode_solvers::Rk4` stored every step). The
//! step count is known in advance and checked against [`super::MAX_STEPS`] before any work.

use std::time::Instant;

use crate::equations::VectorField;
use crate::error::DynamicsError;
use crate::state::{State, DIM};

use super::dense::{begin, hermite, interior_times, too_many, StepSamples, MAX_DENSE_SAMPLES};
use super::ode_solvers_adapter::{initial_only, non_finite_at};
use super::{OutputGrid, Problem, Propagator, Solution, Stats, Tolerances, MAX_STEPS};

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

    /// Steps per grid interval (at least 1).
    fn per_interval(&self, grid: &OutputGrid) -> f64 {
        (grid.spacing() / self.step).ceil().max(1.0)
    }

    /// The exact number of steps of a run on `grid`.
    pub fn steps_for(&self, grid: &OutputGrid) -> f64 {
        if grid.samples <= 1 || grid.t_end == 0.0 {
            0.0
        } else {
            self.per_interval(grid) * (grid.samples - 1) as f64
        }
    }
}

/// y + h·k, component by component.
fn axpy(y: &[f64; DIM], h: f64, k: &[f64; DIM]) -> [f64; DIM] {
    std::array::from_fn(|i| y[i] + h * k[i])
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
        let steps = self.steps_for(grid);
        if steps > MAX_STEPS as f64 {
            return Err(DynamicsError::Settings(format!(
                "rk4 with step {} over t-end {} takes {} steps, more than the limit of {}; \
                 use a larger step (rk4's default step is rtol^(1/4))",
                crate::short(self.step),
                crate::short(grid.t_end),
                crate::short(steps),
                crate::short(MAX_STEPS as f64)
            )));
        }
        let n = self.per_interval(grid) as u64;
        let field = VectorField::new(&problem.fields);
        let mut y = problem.initial.to_array();
        let mut times = Vec::with_capacity(grid.samples);
        let mut states = Vec::with_capacity(grid.samples);
        times.push(0.0);
        states.push(problem.initial.clone());
        let mut stats = Stats::default();
        let (mut k1, mut k2, mut k3, mut k4) = ([0.0; DIM], [0.0; DIM], [0.0; DIM], [0.0; DIM]);
        let start = Instant::now();
        for k in 1..grid.samples {
            let (t0, t1) = (grid.time(k - 1), grid.time(k));
            let h = (t1 - t0) / n as f64;
            for _ in 0..n {
                field.eval_into(&y, &mut k1);
                field.eval_into(&axpy(&y, 0.5 * h, &k1), &mut k2);
                field.eval_into(&axpy(&y, 0.5 * h, &k2), &mut k3);
                field.eval_into(&axpy(&y, h, &k3), &mut k4);
                for i in 0..DIM {
                    y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
                }
            }
            stats.accepted_steps += n;
            stats.rhs_evals += Self::STAGES * n;
            if y.iter().any(|x| !x.is_finite()) {
                return Err(non_finite_at(Self::NAME, t1, k, grid.samples));
            }
            times.push(t1);
            states.push(State::from_slice(&y));
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

impl Rk4 {
    /// The run of [`Propagator::propagate_grid`] on `grid`, as its own steps with `k` samples of
    /// the cubic Hermite interpolant inside each ([`super::dense`]; one more evaluation of the
    /// field per step, at its end — the next step's first stage).
    pub fn propagate_steps(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
        k: usize,
    ) -> Result<StepSamples, DynamicsError> {
        let (mut out, scale) = begin(k, problem.initial.to_array(), grid)?;
        if scale.is_none() {
            return Ok(out);
        }
        let total = self.steps_for(grid) * (k + 1) as f64;
        if total > MAX_DENSE_SAMPLES as f64 {
            return Err(too_many(Self::NAME, total as usize));
        }
        let n = self.per_interval(grid) as u64;
        let field = VectorField::new(&problem.fields);
        let mut y = problem.initial.to_array();
        let mut f = field.eval(&y);
        let (mut k2, mut k3, mut k4) = ([0.0; DIM], [0.0; DIM], [0.0; DIM]);
        for s in 1..grid.samples {
            let (t0, t1) = (grid.time(s - 1), grid.time(s));
            let h = (t1 - t0) / n as f64;
            for j in 0..n {
                field.eval_into(&axpy(&y, 0.5 * h, &f), &mut k2);
                field.eval_into(&axpy(&y, 0.5 * h, &k2), &mut k3);
                field.eval_into(&axpy(&y, h, &k3), &mut k4);
                let next: [f64; DIM] = std::array::from_fn(|i| {
                    y[i] + h / 6.0 * (f[i] + 2.0 * (k2[i] + k3[i]) + k4[i])
                });
                let f_next = field.eval(&next);
                if next.iter().any(|x| !x.is_finite()) {
                    return Err(non_finite_at(Self::NAME, t1, s, grid.samples));
                }
                let (a, b) = (
                    t0 + j as f64 * h,
                    if j + 1 == n {
                        t1
                    } else {
                        t0 + (j + 1) as f64 * h
                    },
                );
                for (i, t) in interior_times(a, b, k).enumerate() {
                    let theta = (i + 1) as f64 / (k + 1) as f64;
                    out.push(t, hermite(theta, b - a, (&y, &f), (&next, &f_next)), false);
                }
                out.push(b, next, true);
                out.step_times.push(b);
                (y, f) = (next, f_next);
            }
        }
        Ok(out)
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
