//! The closed form checked on its own: f64 against 50 digits at the case's times (the same f64
//! inputs, so the difference is the f64 evaluation's error), and the Euler–Poisson residual
//! |dx/dt − f(x)| of the 50-digit motion, with dx/dt from the chain rule through the elliptic
//! functions ([`ExplicitMotion::at_with_derivative`]) and f from the table of equations.

use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Fields, Real, VectorField};
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::ValidateError;

/// Digits of the reference closed form.
pub const DIGITS: u32 = 50;
/// At most this many of the case's sample times are compared (evenly spread, T included).
pub const MAX_TIMES: usize = 64;
/// The residual is evaluated at this many times (0, the middle and T).
pub const RESIDUAL_TIMES: usize = 3;

/// Result of the closed-form check of one (case, torus).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClosedFormCheck {
    /// max over the compared times of max |x_f64 − x_50| over (ω, α, β).
    pub f64_error: f64,
    /// max |dx/dt − f(x)| of the 50-digit motion.
    pub residual: f64,
    pub times_compared: usize,
    /// Elliptic moduli k² of x = 1/s₁ and s₂ (near 0 or 1 close to Σ).
    pub k2: [f64; 2],
    /// Periods of the two angles.
    pub periods: [f64; 2],
}

fn phase<T: Real>(s: &ExplicitState<T>) -> [T; 9] {
    let v = [&s.omega, &s.alpha, &s.beta];
    std::array::from_fn(|k| v[k / 3][k % 3].clone())
}

/// The times compared: at most [`MAX_TIMES`] of the grid of `samples` points on [0, t_end].
pub fn check_times(t_end: f64, samples: usize) -> Vec<f64> {
    if samples <= 1 || t_end == 0.0 {
        return vec![0.0];
    }
    let n = samples.min(MAX_TIMES);
    (0..n)
        .map(|k| {
            let idx = k * (samples - 1) / (n - 1);
            t_end * idx as f64 / (samples - 1) as f64
        })
        .collect()
}

/// Check the closed form at (a, b, m, h) on a torus at the given times.
pub fn check(
    a: f64,
    b: f64,
    m: f64,
    h: f64,
    choice: TorusChoice,
    times: &[f64],
) -> Result<ClosedFormCheck, ValidateError> {
    let cf = |e: rsts_closed_form::ClosedFormError| ValidateError::Run(format!("{e}"));
    let lo = ExplicitMotion::new(a, b, m, h, choice).map_err(cf)?;
    let bits = bits_for_digits(DIGITS);
    let f = |x: f64| Float::with_val(bits, x);
    let hi = ExplicitMotion::new(f(a), f(b), f(m), f(h), choice).map_err(cf)?;
    let mut f64_error = 0.0f64;
    for &t in times {
        let x = phase(&lo.at(&t));
        let y = phase(&hi.at(&f(t)));
        for k in 0..9 {
            let d = (Float::with_val(bits, x[k]) - &y[k]).abs().to_f64();
            // NaN must fail the check, not vanish in max.
            f64_error = if d.is_nan() {
                f64::NAN
            } else {
                f64_error.max(d)
            };
        }
        if f64_error.is_nan() {
            break;
        }
    }
    let fields = Fields { a: f(a), b: f(b) };
    let field = VectorField::new(&fields);
    let mut residual = 0.0f64;
    let picks: Vec<f64> = if times.len() <= RESIDUAL_TIMES {
        times.to_vec()
    } else {
        vec![times[0], times[times.len() / 2], times[times.len() - 1]]
    };
    for t in picks {
        let sd = hi.at_with_derivative(&f(t));
        let p = phase(&sd);
        let x: [Float; 9] = std::array::from_fn(|k| p[k].re.clone());
        let dx: [Float; 9] = std::array::from_fn(|k| p[k].eps.clone());
        let fx = field.eval(&x);
        for k in 0..9 {
            let d = (dx[k].clone() - &fx[k]).abs().to_f64();
            residual = if d.is_nan() {
                f64::NAN
            } else {
                residual.max(d)
            };
        }
    }
    Ok(ClosedFormCheck {
        f64_error,
        residual,
        times_compared: times.len(),
        k2: [lo.first.modulus.k2, lo.second.modulus.k2],
        periods: lo.periods(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_v_is_at_round_off_in_f64_and_solves_the_equations_at_50_digits() {
        let choice = TorusChoice {
            torus: 1,
            phase1: 0.3,
            phase2: 1.0,
        };
        let c = check(1.0, 0.5, -0.7092, 1.5643, choice, &check_times(50.0, 11)).unwrap();
        assert_eq!(c.times_compared, 11);
        assert!(c.f64_error > 0.0 && c.f64_error < 1e-13, "{c:?}");
        assert!(c.residual < 1e-40, "{c:?}");
    }

    #[test]
    fn times_are_grid_points_with_both_ends() {
        let t = check_times(10.0, 1001);
        assert_eq!(t.len(), MAX_TIMES);
        assert_eq!((t[0], *t.last().unwrap()), (0.0, 10.0));
        assert_eq!(check_times(10.0, 3), vec![0.0, 5.0, 10.0]);
        assert_eq!(check_times(0.0, 3), vec![0.0]);
    }
}
