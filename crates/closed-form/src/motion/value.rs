//! One value for "which motion" (issue 32): the fields (a, b), the point (m, h) of N, the torus
//! and the phases, each a [`Decimal`] as the user wrote it. Every face builds it once and every
//! flow uses it; the closed form is computed from the decimals at the precision asked, so a
//! motion means the same thing at every precision.

use std::fmt;

use rug::Float;
use serde::{Deserialize, Serialize};

use rsts_dynamics::number::{Decimal, NumberError};
use rsts_dynamics::{DynamicsError, Fields, Real};

use super::{ExplicitMotion, TorusChoice};
use crate::error::ClosedFormError;
use crate::scalar::{Scalar, GUARD_BITS};

/// A motion on N: field strengths a > b > 0 (seed sec. 1), the values m of the partial integral
/// and h of the energy, the Liouville torus (0-based, see [`TorusChoice`]) and the angles
/// (ψ₁, ψ₂) on it at t = 0.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Motion {
    pub a: Decimal,
    pub b: Decimal,
    pub m: Decimal,
    pub h: Decimal,
    #[serde(default)]
    pub torus: usize,
    #[serde(default)]
    pub phase1: Decimal,
    #[serde(default)]
    pub phase2: Decimal,
}

/// A text that is not a decimal, with the name of the input it was given for.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{name}: {error}")]
pub struct InputError {
    /// The input's name (`a`, `m`, `phase1`, `t-end`, …).
    pub name: &'static str,
    pub error: NumberError,
}

/// Read the decimal `text` given for the input `name`.
pub fn decimal(name: &'static str, text: &str) -> Result<Decimal, InputError> {
    Decimal::parse(text).map_err(|error| InputError { name, error })
}

/// The exact value of the binary64 number `x` given for the input `name`.
pub fn binary(name: &'static str, x: f64) -> Result<Decimal, InputError> {
    Decimal::from_f64(x).map_err(|error| InputError { name, error })
}

impl Motion {
    /// The built-in default motion: camera I+, a = 1, b = 0.5, m = 0.3, h = −0.375, torus 0,
    /// phases 0.
    pub fn default_i_plus() -> Motion {
        Motion::from_decimals(["1", "0.5", "0.3", "-0.375"], 0, ["0", "0"])
            .expect("the default motion's decimals")
    }

    /// The motion of decimals as written: [a, b, m, h], the torus, [ψ₁, ψ₂].
    pub fn from_decimals(
        [a, b, m, h]: [&str; 4],
        torus: usize,
        [phase1, phase2]: [&str; 2],
    ) -> Result<Motion, InputError> {
        Ok(Motion {
            a: decimal("a", a)?,
            b: decimal("b", b)?,
            m: decimal("m", m)?,
            h: decimal("h", h)?,
            torus,
            phase1: decimal("phase1", phase1)?,
            phase2: decimal("phase2", phase2)?,
        })
    }

    /// The motion of binary64 values (a Python float, an f64 of a file): each is its exact
    /// binary value.
    pub fn from_f64s(
        [a, b, m, h]: [f64; 4],
        torus: usize,
        [phase1, phase2]: [f64; 2],
    ) -> Result<Motion, InputError> {
        Ok(Motion {
            a: binary("a", a)?,
            b: binary("b", b)?,
            m: binary("m", m)?,
            h: binary("h", h)?,
            torus,
            phase1: binary("phase1", phase1)?,
            phase2: binary("phase2", phase2)?,
        })
    }

    /// The same fields and point of N on another torus with other phases.
    pub fn on_torus(&self, torus: usize, phases: [Decimal; 2]) -> Motion {
        let [phase1, phase2] = phases;
        Motion {
            torus,
            phase1,
            phase2,
            ..self.clone()
        }
    }

    /// The torus and the phases rounded to f64 (for what shows them as f64 numbers).
    pub fn choice(&self) -> TorusChoice {
        TorusChoice {
            torus: self.torus,
            phase1: self.phase1.to_f64(),
            phase2: self.phase2.to_f64(),
        }
    }

    /// (a, b, m, h) rounded to f64.
    pub fn parameters_f64(&self) -> [f64; 4] {
        [&self.a, &self.b, &self.m, &self.h].map(Decimal::to_f64)
    }

    /// The field strengths at `bits` bits (each rounded once from its decimal).
    pub fn fields<T: Real>(&self, bits: u32) -> Result<Fields<T>, DynamicsError> {
        Fields::new(self.a.to_real(bits), self.b.to_real(bits))
    }

    /// The closed-form motion in the scalar `T` at `bits` bits, exact at every |t| ≤ `t_max`:
    /// its constants are computed from the decimals rounded once to the build's precision
    /// ([`GUARD_BITS`] beyond `bits`, more for a long clock) and rounded once to `bits`.
    pub fn explicit<T: Scalar>(
        &self,
        bits: u32,
        t_max: f64,
    ) -> Result<ExplicitMotion<T>, ClosedFormError> {
        let build = |hi: u32| {
            let [a, b, m, h] = [&self.a, &self.b, &self.m, &self.h].map(|d| d.to_float(hi));
            let phases = [&self.phase1, &self.phase2].map(|d| d.to_float(hi));
            ExplicitMotion::<Float>::build(a, b, m, h, self.torus, phases)
        };
        let hi = bits.max(53) + GUARD_BITS;
        let exact = build(hi)?;
        // The phase clock: as many more bits as log₂(|u̇|·t_max) needs (as `new_until`).
        let u_dot = [&exact.first, &exact.second]
            .iter()
            .map(|v| v.u_dot.to_f64().abs())
            .fold(0.0, f64::max);
        let reach = (u_dot * t_max.abs()).max(1.0).log2().ceil();
        let spare = f64::from(GUARD_BITS - 8);
        let exact = if reach.is_nan() || reach <= spare {
            exact
        } else {
            build(hi + (reach - spare) as u32 + 8)?
        };
        Ok(ExplicitMotion::from_built(bits, &exact, self.choice()))
    }

