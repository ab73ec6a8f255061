//! A run's own steps with its dense output inside them (`rsts compare --dense K`, docs/compare.md):
//! the start and end of every accepted step, and in each step K interior samples evaluated by the
//! method's interpolant, so that an interpolant of lower order than the step shows up.
//!
//! How each built-in method interpolates:
//! - `rk4`: the cubic Hermite polynomial of the states and derivatives at both ends of the step
//!   (order 3: error O(h⁴), the order of the step's global error);
//! - `dopri5`: the continuous extension of Dormand–Prince 5(4) of `ode_solvers` (order 4,
//!   Hairer–Nørsett–Wanner II.6), from its continuous output model;
//! - `dop853`: `ode_solvers` evaluates its dense output (order 7) only on an even grid, so its
//!   interior samples are the points of an even grid of about K points per step (a second run
//!   with the same steps);
//! - the Taylor methods: the Taylor polynomial of the step (its order), evaluated by Horner.

use crate::error::DynamicsError;
use crate::state::DIM;

use super::OutputGrid;

/// Largest K of [`StepSamples`]: interior samples per step.
pub const MAX_DENSE: usize = 64;

/// Most samples (interior ones and step ends) one dense check may hold.
pub const MAX_DENSE_SAMPLES: usize = 1_000_000;

/// Check K: 1 to [`MAX_DENSE`].
pub fn check_dense(k: usize) -> Result<(), DynamicsError> {
    if (1..=MAX_DENSE).contains(&k) {
        Ok(())
    } else {
        Err(DynamicsError::Settings(format!(
            "dense must be between 1 and {MAX_DENSE} samples inside each step, got {k}"
        )))
    }
}

/// The samples of a run at its own steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepSamples {
    /// t₀ = 0 < t₁ < … < tₙ: the start of the run and the end of each of its n accepted steps.
    pub step_times: Vec<f64>,
    /// Sample times in increasing order: interior samples (dense output) and step ends.
    pub times: Vec<f64>,
    /// The state at each time (ω, α, β).
    pub states: Vec<[f64; DIM]>,
    /// Whether each sample is a step end (the method's own state) or interior (interpolated).
    pub at_step_end: Vec<bool>,
}

impl StepSamples {
    /// Number of steps.
    pub fn steps(&self) -> usize {
        self.step_times.len().saturating_sub(1)
    }

    /// The samples of a run from `y0` at t = 0 before its first step (K checked).
    pub fn start(k: usize, y0: [f64; DIM]) -> Result<Self, DynamicsError> {
        check_dense(k)?;
        let mut out = Self::default();
        out.step_times.push(0.0);
        out.push(0.0, y0, true);
        Ok(out)
    }

    /// Add a sample.
    pub fn push(&mut self, t: f64, y: [f64; DIM], at_step_end: bool) {
        self.times.push(t);
        self.states.push(y);
        self.at_step_end.push(at_step_end);
    }

    /// Add a sample of a run sampling its own steps, a step end recorded in
    /// [`step_times`](Self::step_times); a state that is not finite is an error of `method`.
    pub fn push_step_sample(
        &mut self,
        method: &str,
        t: f64,
        y: [f64; DIM],
        at_step_end: bool,
    ) -> Result<(), DynamicsError> {
        if y.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::Integration(format!(
                "{method}: solution not finite at t = {t}"
            )));
        }
        self.push(t, y, at_step_end);
        if at_step_end {
            self.step_times.push(t);
        }
        Ok(())
    }

    /// Append the steps of `more` (a run's samples after its start).
    pub fn append(&mut self, more: StepSamples) {
        self.step_times.extend(more.step_times);
        self.times.extend(more.times);
        self.states.extend(more.states);
        self.at_step_end.extend(more.at_step_end);
    }

    /// Refuse a run whose samples pass [`MAX_DENSE_SAMPLES`].
    pub fn check_size(&self, method: &str) -> Result<(), DynamicsError> {
        if self.times.len() > MAX_DENSE_SAMPLES {
            return Err(too_many(method, self.times.len()));
        }
        Ok(())
    }
}

