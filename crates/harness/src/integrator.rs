//! Producing a trajectory: anything that integrates the Euler–Poisson equations from a state is an
//! [`Integrator`] — a built-in [`MethodConfig`], a user's type implementing the dynamics crate's
//! [`Propagator`] (wrapped in [`Propagated`]), or an external process (`rsts-external`'s `Exec`).
//! The harness analyses what they produce the same way (see [`crate::analysis`]).

use rug::Float;

use rsts_dynamics::integrators::{
    map_problem, MethodConfig, OutputGrid, Problem, Propagator, Solution, Stats, Tolerances,
};
use rsts_dynamics::scalar::F64_BITS;
use rsts_dynamics::State;

use crate::HarnessError;

/// What an integrator produced: states at sample times, and what it cost.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// Sample times relative to the start (`times[0]` = 0 is the time of the initial state), as
    /// the integrator reports them (a dense output may report a time a hair off the one asked).
    pub times: Vec<f64>,
    /// The states, at the precision of the problem's initial state.
    pub states: Vec<State<Float>>,
    /// Steps, evaluations and the integrator's own time (zeros where it does not say).
    pub stats: Stats,
    /// Wall time measured around the integrator from outside (an external process: start-up,
    /// request and answer included); `None` for in-process integrators.
    pub wall_seconds: Option<f64>,
}

impl Trajectory {
    /// The states of a dynamics-crate [`Solution`] widened to `bits`.
    pub fn from_solution_f64(solution: Solution<f64>, bits: u32) -> Self {
        Self {
            times: solution.times,
            states: solution
                .states
                .iter()
                .map(|s| s.map(|x| Float::with_val(bits, *x)))
                .collect(),
            stats: solution.stats,
            wall_seconds: None,
        }
    }
}

