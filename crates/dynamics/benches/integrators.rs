//! Wall time of the integrators over T = 100 for a = 1, b = 0.5 from one fixed valid state:
//! `cargo bench -p rsts-dynamics --bench integrators`. Before timing, one run of each method
//! prints its steps, rhs-equivalent evaluations and its error against a 60-digit Taylor run
//! (at the 101 grid times), so the timings can be read against accuracy.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use rsts_dynamics::integrators::{
    MethodConfig, MethodName, OutputGrid, Problem, Solution, Tolerances,
};
use rsts_dynamics::{Fields, State};
use rug::Float;

const T_END: f64 = 100.0;
const SAMPLES: usize = 101;

fn problem() -> Problem<f64> {
    // A valid state: α = e₁ rotated by 0.3 about e₃, β ⟂ α, |α| = |β| = 1 to round-off.
    let (s, c) = 0.3f64.sin_cos();
    Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: State {
            omega: [0.4, -0.7, 1.1],
            alpha: [c, s, 0.0],
            beta: [-s, c, 0.0],
        },
    }
}

/// (label, method, tolerance, digits of taylor-mp)
const CASES: [(&str, MethodName, f64, Option<u32>); 5] = [
    ("taylor-f64 tol 1e-15", MethodName::TaylorF64, 1e-15, None),
    ("taylor-dd tol 1e-30", MethodName::TaylorDd, 1e-30, None),
    (
        "taylor-mp 30 digits tol 1e-30",
        MethodName::TaylorMp,
        1e-30,
        Some(30),
    ),
    (
        "taylor-mp 60 digits tol 1e-60",
        MethodName::TaylorMp,
        1e-60,
        Some(60),
    ),
    ("dop853 tol 1e-13", MethodName::Dop853, 1e-13, None),
];

fn config(method: MethodName, tol: f64, digits: Option<u32>) -> MethodConfig {
    let c = MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap();
    match digits {
        Some(d) => c.with_digits(d).unwrap(),
        None => c,
    }
}

fn high(method: MethodName, tol: f64, digits: Option<u32>) -> Solution<Float> {
    let p = problem();
    let p = Problem {
        fields: p.fields.to_scalar(300),
        initial: p.initial.to_scalar(300),
    };
    config(method, tol, digits)
        .propagate_mp(&p, &OutputGrid::new(T_END, SAMPLES).unwrap())
        .unwrap()
}

fn max_diff(a: &Solution<Float>, b: &Solution<Float>) -> f64 {
    let mut worst: f64 = 0.0;
    for (x, y) in a.states.iter().zip(&b.states) {
        for (u, v) in x.to_array().iter().zip(y.to_array().iter()) {
            worst = worst.max(Float::with_val(300, u - v).abs().to_f64());
        }
    }
    worst
}

fn integrators(c: &mut Criterion) {
    let reference = high(MethodName::TaylorMp, 1e-75, Some(80));
    for (label, method, tol, digits) in CASES {
        let sol = high(method, tol, digits);
        eprintln!(
            "{label}: steps {}, rhs evals {}, max error vs 80-digit run {:.1e}",
            sol.stats.accepted_steps,
            sol.stats.rhs_evals,
            max_diff(&reference, &sol)
        );
    }
    let p = problem();
    let grid = OutputGrid::new(T_END, SAMPLES).unwrap();
    let mut group = c.benchmark_group("T=100, a=1, b=0.5");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (label, method, tol, digits) in CASES {
        let cfg = config(method, tol, digits);
        group.bench_function(label, |b| b.iter(|| cfg.propagate_f64(&p, &grid).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, integrators);
criterion_main!(benches);
