//! Long-run drift of the first integrals H, K, G and of the geometric constraints
//! (|α|² = |β|² = 1, α·β = 0) along numerical solutions.
//!
//! The exact flow conserves all six (tests/dynamics/conservation.rs); a numerical solution drifts by the
//! accumulated global error. Dop853 at rtol = atol = 1e-12 over t = 100 must keep every drift
//! below 1e-9; Dopri5 at 1e-4 must drift measurably more, which shows the bound is not vacuous.
//! The last sample of a run must agree with the same time inside a longer run.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::integrators::{Dop853, Dopri5, OutputGrid, Problem, Propagator, Tolerances};
use rsts_dynamics::{Fields, State};

const T_END: f64 = 100.0;
const SAMPLES: usize = 201;
const BOUND: f64 = 1e-9;

fn random_unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let v: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 {
            return v.map(|x| x / n);
        }
    }
}

/// A random valid problem: a ∈ [0.5, 2], b ∈ [0, a], |ωᵢ| ≤ 1, α, β orthonormal.
fn random_problem(rng: &mut ChaCha8Rng) -> Problem<f64> {
    let a = rng.gen_range(0.5..2.0);
    let b = rng.gen_range(0.0..=a);
    let omega = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
    let alpha = random_unit(rng);
    let c = random_unit(rng);
    let d = c[0] * alpha[0] + c[1] * alpha[1] + c[2] * alpha[2];
    let c: [f64; 3] = std::array::from_fn(|i| c[i] - d * alpha[i]);
    let n = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let beta = c.map(|x| x / n);
    let initial = State { omega, alpha, beta };
    initial.validate().expect("random state is valid");
    Problem {
        fields: Fields::new(a, b).expect("valid fields"),
        initial,
    }
}

fn problems() -> Vec<Problem<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    (0..6).map(|_| random_problem(&mut rng)).collect()
}

/// Largest drift over the run: [H, K, G, constraints].
fn drifts(problem: &Problem<f64>, method: &dyn Propagator<f64>) -> [f64; 4] {
    let grid = OutputGrid::new(T_END, SAMPLES).unwrap();
    let sol = method.propagate_grid(problem, &grid).unwrap();
    assert_eq!(sol.states.len(), SAMPLES);
    for (k, t) in sol.times.iter().enumerate() {
        assert!((t - grid.time(k)).abs() < 1e-9, "sample {k} at t = {t}");
    }
    let i0 = integrals(&problem.fields, &problem.initial);
    let mut d = [0.0f64; 4];
    for s in &sol.states {
        let i = integrals(&problem.fields, s);
        d[0] = d[0].max((i.h - i0.h).abs());
        d[1] = d[1].max((i.k - i0.k).abs());
        d[2] = d[2].max((i.g - i0.g).abs());
        d[3] = d[3].max(s.constraint_error());
    }
    d
}

fn tight() -> Dop853 {
    Dop853::new(Tolerances::new(1e-12, 1e-12).unwrap())
}

fn loose() -> Dopri5 {
    Dopri5::new(Tolerances::new(1e-4, 1e-4).unwrap())
}

#[test]
fn dop853_at_1e_12_keeps_integrals_and_constraints_within_1e_9_over_t_100() {
    for (n, p) in problems().iter().enumerate() {
        let d = drifts(p, &tight());
        for (name, x) in ["H", "K", "G", "constraints"].iter().zip(d) {
            assert!(
                x < BOUND,
                "problem {n}: drift of {name} = {x:e} >= {BOUND:e} (a = {}, b = {}, {:?})",
                p.fields.a,
                p.fields.b,
                p.initial
            );
        }
    }
}

#[test]
fn dopri5_at_1e_4_drifts_measurably_more() {
    for (n, p) in problems().iter().enumerate() {
        let tight = drifts(p, &tight());
        let loose = drifts(p, &loose());
        let worst_tight = tight.iter().copied().fold(0.0, f64::max);
        let worst_loose = loose.iter().copied().fold(0.0, f64::max);
        eprintln!("problem {n}: worst drift tight {worst_tight:.2e}, loose {worst_loose:.2e}");
        // The loose run breaks the bound the tight run keeps, by a wide margin.
        assert!(
            worst_loose > 100.0 * BOUND && worst_loose > 1000.0 * worst_tight,
            "problem {n}: loose drift {loose:?} vs tight {tight:?}"
        );
    }
}

/// Regression: `ode_solvers` used to extrapolate the sample at t = T from an earlier step (see
/// `solver_end` in the adapter); the last sample must match the same time in a longer run.
#[test]
fn last_sample_agrees_with_a_longer_run() {
    let methods: [&dyn Propagator<f64>; 2] = [
        &tight(),
        &Dopri5::new(Tolerances::new(1e-12, 1e-12).unwrap()),
    ];
    for p in problems().iter().take(3) {
        for m in methods {
            let short = m
                .propagate_grid(p, &OutputGrid::new(10.0, 11).unwrap())
                .unwrap();
            let long = m
                .propagate_grid(p, &OutputGrid::new(12.0, 13).unwrap())
                .unwrap();
            let (a, b) = (&short.states[10], &long.states[10]);
            let diff = a
                .to_array()
                .iter()
                .zip(b.to_array())
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(
                diff < 1e-9,
                "{}: state at t = 10 differs by {diff:e} between runs to 10 and to 12",
                m.name()
            );
        }
    }
}
