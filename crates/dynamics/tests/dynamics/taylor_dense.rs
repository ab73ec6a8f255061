//! The dense output of the Taylor methods (`rsts compare --dense K`): a dense run samples the
//! steps of the plain run — as many, the same state at T to the bit — on every stepper (the lane
//! kernel on each code path of this CPU, the generic stepper in f64, double-double, MPFR), with
//! K samples inside each step and the last step cut at T. Their accuracy against the closed form
//! is tested in crates/harness (`dense.rs`).

use rsts_dynamics::integrators::dense::StepSamples;
use rsts_dynamics::integrators::{
    MethodConfig, MethodName, OutputGrid, Problem, Propagator, SimdPath, Solution, Taylor,
    Tolerances,
};
use rsts_dynamics::{Fields, State};

const K: usize = 3;

fn problem() -> Problem<f64> {
    Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: State {
            omega: [0.3, -0.7, 1.1],
            alpha: [1.0, 0.0, 0.0],
            beta: [0.0, 0.6, 0.8],
        },
    }
}

/// The dense run `steps` took the steps of the plain run `plain` on `grid`: as many, K samples
/// inside each, increasing times ending at T, and the plain run's last state to the bit.
fn assert_same_steps(what: &str, plain: &Solution<f64>, steps: &StepSamples, grid: &OutputGrid) {
    let n = steps.steps();
    assert!(n >= 10, "{what}: {n} steps");
    assert_eq!(n as u64, plain.stats.accepted_steps, "{what}: step count");
    assert_eq!(steps.times.len(), 1 + n * (K + 1), "{what}: samples");
    let ends = steps.at_step_end.iter().filter(|e| **e).count();
    assert_eq!(ends, n + 1, "{what}: step ends (the start included)");
    assert!(
        steps.times.windows(2).all(|w| w[0] < w[1]),
        "{what}: times increase"
    );
    assert_eq!(
        steps.step_times.last(),
        Some(&grid.t_end),
        "{what}: ends at T"
    );
    let last = plain.states.last().unwrap().to_array();
    let dense_last = steps.states.last().unwrap();
    assert_eq!(
        last.map(f64::to_bits),
        dense_last.map(f64::to_bits),
        "{what}: the state at T differs: {last:?} vs {dense_last:?}"
    );
}

/// The three Taylor methods as the CLI runs them ([`MethodConfig`]), tolerances that end the
/// last step inside it (T is not a step end).
#[test]
fn dense_runs_take_the_plain_runs_steps() {
    let grid = OutputGrid::new(7.3, 9).unwrap();
    for (method, tol) in [
        (MethodName::TaylorF64, 1e-12),
        (MethodName::TaylorF64, 1e-6),
        (MethodName::TaylorDd, 1e-24),
        (MethodName::TaylorMp, 1e-30),
    ] {
        let config = MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None)
            .unwrap()
            .with_digits(40)
            .unwrap();
        let plain = config.propagate_f64(&problem(), &grid).unwrap();
        let steps = config.propagate_steps(&problem(), &grid, K).unwrap();
        assert_same_steps(&format!("{method} at {tol:e}"), &plain, &steps, &grid);
    }
}

/// The lane kernel on every code path of this CPU, and the generic stepper in f64 (a run
/// without compensation takes it).
#[test]
fn every_stepper_samples_its_own_steps() {
    let grid = OutputGrid::new(5.0, 6).unwrap();
    let tol = Tolerances::new(1e-13, 1e-13).unwrap();
    let mut runs = vec![(
        "generic, uncompensated".to_string(),
        Taylor::new(tol).uncompensated(),
    )];
    for path in SimdPath::ALL {
        if path.available() {
            runs.push((
                format!("lane kernel, {path}"),
                Taylor::new(tol).with_simd(path),
            ));
        } else {
            rsts_io::report_skip(
                "every_stepper_samples_its_own_steps",
                &format!("this CPU has no {path} path"),
            );
        }
    }
    for (what, taylor) in runs {
        let plain = taylor.propagate_grid(&problem(), &grid).unwrap();
        let steps = taylor.propagate_steps(&problem(), &grid, K).unwrap();
        assert_same_steps(&what, &plain, &steps, &grid);
    }
    // K is checked; a grid of one sample takes no step.
    let taylor = Taylor::new(tol);
    assert!(taylor.propagate_steps(&problem(), &grid, 0).is_err());
    let one = OutputGrid::new(5.0, 1).unwrap();
    assert_eq!(
        taylor.propagate_steps(&problem(), &one, K).unwrap().steps(),
        0
    );
}
