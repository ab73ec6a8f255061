//! The closed form at time t agrees with the closed form at 0 carried to t by an independent
//! integrator of the full Euler–Poisson equations (Dop853 in f64, rtol = atol = 1e-13), in every
//! camera; and the check fails when the closed form is started on the wrong torus.

mod common;
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
