//! Dormand–Prince 5(4) and 8(5,3) of `ode_solvers` at a fixed step, for convergence studies
//! (`rsts convergence`): the observed order of the method itself, not of its step control.
//!
//! `ode_solvers` has no fixed-step mode, but its controller can be switched off: with
//! fac_min = fac_max = 1 the next step is always the last one (h_new = h/fac, fac clamped to
//! [1/fac_max, 1/fac_min] = {1}), h_max = h, and with atol = 1e300 (rtol = 0) the error estimate
//! is ≪ 1, so every step is accepted. Stiffness detection is off. Each interval between two
//! grid times is one run of n = ⌈Δ/h⌉ equal steps (in the scaled time s = t/Δ of
//! [`super::ode_solvers_adapter`], steps of 1/n), so every sample is the end of a step — no dense
//! output, whose order is lower than the method's. Each interval starts afresh (one evaluation
//! more for the first stage, counted).

use std::time::Instant;

use crate::equations::VectorField;
use crate::error::DynamicsError;

use super::ode_solvers_adapter::{
    initial_only, non_finite_at, solver_error, tiny_grid, to_state, to_vector, EulerPoissonSystem,
    FIXED_SPARE_STEPS, TINY_SPACING,
};
use super::{Dop853, Dopri5, OutputGrid, Problem, Propagator, Solution, Stats, MAX_STEPS};

/// Which Dormand–Prince method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DormandPrince {
    Dopri5,
    Dop853,
}

impl DormandPrince {
    pub fn name(&self) -> &'static str {
        match self {
            DormandPrince::Dopri5 => Dopri5::NAME,
            DormandPrince::Dop853 => Dop853::NAME,
        }
    }

    /// The order of the step (5 and 8).
    pub fn order(&self) -> u32 {
        match self {
            DormandPrince::Dopri5 => Dopri5::ORDER,
            DormandPrince::Dop853 => Dop853::ORDER,
        }
    }
}

/// A Dormand–Prince method at a fixed step (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct FixedStepDormandPrince {
    pub method: DormandPrince,
    /// Largest step; each grid interval Δ is cut into ⌈Δ/step⌉ equal steps.
    pub step: f64,
}

impl FixedStepDormandPrince {
    /// Checked: a positive finite step.
    pub fn new(method: DormandPrince, step: f64) -> Result<Self, DynamicsError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(DynamicsError::Settings(format!(
                "step must be a positive finite number, got {}",
                crate::short(step)
            )));
        }
        Ok(Self { method, step })
    }
}

impl Propagator<f64> for FixedStepDormandPrince {
    fn name(&self) -> &'static str {
        self.method.name()
    }

    fn propagate_grid(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
    ) -> Result<Solution<f64>, DynamicsError> {
        let name = self.method.name();
        if grid.samples <= 1 || grid.t_end == 0.0 {
            return Ok(initial_only(name, &problem.initial));
        }
        let field = VectorField::new(&problem.fields);
        let spacing = grid.spacing();
        if spacing < TINY_SPACING {
            return Ok(tiny_grid(name, &field, &problem.initial, grid));
        }
        let n = (spacing / self.step).ceil().max(1.0);
        let total = n * (grid.samples - 1) as f64;
        if total > MAX_STEPS as f64 || n > f64::from(u32::MAX - FIXED_SPARE_STEPS) {
            return Err(DynamicsError::Settings(format!(
                "{name} with step {} over t-end {} takes {} steps, more than the limit of {}",
                crate::short(self.step),
                crate::short(grid.t_end),
                crate::short(total),
                crate::short(MAX_STEPS as f64)
            )));
        }
        let n = n as u32;
        let start = Instant::now();
        let mut y = to_vector(&problem.initial);
        let mut stats = Stats::default();
        let mut times = vec![0.0];
        let mut states = vec![problem.initial.clone()];
        for k in 1..grid.samples {
            let system = EulerPoissonSystem::new(field.clone(), spacing);
            let (next, s) = match self.method {
                DormandPrince::Dopri5 => Dopri5::fixed_interval(system, y, n),
                DormandPrince::Dop853 => Dop853::fixed_interval(system, y, n),
            }
            .map_err(|e| solver_error(name, e, spacing))?;
            if s.accepted_steps != n || s.rejected_steps != 0 {
                return Err(DynamicsError::Integration(format!(
                    "{name}: a fixed-step interval took {} accepted and {} rejected steps, not {n}",
                    s.accepted_steps, s.rejected_steps
                )));
            }
            if next.iter().any(|x| !x.is_finite()) {
                return Err(non_finite_at(name, grid.time(k), k, grid.samples));
            }
            stats.accepted_steps += u64::from(s.accepted_steps);
            stats.rhs_evals += u64::from(s.num_eval);
            times.push(grid.time(k));
            states.push(to_state(&next));
            y = next;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{Rk4, Tolerances};
    use crate::{Fields, State};

    fn problem() -> Problem<f64> {
        Problem {
            fields: Fields::new(1.0, 0.5).unwrap(),
            initial: State {
                omega: [0.3, -0.2, 0.5],
                alpha: [1.0, 0.0, 0.0],
                beta: [0.0, 1.0, 0.0],
            },
        }
    }

    fn error_at(method: DormandPrince, step: f64, truth: &State<f64>) -> (f64, Stats) {
        let grid = OutputGrid::new(2.0, 3).unwrap();
        let sol = FixedStepDormandPrince::new(method, step)
            .unwrap()
            .propagate_grid(&problem(), &grid)
            .unwrap();
        let last = sol.states.last().unwrap().to_array();
        let e = last
            .iter()
            .zip(truth.to_array().iter())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        (e, sol.stats)
    }

    /// Every step is accepted at the step asked (n per interval, none rejected), and halving
    /// the step divides the error by about 2^order (5 and 8): the step control is really off.
    /// (With the control on, the error would not follow the step.)
    #[test]
    fn the_step_is_fixed_and_the_error_falls_like_the_order() {
        let truth = Dop853::new(Tolerances::new(1e-15, 1e-15).unwrap())
            .propagate_grid(&problem(), &OutputGrid::new(2.0, 3).unwrap())
            .unwrap()
            .states[2]
            .clone();
        for (method, h, floor) in [
            (DormandPrince::Dopri5, 0.1, 1e-13),
            (DormandPrince::Dop853, 0.5, 1e-12),
        ] {
            let (e1, s1) = error_at(method, h, &truth);
            let (e2, s2) = error_at(method, h / 2.0, &truth);
            let n = (1.0 / h).ceil() as u64;
            assert_eq!(s1.accepted_steps, 2 * n, "{method:?}");
            assert_eq!(s2.accepted_steps, 4 * n, "{method:?}");
            assert_eq!(s1.rejected_steps + s2.rejected_steps, 0);
            assert!(e2 > floor, "{method:?}: {e2:e} is in the floor");
            let slope = (e1 / e2).log2();
            let p = f64::from(method.order());
            assert!(
                (slope - p).abs() < 0.6,
                "{method:?}: observed {slope} against {p} ({e1:e}, {e2:e})"
            );
        }
        assert!(FixedStepDormandPrince::new(DormandPrince::Dopri5, 0.0).is_err());
        // The same grid hit by rk4 at the same step: steps counted alike.
        let rk = Rk4::new(0.1)
            .propagate_grid(&problem(), &OutputGrid::new(2.0, 3).unwrap())
            .unwrap();
        assert_eq!(rk.stats.accepted_steps, 20);
    }
}
