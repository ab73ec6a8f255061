//! Dormand–Prince 5(4) with dense output of order 4 (Hairer, Nørsett, Wanner, *Solving ODE I*,
//! sec. II.5), from `ode_solvers`.

use super::ode_solvers_adapter::dormand_prince_method;

dormand_prince_method! {
    /// Dormand–Prince 5(4).
    Dopri5, ode_solvers::Dopri5<f64, super::ode_solvers_adapter::Vector9, super::ode_solvers_adapter::EulerPoissonSystem>, name = "dopri5", order = 5,
    beta = 0.04, fac_min = 0.2, fac_max = 10.0
}

use ode_solvers::continuous_output_model::ContinuousOutputModel;

use super::dense::{begin, interior_times, StepSamples};
use super::ode_solvers_adapter::{self as adapter, Vector9};
use super::{OutputGrid, Problem};
use crate::equations::VectorField;
use crate::error::DynamicsError;

impl Dopri5 {
    /// The run of [`super::Propagator::propagate_grid`] on `grid` (the same steps), as its own
    /// steps with `k` samples of its continuous extension (order 4) inside each
    /// ([`super::dense`]).
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
        let mut solver = self.solver(
            field,
            &problem.initial,
            grid,
            1.0,
            ode_solvers::OutputType::Continuous,
        );
        let mut model = ContinuousOutputModel::<f64, Vector9>::new();
        solver
            .integrate_with_continuous_output_model(&mut model)
            .map_err(|e| adapter::solver_error(Self::NAME, e, scale))?;
        let mut s0 = 0.0;
        for (&s1, y1) in solver.x_out().iter().zip(solver.y_out()) {
            if s1 <= s0 {
                continue;
            }
            for t in interior_times(s0, s1, k) {
                let y = model.evaluate(t).ok_or_else(|| {
                    DynamicsError::Integration(format!(
                        "{}: no continuous output at t = {}",
                        Self::NAME,
                        crate::short(t * scale)
                    ))
                })?;
                out.push(t * scale, adapter::to_state(&y).to_array(), false);
            }
            out.push(s1 * scale, adapter::to_state(y1).to_array(), true);
            out.step_times.push(s1 * scale);
            out.check_size(Self::NAME)?;
            s0 = s1;
        }
        adapter::check_reached(Self::NAME, &out, grid)?;
        Ok(out)
    }
}
