//! Glue between the project's interface and the `ode_solvers` crate (f64 only).

use ode_solvers::{SVector, System};

use crate::equations::VectorField;
use crate::error::DynamicsError;
use crate::state::{State, DIM};

use super::{OutputGrid, Solution, Stats};

pub(super) type Vector9 = SVector<f64, DIM>;

/// The Euler–Poisson vector field as an `ode_solvers` system.
pub(super) struct EulerPoissonSystem(pub VectorField<f64>);

impl System<f64, Vector9> for EulerPoissonSystem {
    fn system(&self, _t: f64, y: &Vector9, dy: &mut Vector9) {
        self.0.eval_into(y.as_slice(), dy.as_mut_slice());
    }
}

pub(super) fn to_vector(s: &State<f64>) -> Vector9 {
    Vector9::from_column_slice(&s.to_array())
}

pub(super) fn to_state(v: &Vector9) -> State<f64> {
    State::from_slice(v.as_slice())
}

pub(super) fn convert_stats(s: ode_solvers::dop_shared::Stats, seconds: f64) -> Stats {
    Stats {
        accepted_steps: u64::from(s.accepted_steps),
        rejected_steps: u64::from(s.rejected_steps),
        rhs_evals: u64::from(s.num_eval),
        integration_seconds: seconds,
    }
}

/// Match the dense output of an `ode_solvers` run (times accumulated as x₀ + dx + dx + …) to the
/// grid: every grid time must have an output point within a relative 1e-9 of the spacing.
/// The reported time is the one at which the solver evaluated its interpolant.
pub(super) fn collect_dense(
    method: &'static str,
    grid: &OutputGrid,
    xs: &[f64],
    ys: &[Vector9],
    stats: Stats,
) -> Result<Solution<f64>, DynamicsError> {
    let dx = grid.spacing();
    let tol = 1e-9 * dx.max(f64::MIN_POSITIVE);
    let mut times = Vec::with_capacity(grid.samples);
    let mut states = Vec::with_capacity(grid.samples);
    let mut j = 0;
    for k in 0..grid.samples {
        let t = grid.time(k);
        while j < xs.len() && xs[j] < t - tol {
            j += 1;
        }
        if j >= xs.len() || (xs[j] - t).abs() > tol {
            return Err(DynamicsError::Integration(format!(
                "{method}: no dense output at t = {t} (sample {k} of {})",
                grid.samples
            )));
        }
        times.push(xs[j]);
        states.push(to_state(&ys[j]));
        j += 1;
    }
    Ok(Solution {
        method,
        times,
        states,
        stats,
    })
}

/// End time to give an `ode_solvers` dense-output run: slightly beyond the last grid time.
///
/// `ode_solvers` 0.6 (Dopri5 and Dop853) pushes an output "at x_end" from *any* step after which
/// the next dense-output time is within 1e-9 of x_end, with θ = (x_end − x_old)/h_old > 1 when
/// that step ends before x_end: the last sample was an extrapolation, off by ~1e-4 at rtol 1e-12.
/// Ending a hair past T (never within 1e-9 of a grid time) makes every sample, T included, an
/// interpolation inside the step that contains it; the cost is one extra short step.
pub(super) fn solver_end(grid: &OutputGrid) -> f64 {
    grid.t_end + 1e-6 * grid.spacing() + 1e-8
}

/// Solution of a grid with a single sample: the initial state, no work.
pub(super) fn initial_only(method: &'static str, initial: &State<f64>) -> Solution<f64> {
    Solution {
        method,
        times: vec![0.0],
        states: vec![initial.clone()],
        stats: Stats::default(),
    }
}

/// Maximum number of steps allowed in one run (ode_solvers' default of 1e5 is too few for
/// long validation runs at tight tolerances).
pub(super) const MAX_STEPS: u32 = 200_000_000;

/// Defines an adaptive Dormand–Prince method of `ode_solvers` as a project method: a type with
/// its name and order as associated constants, configured by [`super::Tolerances`], implementing
/// [`super::Propagator`] with dense output at the grid times. The step-size controller constants
/// (PI parameter β, bounds of the step ratio) are those `ode_solvers` uses by default for it.
macro_rules! dormand_prince_method {
    ($(#[$doc:meta])* $ty:ident, $solver:path, name = $name:literal, order = $order:literal,
     beta = $beta:literal, fac_min = $fac_min:literal, fac_max = $fac_max:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $ty {
            pub tolerances: $crate::integrators::Tolerances,
        }

        impl $ty {
            pub const NAME: &'static str = $name;
            pub const ORDER: u32 = $order;

            pub fn new(tolerances: $crate::integrators::Tolerances) -> Self {
                Self { tolerances }
            }
        }

        impl $crate::integrators::Propagator<f64> for $ty {
            fn name(&self) -> &'static str {
                Self::NAME
            }

            fn propagate_grid(
                &self,
                problem: &$crate::integrators::Problem<f64>,
                grid: &$crate::integrators::OutputGrid,
            ) -> Result<$crate::integrators::Solution<f64>, $crate::error::DynamicsError> {
                use $crate::integrators::ode_solvers_adapter as adapter;
                if grid.samples <= 1 || grid.t_end == 0.0 {
                    return Ok(adapter::initial_only(Self::NAME, &problem.initial));
                }
                let mut solver = <$solver>::from_param(
                    adapter::EulerPoissonSystem($crate::equations::VectorField::new(&problem.fields)),
                    0.0,
                    adapter::solver_end(grid),
                    grid.spacing(),
                    adapter::to_vector(&problem.initial),
                    self.tolerances.rtol,
                    self.tolerances.atol,
                    0.9,
                    $beta,
                    $fac_min,
                    $fac_max,
                    grid.t_end,
                    0.0,
                    adapter::MAX_STEPS,
                    1000,
                    ode_solvers::OutputType::Dense,
                );
                let start = std::time::Instant::now();
                let stats = solver.integrate().map_err(|e| {
                    $crate::error::DynamicsError::Integration(format!("{}: {e}", Self::NAME))
                })?;
                let seconds = start.elapsed().as_secs_f64();
                adapter::collect_dense(
                    Self::NAME,
                    grid,
                    solver.x_out(),
                    solver.y_out(),
                    adapter::convert_stats(stats, seconds),
                )
            }
        }
    };
}
pub(super) use dormand_prince_method;
