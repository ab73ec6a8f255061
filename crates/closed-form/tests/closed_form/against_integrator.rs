//! The closed form at time t agrees with the closed form at 0 carried to t by an independent
//! integrator of the full Euler–Poisson equations (Dop853 in f64, rtol = atol = 1e-13), in every
//! camera; and the check fails when the closed form is started on the wrong torus.

use crate::common;
use common::CAMERA_POINTS;
use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};
use rsts_dynamics::integrators::{Dop853, OutputGrid, Problem, Propagator, Tolerances};
use rsts_dynamics::{Fields, State};

fn state(s: &ExplicitState<f64>) -> State<f64> {
    State {
        omega: s.omega,
        alpha: s.alpha,
        beta: s.beta,
    }
}

fn max_deviation(motion: &ExplicitMotion<f64>, start: &State<f64>, t_end: f64) -> f64 {
    let problem = Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: start.clone(),
    };
    let grid = OutputGrid::new(t_end, 41).unwrap();
    let tol = Tolerances::new(1e-13, 1e-13).unwrap();
    let sol = Dop853::new(tol).propagate_grid(&problem, &grid).unwrap();
    sol.times
        .iter()
        .zip(&sol.states)
        .map(|(t, s)| {
            let e = state(&motion.at(t)).to_array();
            let x = s.to_array();
            (0..9).map(|k| (e[k] - x[k]).abs()).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn closed_form_follows_dop853_in_every_camera() {
    for (label, m, h) in CAMERA_POINTS {
        let choice = TorusChoice {
            torus: 0,
            phase1: 1.1,
            phase2: 0.4,
        };
        let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
        let dev = max_deviation(&motion, &state(&motion.at(&0.0)), 20.0);
        assert!(
            dev < 1e-9,
            "{label}: closed form and Dop853 differ by {dev:e}"
        );
    }
}

#[test]
fn a_wrong_start_is_detected() {
    // Start the integrator on another torus of camera V (a reflection of this one): the
    // trajectories separate at once.
    let (m, h) = (-0.7092, 1.5643);
    let on = |torus| {
        ExplicitMotion::new(
            1.0,
            0.5,
            m,
            h,
            TorusChoice {
                torus,
                phase1: 1.1,
                phase2: 0.4,
            },
        )
        .unwrap()
    };
    let (t0, t1) = (on(0), on(1));
    let dev = max_deviation(&t0, &state(&t1.at(&0.0)), 5.0);
    assert!(dev > 1e-2, "different tori must not agree: {dev:e}");
}

#[test]
fn closed_form_follows_the_40_digit_taylor_integrator() {
    // The arbitrary-precision integrator (Taylor series in MPFR, 50 digits, tolerance 1e-45)
    // carries the 60-digit closed-form state at 0 to t = 10; both agree to 40 digits, in three
    // cameras.
    use rsts_dynamics::integrators::{MethodConfig, MethodName};
    use rsts_dynamics::scalar::bits_for_digits;
    use rug::Float;
    let bits = bits_for_digits(60);
    let f = |x: f64| Float::with_val(bits, x);
    let tol = Tolerances::new(1e-45, 1e-45).unwrap();
    let cfg = MethodConfig::new(MethodName::TaylorMp, tol, None)
        .unwrap()
        .with_digits(50)
        .unwrap();
    for (label, m, h) in [CAMERA_POINTS[0], CAMERA_POINTS[4], CAMERA_POINTS[7]] {
        let choice = TorusChoice {
            torus: 0,
            phase1: 0.3,
            phase2: 2.0,
        };
        let motion = ExplicitMotion::new(f(1.0), f(0.5), f(m), f(h), choice).unwrap();
        let s0 = motion.at(&f(0.0));
        let problem = Problem {
            fields: Fields::new(f(1.0), f(0.5)).unwrap(),
            initial: State {
                omega: s0.omega,
                alpha: s0.alpha,
                beta: s0.beta,
            },
        };
        let sol = cfg
            .propagate_mp(&problem, &OutputGrid::new(10.0, 6).unwrap())
            .unwrap();
        for (t, s) in sol.times.iter().zip(&sol.states) {
            let e = motion.at(&f(*t));
            let exact = State {
                omega: e.omega,
                alpha: e.alpha,
                beta: e.beta,
            }
            .to_array();
            let x = s.to_array();
            let dev = (0..9)
                .map(|k| Float::with_val(bits, &x[k] - &exact[k]).abs().to_f64())
                .fold(0.0, f64::max);
            assert!(dev < 1e-40, "{label} at t = {t}: {dev:e}");
        }
    }
}