    /// Check that the motion exists: a, b, m, h within the documented ranges, (m, h) off Σ in
    /// the admissible region, the torus among the point's tori (a build at f64's precision).
    pub fn validate(&self) -> Result<(), ClosedFormError> {
        self.fields::<Float>(64)
            .map_err(|e| ClosedFormError::Parameters(e.to_string()))?;
        self.explicit::<Float>(64, 0.0).map(|_| ())
    }
}

impl Default for Motion {
    fn default() -> Self {
        Motion::default_i_plus()
    }
}

/// `a = 1.3, b = 0.7, m = -0.52, h = 2.07, torus 1, phases (0.3, 1.1)`: the decimals as written.
impl fmt::Display for Motion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "a = {}, b = {}, m = {}, h = {}, torus {}",
            self.a, self.b, self.m, self.h, self.torus
        )?;
        if !(self.phase1.is_zero() && self.phase2.is_zero()) {
            write!(f, ", phases ({}, {})", self.phase1, self.phase2)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera_v() -> Motion {
        Motion::from_decimals(["1.3", "0.7", "-0.52", "2.07"], 1, ["0.3", "1.1"]).unwrap()
    }

    fn state_at(m: &ExplicitMotion<Float>, t: &str) -> Vec<Float> {
        let bits = m.constants.a.prec();
        let t = Float::with_val(bits, Float::parse(t).unwrap());
        let s = m.at(&t);
        s.omega
            .iter()
            .chain(&s.alpha)
            .chain(&s.beta)
            .cloned()
            .collect()
    }

    fn max_diff(x: &[Float], y: &[Float]) -> f64 {
        x.iter()
            .zip(y)
            .map(|(p, q)| Float::with_val(400, p - q).abs().to_f64())
            .fold(0.0, f64::max)
    }

    /// The same motion at 200 and 400 bits agrees to 200 bits; the motion of the f64 values of
    /// the same decimals is another motion, 1e-16 away.
    #[test]
    fn a_decimal_motion_is_the_same_at_every_precision() {
        let motion = camera_v();
        let lo = motion.explicit::<Float>(200, 10.0).unwrap();
        let hi = motion.explicit::<Float>(400, 10.0).unwrap();
        let [a, b, m, h] = motion.parameters_f64();
        let f = |x: f64| Float::with_val(400, x);
        let of_f64 =
            ExplicitMotion::new_until(f(a), f(b), f(m), f(h), motion.choice(), 10.0).unwrap();
        for t in ["0", "0.55", "7.25"] {
            let (x, y, z) = (state_at(&lo, t), state_at(&hi, t), state_at(&of_f64, t));
            assert!(max_diff(&x, &y) < 1e-58, "t = {t}: {:e}", max_diff(&x, &y));
            let apart = max_diff(&y, &z);
            assert!(apart > 1e-18 && apart < 1e-14, "t = {t}: {apart:e}");
        }
    }

    /// Binary64 inputs give bit for bit the motion built from f64 values, in f64 and MPFR.
    #[test]
    fn binary_inputs_are_the_f64_motion() {
        let choice = TorusChoice {
            torus: 1,
            phase1: 0.3,
            phase2: 1.1,
        };
        let motion = Motion::from_f64s([1.3, 0.7, -0.52, 2.07], 1, [0.3, 1.1]).unwrap();
        let new = motion.explicit::<f64>(53, 1e4).unwrap();
        let old = ExplicitMotion::<f64>::new_until(1.3, 0.7, -0.52, 2.07, choice, 1e4).unwrap();
        for t in [0.0, 0.55, 7.25, 9999.0] {
            let (x, y) = (new.at(&t), old.at(&t));
            assert_eq!(
                format!("{:?}", x.omega),
                format!("{:?}", y.omega),
                "t = {t}"
            );
            assert_eq!(format!("{:?}", x.beta), format!("{:?}", y.beta), "t = {t}");
        }
        let f = |x: f64| Float::with_val(120, x);
        let new = motion.explicit::<Float>(120, 50.0).unwrap();
        let old =
            ExplicitMotion::new_until(f(1.3), f(0.7), f(-0.52), f(2.07), choice, 50.0).unwrap();
        assert_eq!(state_at(&new, "3.5"), state_at(&old, "3.5"));
    }

    #[test]
    fn a_motion_that_does_not_exist_is_refused() {
        let mut m = camera_v();
        m.torus = 99;
        assert!(matches!(
            m.validate(),
            Err(ClosedFormError::NoSuchTorus { .. })
        ));
        assert!(camera_v().validate().is_ok());
        let e = Motion::from_decimals(["1", "0.5", "nan", "0"], 0, ["0", "0"]).unwrap_err();
        assert_eq!(e.name, "m");
        assert!(Motion::from_f64s([1.0, 0.5, f64::INFINITY, 0.0], 0, [0.0, 0.0]).is_err());
    }

    #[test]
    fn the_default_motion_is_camera_i_plus() {
        let m = Motion::default_i_plus();
        assert_eq!(m.parameters_f64(), [1.0, 0.5, 0.3, -0.375]);
        assert_eq!(m.explicit::<f64>(53, 1.0).unwrap().camera.label(), "I+");
        assert_eq!(
            m.to_string(),
            "a = 1, b = 0.5, m = 0.3, h = -0.375, torus 0"
        );
        let json = serde_json::to_string(&m).unwrap();
        let back: Motion = serde_json::from_str(&json).unwrap();
        assert_eq!(back, m);
    }
}
