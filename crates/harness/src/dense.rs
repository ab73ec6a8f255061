//! The dense-output check (`rsts compare --dense K`, `rsts bench --dense K`; docs/compare.md):
//! K samples inside each of an integrator's own steps, evaluated by its interpolant, measured
//! against the closed form apart from the states at the step ends, so that an interpolant of
//! lower order than the step shows up as `dense_max_error` ≫ `step_max_error`.

use rayon::prelude::*;
use serde::Serialize;

use rsts_dynamics::integrators::dense::StepSamples;
use rsts_dynamics::integrators::{MethodConfig, Problem};
use rsts_dynamics::State;

use crate::case::Case;
use crate::reference::ReferenceTable;
use crate::HarnessError;

pub use rsts_dynamics::integrators::dense::{check_dense, MAX_DENSE};

/// What the dense check found (flattened into a compare report, a bench row).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct DenseReport {
    /// K: samples inside each step.
    pub dense: usize,
    /// Steps of the run checked.
    pub dense_steps: usize,
    /// Largest state error (max-norm over ω, α, β) at the ends of the steps: the integrator's
    /// own states.
    pub step_max_error: f64,
    /// Largest state error at the K samples inside each step: its dense output.
    pub dense_max_error: f64,
}

impl DenseReport {
    /// One line for a text report.
    pub fn summary(&self) -> String {
        format!(
            "max error {:.3e} inside the steps ({} per step), {:.3e} at their ends ({} steps)",
            self.dense_max_error, self.dense, self.step_max_error, self.dense_steps
        )
    }
}

/// The dense check of the built-in method `config` along `case`: one more (untimed) run over the
/// case's grid in one piece, as its own steps with `k` samples of its dense output inside each
/// ([`MethodConfig::propagate_steps`]).
pub fn dense_of_method(
    case: &Case,
    config: &MethodConfig,
    k: usize,
) -> Result<DenseReport, HarnessError> {
    check_dense(k)?;
    case.validate()?;
    let start = ReferenceTable::new(case, &[0.0], None)?
        .row_f64(0.0)
        .map_err(HarnessError::Data)?;
    let problem = Problem {
        fields: case.motion.fields(53)?,
        initial: State::from_slice(&start[1..10]),
    };
    let grid = case.grid()?;
    let samples = config.propagate_steps(&problem, &grid, k)?;
    dense_of_samples(case, k, &samples)
}

/// Measure the samples of a run at its own steps (`k` inside each) against the closed form of
/// `case` (correctly rounded to f64: errors below ~1e-16 are not resolved).
pub fn dense_of_samples(
    case: &Case,
    k: usize,
    samples: &StepSamples,
) -> Result<DenseReport, HarnessError> {
    let table = ReferenceTable::new(case, &samples.times, None)?;
    let errors: Vec<(f64, bool)> = samples
        .times
        .par_iter()
        .zip(&samples.states)
        .zip(&samples.at_step_end)
        .map(|((&t, y), &end)| {
            let exact = table.row_f64(t)?;
            let e = (0..9).fold(0.0f64, |m, i| m.max((y[i] - exact[i + 1]).abs()));
            Ok((e, end))
        })
        .collect::<Result<_, String>>()
        .map_err(HarnessError::Data)?;
    let worst = |at_end: bool| {
        errors
            .iter()
            .filter(|(_, end)| *end == at_end)
            .fold(0.0f64, |m, (e, _)| m.max(*e))
    };
    Ok(DenseReport {
        dense: k,
        dense_steps: samples.steps(),
        step_max_error: worst(true),
        dense_max_error: worst(false),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsts_dynamics::integrators::{MethodName, Tolerances};

    fn config(method: MethodName, tol: f64) -> MethodConfig {
        MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap()
    }

    /// Every interpolant of the built-ins is of the order of its step's error: the dense error
    /// stays within a small factor of the error at the step ends (and both are small), and the
    /// runs report K + 1 samples per step.
    #[test]
    fn the_builtins_interpolate_at_the_order_of_their_steps() {
        let case =
            Case::default_i_plus().with_grid(rsts_closed_form::Decimal::parse("5").unwrap(), 11);
        for (method, tol) in [
            (MethodName::Rk4, 1e-10),
            (MethodName::Dopri5, 1e-9),
            (MethodName::Dop853, 1e-11),
        ] {
            let r = dense_of_method(&case, &config(method, tol), 3).unwrap();
            assert!(r.dense_steps >= 10, "{method}: {r:?}");
            assert!(
                r.step_max_error > 0.0 && r.step_max_error < 1e-6,
                "{method}: {r:?}"
            );
            assert!(
                r.dense_max_error < 30.0 * r.step_max_error,
                "{method}: dense error far above the step ends: {r:?}"
            );
        }
        assert!(dense_of_method(&case, &config(MethodName::Rk4, 1e-10), 0).is_err());
    }

    /// The samples with the K interior states replaced by the chord between the step ends: a
    /// linear interpolant (error O(h²)), the wrong dense output the check must expose.
    fn chord(samples: &StepSamples) -> StepSamples {
        let mut out = samples.clone();
        let mut start = 0;
        for end in (1..samples.times.len()).filter(|&i| samples.at_step_end[i]) {
            let (t0, t1) = (samples.times[start], samples.times[end]);
            let (y0, y1) = (samples.states[start], samples.states[end]);
            for i in start + 1..end {
                let s = (samples.times[i] - t0) / (t1 - t0);
                out.states[i] = std::array::from_fn(|c| y0[c] + s * (y1[c] - y0[c]));
            }
            start = end;
        }
        out
    }

    /// The Taylor methods sample inside a step from the step's own polynomial, of full order:
    /// the dense error stays within 10× the error at the step ends (f64, double-double, MPFR);
    /// the chord between the same step ends — what a Taylor method interpolating linearly
    /// would report — is off by many orders of magnitude.
    #[test]
    fn taylor_methods_interpolate_with_their_own_polynomial() {
        let case =
            Case::default_i_plus().with_grid(rsts_closed_form::Decimal::parse("10").unwrap(), 11);
        let k = 4;
        for (method, tol) in [
            (MethodName::TaylorF64, 1e-10),
            (MethodName::TaylorF64, 1e-13),
            (MethodName::TaylorDd, 1e-10),
            (MethodName::TaylorMp, 1e-10),
        ] {
            let r = dense_of_method(&case, &config(method, tol), k).unwrap();
            assert!(r.dense_steps >= 20, "{method}: {r:?}");
            assert!(
                r.step_max_error > 0.0 && r.step_max_error < 100.0 * tol,
                "{method} at {tol:e}: {r:?}"
            );
            assert!(
                r.dense_max_error <= 10.0 * r.step_max_error,
                "{method} at {tol:e}: dense error far above the step ends: {r:?}"
            );
        }
        let grid = case.grid().unwrap();
        let start = ReferenceTable::new(&case, &[0.0], None)
            .unwrap()
            .row_f64(0.0)
            .unwrap();
        let problem = Problem {
            fields: case.motion.fields(53).unwrap(),
            initial: State::from_slice(&start[1..10]),
        };
        let samples = config(MethodName::TaylorF64, 1e-10)
            .propagate_steps(&problem, &grid, k)
            .unwrap();
        let own = dense_of_samples(&case, k, &samples).unwrap();
        let linear = dense_of_samples(&case, k, &chord(&samples)).unwrap();
        assert_eq!(own.step_max_error, linear.step_max_error);
        assert!(
            linear.dense_max_error > 1e4 * linear.step_max_error,
            "the chord is not exposed: {linear:?}"
        );
    }
}
