//! Glue between the project's interface and the `ode_solvers` crate (f64 only).

use ode_solvers::{SVector, System};

use crate::equations::VectorField;
use crate::error::DynamicsError;
use crate::state::{State, DIM};

use super::{OutputGrid, Solution, Stats};

pub(super) type Vector9 = SVector<f64, DIM>;

/// The Euler–Poisson vector field as an `ode_solvers` system in the scaled time s = t/Δ, where
/// Δ is the spacing of the output grid: dy/ds = Δ·f(y). The grid times are then the integers
/// 0, 1, …, N−1, which `ode_solvers`' dense output (times accumulated as x₀ + dx + dx + …)
/// reaches exactly for any N up to 2⁵³ — in t the accumulated times drifted off the grid beyond
/// ~8000 samples ("no dense output at t"). It also stops the run at the first non-finite output.
pub(super) struct EulerPoissonSystem {
    pub field: VectorField<f64>,
    /// Δ: one unit of s in t.
    pub scale: f64,
    /// The scaled time of the first non-finite output or derivative, if any.
    pub non_finite_at: Option<f64>,
}

impl EulerPoissonSystem {
    pub fn new(field: VectorField<f64>, scale: f64) -> Self {
        Self {
            field,
            scale,
            non_finite_at: None,
        }
    }
}

impl System<f64, Vector9> for EulerPoissonSystem {
    fn system(&self, _s: f64, y: &Vector9, dy: &mut Vector9) {
        self.field.eval_into(y.as_slice(), dy.as_mut_slice());
        for d in dy.iter_mut() {
            *d *= self.scale;
        }
    }

    fn solout(&mut self, s: f64, y: &Vector9, dy: &Vector9) -> bool {
        if y.iter().chain(dy.iter()).all(|x| x.is_finite()) {
            return false;
        }
        self.non_finite_at.get_or_insert(s);
        true
    }
}

/// The error for a state that is not finite at grid time `t` (sample `k` of `n`).
pub(super) fn non_finite_at(method: &str, t: f64, k: usize, n: usize) -> DynamicsError {
    DynamicsError::Integration(format!(
        "{method}: the solution is not finite at t = {} (sample {k} of {n}); the tolerances or \
         the step are too loose for this motion, or it is singular",
        crate::short(t)
    ))
}