/// An integrator as the harness sees it: a name, the settings a report shows, the precision the
/// reference must exceed, and one call that integrates from a state through a list of times.
///
/// Implement it directly for an integrator in a scalar other than `f64` (round the problem to
/// your scalar, widen the states to the precision of `problem.initial`); for an `f64`
/// [`Propagator`] use [`Propagated`].
pub trait Integrator {
    /// Name in reports, tables, diagrams and suites.
    fn name(&self) -> String;
    /// The version of the library behind it, when it says (an external integrator's answer);
    /// recorded in the reports' environment.
    fn version(&self) -> Option<String> {
        None
    }
    /// Tolerances shown in the report (`None`: the integrator has none, e.g. a fixed step).
    fn tolerances(&self) -> Option<Tolerances> {
        None
    }
    /// Bits of the scalar the integrator computes in (53 for f64). The closed-form reference is
    /// evaluated [`crate::REFERENCE_GUARD_BITS`] beyond it (and at least at 30 + 19 digits).
    fn working_bits(&self) -> u32;
    /// Decimal digits shown in reports (default: those of [`working_bits`](Self::working_bits)).
    fn digits(&self) -> u32 {
        rsts_dynamics::scalar::digits_for_bits(self.working_bits())
    }
    /// What the last run stated about its cost, part by part, when the integrator does not
    /// count it itself (an external integrator's answer may leave out its steps or evaluations:
    /// reported as not known, not as 0). `None` (default): every count in the trajectory's
    /// `stats` is the integrator's own.
    fn stated_stats(&self) -> Option<crate::StatedStats> {
        None
    }
    /// The states at `times`, starting from `problem.initial` at `times[0]` = 0. `times` is
    /// strictly increasing (a single 0 for a run of no length); the answer has one state per time.
    fn integrate(
        &mut self,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError>;
    /// True when the harness may cut a long run into pieces, each a new call of
    /// [`integrate`](Self::integrate) from the last state of the previous one (progress reports,
    /// Ctrl-C between pieces). False for integrators where a call is expensive to start (an
    /// external process).
    fn restartable(&self) -> bool {
        true
    }
    /// Refuse at once a run over the whole of `grid` from `problem` that cannot fit the
    /// integrator's limits (a built-in method's step budget), before the harness cuts it into
    /// pieces and starts. Default: no limit known.
    fn check_budget(
        &self,
        problem: &Problem<Float>,
        grid: &OutputGrid,
    ) -> Result<(), HarnessError> {
        let _ = (problem, grid);
        Ok(())
    }
}

/// `times` as an evenly spaced grid from 0, when it is exactly one.
fn as_grid(times: &[f64]) -> Option<OutputGrid> {
    let last = *times.last()?;
    let grid = OutputGrid::new(last, times.len()).ok()?;
    (times[0] == 0.0 && (0..times.len()).all(|k| grid.time(k) == times[k])).then_some(grid)
}

/// Check the times handed to an integrator: starting at 0, finite, strictly increasing.
pub fn check_times(times: &[f64]) -> Result<(), HarnessError> {
    if times.is_empty() {
        return Err(HarnessError::Data("no sample times".into()));
    }
    if times[0] != 0.0 {
        return Err(HarnessError::Data(format!(
            "sample times must start at 0 (the initial state), got {}",
            times[0]
        )));
    }
    for (k, w) in times.windows(2).enumerate() {
        if !(w[1].is_finite() && w[1] > w[0]) {
            return Err(HarnessError::Data(format!(
                "sample times must be finite and strictly increasing: time {} is {} after {}",
                k + 1,
                w[1],
                w[0]
            )));
        }
    }
    Ok(())
}

/// Integrate through arbitrary times with a grid integrator: one call when the times are an
/// even grid, otherwise one call per interval (restarting from the last state; the times of the
/// answer are then the sums of the intervals).
fn through_times<T: Clone>(
    times: &[f64],
    initial: &State<T>,
    mut run: impl FnMut(&State<T>, &OutputGrid) -> Result<Solution<T>, HarnessError>,
) -> Result<Solution<T>, HarnessError> {
    check_times(times)?;
    if let Some(grid) = as_grid(times) {
        return run(initial, &grid);
    }
    let mut out: Option<Solution<T>> = None;
    let mut state = initial.clone();
    for w in times.windows(2) {
        let sol = run(&state, &OutputGrid::new(w[1] - w[0], 2)?)?;
        let (t_end, last) = match (sol.times.last(), sol.states.last()) {
            (Some(t), Some(s)) if sol.states.len() == 2 => (*t, s.clone()),
            _ => {
                return Err(HarnessError::Integrator(format!(
                    "{} returned {} states for 2 times",
                    sol.method,
                    sol.states.len()
                )))
            }
        };
        let whole = out.get_or_insert_with(|| Solution {
            method: sol.method,
            times: vec![0.0],
            states: vec![initial.clone()],
            stats: Stats::default(),
        });
        let t0 = *whole.times.last().expect("starts with t = 0");
        whole.times.push(t0 + t_end);
        whole.states.push(last.clone());
        whole.stats.accepted_steps += sol.stats.accepted_steps;
        whole.stats.rejected_steps += sol.stats.rejected_steps;
        whole.stats.rhs_evals += sol.stats.rhs_evals;
        whole.stats.integration_seconds += sol.stats.integration_seconds;
        state = last;
    }
    Ok(out.unwrap_or_else(|| Solution {
        method: "",
        times: vec![0.0],
        states: vec![initial.clone()],
        stats: Stats::default(),
    }))
}

/// The built-in methods, chosen at run time.
impl Integrator for MethodConfig {
    fn name(&self) -> String {
        self.method.as_str().to_string()
    }

    fn tolerances(&self) -> Option<Tolerances> {
        Some(self.tolerances)
    }

    fn working_bits(&self) -> u32 {
        MethodConfig::working_bits(self)
    }

    fn check_budget(
        &self,
        problem: &Problem<Float>,
        grid: &OutputGrid,
    ) -> Result<(), HarnessError> {
        Ok(MethodConfig::check_budget(
            self,
            &map_problem(problem, Float::to_f64),
            grid,
        )?)
    }

    fn integrate(
        &mut self,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        let sol = through_times(times, &problem.initial, |initial, grid| {
            let p = Problem {
                fields: problem.fields.clone(),
                initial: initial.clone(),
            };
            Ok(self.propagate_mp(&p, grid)?)
        })?;
        Ok(Trajectory {
            times: sol.times,
            states: sol.states,
            stats: sol.stats,
            wall_seconds: None,
        })
    }
}

/// A user's `f64` integrator (any type implementing [`Propagator<f64>`]) as an [`Integrator`]:
/// the problem is rounded to f64, the states are widened exactly.
///
/// ```
/// use rsts_dynamics::integrators::{Rk4, Tolerances};
/// use rsts_harness::{compare_integrator, Case, CompareOptions, NoObserver, Propagated};
///
/// // Any Propagator<f64> plugs in; here the built-in RK4 with step 0.01 under its own name.
/// let mut mine = Propagated::new(Rk4::new(0.01)).named("my-rk4");
/// let case = Case::default_i_plus().with_grid(rsts_closed_form::Decimal::parse("5").unwrap(), 11);
/// let report = compare_integrator(&case, &mut mine, &CompareOptions::default(), &mut NoObserver).unwrap();
/// assert_eq!(report.method, "my-rk4");
/// assert!(report.max_state_error < 1e-6);
/// ```
#[derive(Clone, Debug)]
pub struct Propagated<P> {
    pub propagator: P,
    name: Option<String>,
    tolerances: Option<Tolerances>,
}

impl<P: Propagator<f64>> Propagated<P> {
    pub fn new(propagator: P) -> Self {
        Self {
            propagator,
            name: None,
            tolerances: None,
        }
    }

