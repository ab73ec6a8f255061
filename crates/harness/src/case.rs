//! A comparison case: one [`Motion`] and its sample times, N evenly spaced on [0, T].

use rsts_closed_form::{Decimal, ExplicitMotion, Motion, Times};
use rsts_dynamics::integrators::OutputGrid;
use rsts_dynamics::Fields;
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::HarnessError;

/// Which motion and how it is sampled: N ≥ 1 times t_k = k·T/(N−1) on [0, T] (serialised with
/// the motion's fields flattened: `{"a": 1.0, …, "t_end": 100.0, "samples": 1001}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Case {
    #[serde(flatten)]
    pub motion: Motion,
    pub t_end: Decimal,
    pub samples: usize,
}

impl Case {
    /// The built-in default case: camera I+, a = 1, b = 0.5, m = 0.3, h = −0.375, T = 100,
    /// 1001 samples.
    pub fn default_i_plus() -> Self {
        Self::new(Motion::default_i_plus(), Decimal::from_integer(100), 1001)
    }

    /// The motion sampled at N times on [0, T].
    pub fn new(motion: Motion, t_end: Decimal, samples: usize) -> Self {
        Self {
            motion,
            t_end,
            samples,
        }
    }

    /// A case of binary64 values, each its exact value ([a, b, m, h], the torus, [ψ₁, ψ₂], T, N):
    /// for callers that hold f64 numbers.
    pub fn binary(
        parameters: [f64; 4],
        torus: usize,
        phases: [f64; 2],
        t_end: f64,
        samples: usize,
    ) -> Result<Self, HarnessError> {
        let named =
            |e: rsts_closed_form::InputError| HarnessError::setting(&[e.name], e.error.to_string());
        let motion = Motion::from_f64s(parameters, torus, phases).map_err(named)?;
        let t_end = rsts_closed_form::motion::binary("t-end", t_end).map_err(named)?;
        Ok(Self::new(motion, t_end, samples))
    }

    /// The same motion on another grid.
    pub fn with_grid(&self, t_end: Decimal, samples: usize) -> Self {
        Self::new(self.motion.clone(), t_end, samples)
    }

    /// T ≥ 0 and N ≥ 1 (the motion itself is checked by the closed form).
    pub fn validate(&self) -> Result<(), HarnessError> {
        if self.t_end.is_negative() {
            return Err(HarnessError::setting(
                &["t-end"],
                format!(
                    "t-end must be non-negative, got {}",
                    rsts_dynamics::number::shorten(self.t_end.as_str())
                ),
            ));
        }
        if self.samples == 0 {
            return Err(HarnessError::setting(
                &["samples"],
                "samples must be at least 1",
            ));
        }
        Ok(())
    }

    /// T rounded to f64.
    pub fn t_end_f64(&self) -> f64 {
        self.t_end.to_f64()
    }

    /// The sample times.
    pub fn times(&self) -> Times {
        Times::grid(self.t_end.clone(), self.samples)
    }

    /// The grid of an f64 integrator (T rounded to f64).
    pub fn grid(&self) -> Result<OutputGrid, HarnessError> {
        Ok(OutputGrid::new(self.t_end_f64(), self.samples)?)
    }

    /// The closed-form motion of the case and its fields, at `bits` bits (the reference), exact
    /// at every time up to t-end.
    pub fn reference_motion(
        &self,
        bits: u32,
    ) -> Result<(ExplicitMotion<Float>, Fields<Float>), HarnessError> {
        self.validate()?;
        let motion = self.motion.explicit::<Float>(bits, self.t_end_f64())?;
        let fields = self.motion.fields(bits)?;
        Ok((motion, fields))
    }
}
