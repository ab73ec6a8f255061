//! Dormand–Prince 8(5,3) with dense output of order 7 (Hairer, Nørsett, Wanner, *Solving ODE I*,
//! sec. II.10), from `ode_solvers`.

use super::ode_solvers_adapter::dormand_prince_method;

dormand_prince_method! {
    /// Dormand–Prince 8(5,3).
    Dop853, ode_solvers::Dop853<f64, super::ode_solvers_adapter::Vector9, super::ode_solvers_adapter::EulerPoissonSystem>, name = "dop853", order = 8,
    beta = 0.0, fac_min = 0.333, fac_max = 6.0
}

use super::dense::{begin, too_many, StepSamples, MAX_DENSE_SAMPLES};
use super::ode_solvers_adapter as adapter;
use super::{OutputGrid, Problem};
use crate::equations::VectorField;
use crate::error::DynamicsError;

impl Dop853 {
    /// The run of [`super::Propagator::propagate_grid`] on `grid` (the same steps), as its own
    /// steps with its dense output (order 7) inside them ([`super::dense`]). `ode_solvers`
    /// evaluates that output only every dx of an even grid, so the run is made twice with the
    /// same steps: once for the step ends, once with an even grid of about `k` points per step
    /// (dx a power of two in the scaled time, so the grid accumulates exactly).
    pub fn propagate_steps(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
        k: usize,
    ) -> Result<StepSamples, DynamicsError> {
        let (mut out, scale) = begin(k, problem.initial.to_array(), grid)?;
        let Some(scale) = scale else {
            return Ok(out);
        };
        let field = VectorField::new(&problem.fields);
        let fail = |e| adapter::solver_error(Self::NAME, e, scale);
        let sparse = ode_solvers::OutputType::Sparse;
        let mut ends = self.solver(field.clone(), &problem.initial, grid, 1.0, sparse);
        let end_stats = ends.integrate().map_err(fail)?;
        let steps = end_stats.accepted_steps as usize;
        if steps.saturating_mul(k + 1) > MAX_DENSE_SAMPLES {
            return Err(too_many(Self::NAME, steps.saturating_mul(k + 1)));
        }
        // Points per unit of s: the power of two nearest k steps per unit.
        let per_unit = (k as f64 * steps as f64 / (grid.samples - 1) as f64).max(1.0);
        let dx = 2f64.powi(-(per_unit.log2().round() as i32));
        let dense = ode_solvers::OutputType::Dense;
        let mut inside = self.solver(field, &problem.initial, grid, dx, dense);
        let inside_stats = inside.integrate().map_err(fail)?;
        if inside_stats.accepted_steps != end_stats.accepted_steps {
            return Err(DynamicsError::Integration(format!(
                "{}: the run with dense output took {} steps, the run without {}",
                Self::NAME,
                inside_stats.accepted_steps,
                end_stats.accepted_steps
            )));
        }
        let (xs, ys) = (inside.x_out(), inside.y_out());
        let mut j = 0;
        let mut s0 = 0.0;
        for (&s1, y1) in ends.x_out().iter().zip(ends.y_out()) {
            if s1 <= s0 {
                continue;
            }
            while j < xs.len() && xs[j] < s1 {
                if xs[j] > s0 {
                    out.push(xs[j] * scale, adapter::to_state(&ys[j]).to_array(), false);
                }
                j += 1;
            }
            out.push(s1 * scale, adapter::to_state(y1).to_array(), true);
            out.step_times.push(s1 * scale);
            s0 = s1;
        }
        out.check_size(Self::NAME)?;
        adapter::check_reached(Self::NAME, &out, grid)?;
        Ok(out)
    }
}