    /// Report under this name instead of [`Propagator::name`].
    pub fn named(self, name: impl Into<String>) -> Self {
        Self {
            name: Some(name.into()),
            ..self
        }
    }

    /// Show these tolerances in reports (the harness does not pass them on: configure the
    /// propagator itself).
    pub fn with_tolerances(self, tolerances: Tolerances) -> Self {
        Self {
            tolerances: Some(tolerances),
            ..self
        }
    }
}

impl<P: Propagator<f64>> Integrator for Propagated<P> {
    fn name(&self) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| self.propagator.name().to_string())
    }

    fn tolerances(&self) -> Option<Tolerances> {
        self.tolerances
    }

    fn working_bits(&self) -> u32 {
        F64_BITS
    }

    fn integrate(
        &mut self,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        let bits = problem.initial.omega[0].prec();
        let p = map_problem(problem, Float::to_f64);
        let sol = through_times(times, &p.initial, |initial, grid| {
            let q = Problem {
                fields: p.fields.clone(),
                initial: initial.clone(),
            };
            Ok(self.propagator.propagate_grid(&q, grid)?)
        })?;
        Ok(Trajectory::from_solution_f64(sol, bits))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsts_dynamics::integrators::{MethodName, Rk4};
    use rsts_dynamics::Fields;

    fn problem(bits: u32) -> Problem<Float> {
        let f = |x: f64| Float::with_val(bits, x);
        Problem {
            fields: Fields::new(f(1.0), f(0.5)).unwrap(),
            initial: State {
                omega: [f(0.3), f(-0.2), f(0.5)],
                alpha: [f(1.0), f(0.0), f(0.0)],
                beta: [f(0.0), f(1.0), f(0.0)],
            },
        }
    }

    #[test]
    fn times_must_start_at_zero_and_increase() {
        assert!(check_times(&[0.0, 1.0, 2.5]).is_ok());
        for bad in [
            &[][..],
            &[0.5, 1.0][..],
            &[0.0, 1.0, 1.0][..],
            &[0.0, 2.0, 1.0][..],
            &[0.0, f64::NAN][..],
        ] {
            assert!(check_times(bad).is_err(), "{bad:?} accepted");
        }
        assert!(as_grid(&[0.0, 0.5, 1.0]).is_some());
        assert!(as_grid(&[0.0, 0.4, 1.0]).is_none());
    }

    /// Uneven times: each interval is its own call; RK4 with a fixed step that divides every
    /// interval gives the same states as one run on the even grid through the same times.
    #[test]
    fn uneven_times_are_integrated_interval_by_interval() {
        let p = problem(120);
        let mut rk4 = Propagated::new(Rk4::new(0.125));
        let even = rk4.integrate(&p, &[0.0, 0.5, 1.0, 1.5, 2.0]).unwrap();
        let uneven = rk4.integrate(&p, &[0.0, 1.0, 2.0]).unwrap();
        assert_eq!(uneven.times, vec![0.0, 1.0, 2.0]);
        assert_eq!(uneven.states.len(), 3);
        for (a, b) in [(1, 2), (2, 4)] {
            for (x, y) in uneven.states[a]
                .to_array()
                .iter()
                .zip(even.states[b].to_array().iter())
            {
                assert!((x.clone() - y).abs().to_f64() < 1e-15, "{x} vs {y}");
            }
        }
        assert_eq!(uneven.stats.accepted_steps, 16);
        assert!(rk4.integrate(&p, &[0.0, 1.0, 0.5]).is_err());
        let mut cfg = MethodConfig::new(
            MethodName::Dop853,
            Tolerances::new(1e-10, 1e-10).unwrap(),
            None,
        )
        .unwrap();
        let t = cfg.integrate(&p, &[0.0, 0.3, 1.7]).unwrap();
        assert_eq!(t.states.len(), 3);
        assert!((t.times[2] - 1.7).abs() < 1e-12);
        assert_eq!(t.states[0].omega[0].prec(), 120);
    }
}