/// An `ode_solvers` failure with its scaled time converted back to t.
pub(super) fn solver_error(
    method: &str,
    e: ode_solvers::dop_shared::IntegrationError,
    scale: f64,
) -> DynamicsError {
    use ode_solvers::dop_shared::IntegrationError as E;
    let what = match e {
        E::MaxNumStepReached { x, n_step } => format!(
            "more than {} steps before t = {}",
            crate::short(f64::from(n_step)),
            crate::short(x * scale)
        ),
        E::StepSizeUnderflow { x } => format!(
            "step size underflow at t = {} (the tolerances cannot be met in f64 here, or the \
             solution is singular)",
            crate::short(x * scale)
        ),
        E::StiffnessDetected { x } => {
            format!(
                "the problem became stiff at t = {}",
                crate::short(x * scale)
            )
        }
    };
    DynamicsError::Integration(format!("{method}: {what}"))
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

/// Match the dense output of an `ode_solvers` run in the scaled time s = t/Δ (outputs at
/// s = 0, 1, 2, … exactly) to the grid: output k is grid time k, T·k/(N−1) (within one rounding
/// of k·Δ). Every state must be finite.
pub(super) fn collect_dense(
    method: &'static str,
    grid: &OutputGrid,
    xs: &[f64],
    ys: &[Vector9],
    stats: Stats,
) -> Result<Solution<f64>, DynamicsError> {
    let mut times = Vec::with_capacity(grid.samples);
    let mut states = Vec::with_capacity(grid.samples);
    for k in 0..grid.samples {
        let t = grid.time(k);
        match (xs.get(k), ys.get(k)) {
            (Some(&s), Some(y)) if s == k as f64 => {
                if y.iter().any(|x| !x.is_finite()) {
                    return Err(non_finite_at(method, t, k, grid.samples));
                }
                times.push(t);
                states.push(to_state(y));
            }
            _ => {
                return Err(DynamicsError::Integration(format!(
                    "{method}: no dense output at t = {} (sample {k} of {})",
                    crate::short(t),
                    grid.samples
                )))
            }
        }
    }
    Ok(Solution {
        method,
        times,
        states,
        stats,
    })
}

/// End of an `ode_solvers` dense-output run, in the scaled time s = t/Δ: slightly beyond the
/// last grid time s = N − 1.
///
/// `ode_solvers` 0.6 (Dopri5 and Dop853) pushes an output "at x_end" from *any* step after which
/// the next dense-output time is within 1e-9 of x_end, with θ = (x_end − x_old)/h_old > 1 when
/// that step ends before x_end: the last sample was an extrapolation, off by ~1e-4 at rtol 1e-12.
/// Ending a hair past N − 1 (never within 1e-9 of a grid time) makes every sample, T included, an
/// interpolation inside the step that contains it; the cost is one extra short step. Relative to
/// the spacing, so a tiny T (1e-300) does not integrate on to an absolute 1e-8 in steps of T.
pub(super) fn solver_end(grid: &OutputGrid) -> f64 {
    (grid.samples - 1) as f64 + 1e-6
}

/// A dense check must reach T with finite states (the solver stops at the first non-finite
/// state, see [`EulerPoissonSystem`]).
pub(super) fn check_reached(
    method: &str,
    out: &super::dense::StepSamples,
    grid: &OutputGrid,
) -> Result<(), DynamicsError> {
    let end = out.times.last().copied().unwrap_or(0.0);
    match out
        .states
        .iter()
        .position(|y| y.iter().any(|x| !x.is_finite()))
    {
        Some(i) => Err(non_finite_at(method, out.times[i], i, out.times.len())),
        None if end < grid.t_end * (1.0 - 1e-12) => Err(DynamicsError::Integration(format!(
            "{method}: the run stopped at t = {} before t-end (a state that is not finite)",
            crate::short(end)
        ))),
        None => Ok(()),
    }
}

/// Below this grid spacing the scaled field Δ·f(y) would lose digits to subnormal numbers; the
/// motion over such a time is y₀ + t·f(y₀) to within f64 rounding (the next term is ~t²).
pub(super) const TINY_SPACING: f64 = 1e-290;

/// The samples of a grid whose spacing is below [`TINY_SPACING`]: y₀ + t·f(y₀) (one evaluation).
pub(super) fn tiny_grid(
    method: &'static str,
    field: &VectorField<f64>,
    initial: &State<f64>,
    grid: &OutputGrid,
) -> Solution<f64> {
    let y0 = initial.to_array();
    let f0 = field.eval(&y0);
    let times = grid.times();
    let states = times
        .iter()
        .map(|&t| State::from_slice(&std::array::from_fn::<f64, DIM, _>(|i| y0[i] + t * f0[i])))
        .collect();
    Solution {
        method,
        times,
        states,
        stats: Stats {
            rhs_evals: 1,
            ..Stats::default()
        },
    }
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

            /// The `ode_solvers` solver of a run on `grid` in the scaled time s = t/Δ (Δ the
            /// grid spacing), its output `out` every `dx` (in s): the one set-up of every run
            /// of this method, so two runs with different outputs take the same steps.
            pub(super) fn solver(
                &self,
                field: $crate::equations::VectorField<f64>,
                initial: &$crate::state::State<f64>,
                grid: &$crate::integrators::OutputGrid,
                dx: f64,
                out: ode_solvers::OutputType,
            ) -> $solver {
                use $crate::integrators::ode_solvers_adapter as adapter;
                <$solver>::from_param(
                    adapter::EulerPoissonSystem::new(field, grid.spacing()),
                    0.0,
                    adapter::solver_end(grid),
                    dx,
                    adapter::to_vector(initial),
                    self.tolerances.rtol,
                    self.tolerances.atol,
                    0.9,
                    $beta,
                    $fac_min,
                    $fac_max,
                    (grid.samples - 1) as f64,
                    0.0,
                    $crate::integrators::MAX_STEPS as u32,
                    1000,
                    out,
                )
            }

            /// `n` equal steps over s ∈ [0, 1] of `system` from `y0`, the step-size control
            /// off (see [`super::fixed_step`]): the state at s = 1 and the counts.
            pub(super) fn fixed_interval(
                system: $crate::integrators::ode_solvers_adapter::EulerPoissonSystem,
                y0: $crate::integrators::ode_solvers_adapter::Vector9,
                n: u32,
            ) -> Result<
                ($crate::integrators::ode_solvers_adapter::Vector9, ode_solvers::dop_shared::Stats),
                ode_solvers::dop_shared::IntegrationError,
            > {
                use $crate::integrators::ode_solvers_adapter as adapter;
                let h = 1.0 / f64::from(n);
                let mut solver = <$solver>::from_param(
                    system,
                    0.0,
                    1.0,
                    1.0,
                    y0,
                    0.0,
                    adapter::FIXED_ATOL,
                    1.0,
                    $beta,
                    1.0,
                    1.0,
                    h,
                    h,
                    n + adapter::FIXED_SPARE_STEPS,
                    u32::MAX,
                    ode_solvers::OutputType::Sparse,
                );
                let stats = solver.integrate()?;
                let y = solver.y_out().last().cloned().unwrap_or(y0);
                Ok((y, stats))
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
                let field = $crate::equations::VectorField::new(&problem.fields);
                let scale = grid.spacing();
                if scale < adapter::TINY_SPACING {
                    return Ok(adapter::tiny_grid(Self::NAME, &field, &problem.initial, grid));
                }
                let mut solver = self.solver(
                    field,
                    &problem.initial,
                    grid,
                    1.0,
                    ode_solvers::OutputType::Dense,
                );
                let start = std::time::Instant::now();
                let stats = solver
                    .integrate()
                    .map_err(|e| adapter::solver_error(Self::NAME, e, scale))?;
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

/// The absolute tolerance of a fixed-step run: so large that the error estimate is always
/// ≪ 1, so every step is accepted; with fac_min = fac_max = 1 the next step equals the last.
pub(super) const FIXED_ATOL: f64 = 1e300;
/// Attempts beyond the n steps of a fixed-step interval before giving up (a NaN estimate is
/// rejected forever with the same step: this stops it).
pub(super) const FIXED_SPARE_STEPS: u32 = 4;
