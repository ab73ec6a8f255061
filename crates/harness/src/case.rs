//! A comparison case: the point (m, h) of N, the torus and phases, and the sample times.

use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::Fields;
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::HarnessError;

/// Where the motion is and how it is sampled.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Case {
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    #[serde(default)]
    pub torus: usize,
    #[serde(default)]
    pub phase1: f64,
    #[serde(default)]
    pub phase2: f64,
    pub t_end: f64,
    pub samples: usize,
}

impl Case {
    /// The built-in default case: camera I+, a = 1, b = 0.5, m = 0.3, h = −0.375.
    pub fn default_i_plus() -> Self {
        Self {
            a: 1.0,
            b: 0.5,
            m: 0.3,
            h: -0.375,
            torus: 0,
            phase1: 0.0,
            phase2: 0.0,
            t_end: 100.0,
            samples: 1001,
        }
    }

    /// Finite numbers, T ≥ 0, N ≥ 1 (a, b, m, h themselves are checked by the closed form).
    pub fn validate(&self) -> Result<(), HarnessError> {
        for (name, v) in [
            ("a", self.a),
            ("b", self.b),
            ("m", self.m),
            ("h", self.h),
            ("phase1", self.phase1),
            ("phase2", self.phase2),
            ("t-end", self.t_end),
        ] {
            if !v.is_finite() {
                return Err(HarnessError::Case(format!(
                    "{name} must be a finite number, got {v}"
                )));
            }
        }
        if self.t_end < 0.0 {
            return Err(HarnessError::Case(format!(
                "t-end must be non-negative, got {}",
                self.t_end
            )));
        }
        if self.samples == 0 {
            return Err(HarnessError::Case("samples must be at least 1".into()));
        }
        Ok(())
    }

    /// The closed-form motion of the case and its fields, at `bits` bits (the reference), exact
    /// at every time up to t-end.
    pub fn reference_motion(
        &self,
        bits: u32,
    ) -> Result<(ExplicitMotion<Float>, Fields<Float>), HarnessError> {
        self.validate()?;
        let f = |x: f64| Float::with_val(bits, x);
        let choice = TorusChoice {
            torus: self.torus,
            phase1: self.phase1,
            phase2: self.phase2,
        };
        // The phase clock carries the bits t-end needs (the state at t = 1e300 is the motion's).
        let motion = ExplicitMotion::new_until(
            f(self.a),
            f(self.b),
            f(self.m),
            f(self.h),
            choice,
            self.t_end,
        )?;
        let fields = Fields::new(f(self.a), f(self.b))?;
        Ok((motion, fields))
    }
}
