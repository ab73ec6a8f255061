//! Dormand–Prince 8(5,3) with dense output of order 7 (Hairer, Nørsett, Wanner, *Solving ODE I*,
//! sec. II.10), from `ode_solvers`.

use std::time::Instant;

use ode_solvers::OutputType;

use crate::equations::VectorField;
use crate::error::DynamicsError;

use super::ode_solvers_adapter::{
    collect_dense, convert_stats, initial_only, solver_end, to_vector, EulerPoissonSystem,
    MAX_STEPS,
};
use super::{OutputGrid, Problem, Propagator, Solution, Tolerances};

/// Dormand–Prince 8(5,3).
#[derive(Clone, Copy, Debug)]
pub struct Dop853 {
    pub tolerances: Tolerances,
}

impl Dop853 {
    pub const NAME: &'static str = "dop853";
    pub const ORDER: u32 = 8;

    pub fn new(tolerances: Tolerances) -> Self {
        Self { tolerances }
    }
}

impl Propagator<f64> for Dop853 {
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
        let mut solver = ode_solvers::Dop853::from_param(
            EulerPoissonSystem(VectorField::new(&problem.fields)),
            0.0,
            solver_end(grid),
            grid.spacing(),
            to_vector(&problem.initial),
            self.tolerances.rtol,
            self.tolerances.atol,
            0.9,
            0.0,
            0.333,
            6.0,
            grid.t_end,
            0.0,
            MAX_STEPS,
            1000,
            OutputType::Dense,
        );
        let start = Instant::now();
        let stats = solver
            .integrate()
            .map_err(|e| DynamicsError::Integration(format!("{}: {e}", Self::NAME)))?;
        let seconds = start.elapsed().as_secs_f64();
        collect_dense(
            Self::NAME,
            grid,
            solver.x_out(),
            solver.y_out(),
            convert_stats(stats, seconds),
        )
    }
}