/// The start of every built-in's dense check on `grid`: the samples at t = 0 (K checked) and Δ,
/// the grid spacing, when the run takes steps (`None`: one sample, T = 0, or a spacing below
/// [`super::ode_solvers_adapter::TINY_SPACING`], over which the motion is y₀ + t·f(y₀) to within
/// rounding).
pub(super) fn begin(
    k: usize,
    y0: [f64; DIM],
    grid: &OutputGrid,
) -> Result<(StepSamples, Option<f64>), DynamicsError> {
    let scale = grid.spacing();
    let steps =
        grid.samples > 1 && grid.t_end != 0.0 && scale >= super::ode_solvers_adapter::TINY_SPACING;
    Ok((StepSamples::start(k, y0)?, steps.then_some(scale)))
}

/// Where a method with a polynomial per step (the Taylor methods) samples its step
/// [t, t + h] of a run to T: the K interior times of [t, b] and b itself (a step end), with
/// b = min(t + h, T) — the last step is cut at T, where the plain run takes its last sample
/// from the same polynomial. The flag is `true` for the step end; the `bool` returned says
/// whether this step is the last.
pub fn polynomial_step(
    t: f64,
    h: f64,
    t_end: f64,
    k: usize,
) -> (impl Iterator<Item = (f64, bool)>, bool) {
    let last = t_end <= t + h;
    let b = if last { t_end } else { t + h };
    let inside = interior_times(t, b, k).map(|s| (s, false));
    (inside.chain(std::iter::once((b, true))), last)
}

/// The error of a dense check holding `samples` samples.
pub fn too_many(method: &str, samples: usize) -> DynamicsError {
    DynamicsError::Settings(format!(
        "{method}: the dense check takes {samples} samples (K + 1 per step), more than the limit \
         of {MAX_DENSE_SAMPLES}; shorten t-end or ask fewer samples per step"
    ))
}

/// The K interior times of the step [t₀, t₁]: t₀ + j(t₁ − t₀)/(K + 1), j = 1 … K (the rule of
/// the built-ins and of the protocol's `"dense"` answer).
pub fn interior_times(t0: f64, t1: f64, k: usize) -> impl Iterator<Item = f64> {
    (1..=k).map(move |j| t0 + (t1 - t0) * j as f64 / (k + 1) as f64)
}

/// The cubic Hermite interpolant at θ ∈ [0, 1] of a step of length h from (y₀, f₀) to (y₁, f₁).
pub fn hermite(
    theta: f64,
    h: f64,
    (y0, f0): (&[f64; DIM], &[f64; DIM]),
    (y1, f1): (&[f64; DIM], &[f64; DIM]),
) -> [f64; DIM] {
    let (s, s2, s3) = (theta, theta * theta, theta * theta * theta);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = 3.0 * s2 - 2.0 * s3;
    let h11 = s3 - s2;
    std::array::from_fn(|i| h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Hermite cubic reproduces a cubic exactly and hits both ends.
    #[test]
    fn hermite_is_exact_on_cubics() {
        let p = |t: f64| 1.0 - 2.0 * t + 0.5 * t * t * t;
        let dp = |t: f64| -2.0 + 1.5 * t * t;
        let (t0, h) = (0.3, 0.7);
        let v = |x: f64| [x; DIM];
        for theta in [0.0, 0.25, 0.5, 1.0] {
            let y = hermite(
                theta,
                h,
                (&v(p(t0)), &v(dp(t0))),
                (&v(p(t0 + h)), &v(dp(t0 + h))),
            );
            assert!((y[0] - p(t0 + theta * h)).abs() < 1e-14, "θ = {theta}");
        }
        let t: Vec<f64> = interior_times(1.0, 2.0, 3).collect();
        assert_eq!(t, vec![1.25, 1.5, 1.75]);
        assert!(check_dense(0).is_err() && check_dense(MAX_DENSE + 1).is_err());
    }
}
