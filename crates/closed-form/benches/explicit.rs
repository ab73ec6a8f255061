//! Time per closed-form state in f64, double-double and at 30, 100 and 1000 digits, at t = 1, 1e3, 1e6 and 1.5e9
//! (the cost must not grow with t: the phase is reduced modulo the period). In double-double
//! also ω, α, β alone at an f64 time (the state of a reference row) on each build: `body-fma/`
//! (FMA instructions, skipped on a CPU without FMA) and `body-portable/`.
//!
//!     cargo bench -p rsts-closed-form --bench explicit

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{DdPath, ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::{bits_for_digits, DoubleDouble};
use rug::Float;

const CHOICE: TorusChoice = TorusChoice {
    torus: 0,
    phase1: 0.7,
    phase2: 2.1,
};

fn bench_in<T: Scalar>(c: &mut Criterion, label: &str, bits: u32) {
    let x = |v: f64| T::from_f64(v, bits);
    let motion = ExplicitMotion::new(x(1.0), x(0.5), x(0.3), x(-0.375), CHOICE).unwrap();
    let mut group = c.benchmark_group(format!("state/{label}"));
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(2));
    for t in [1.0, 1e3, 1e6, 1.5e9] {
        let tt = x(t);
        group.bench_with_input(
            BenchmarkId::from_parameter(format!("t={t:e}")),
            &tt,
            |b, tt| b.iter(|| black_box(motion.at(black_box(tt)))),
        );
    }
    group.finish();
}

/// ω, α, β in double-double at an f64 time on each build the CPU has.
fn bench_dd_body(c: &mut Criterion) {
    let x = DoubleDouble::from_f64_exact;
    let motion = ExplicitMotion::new(x(1.0), x(0.5), x(0.3), x(-0.375), CHOICE).unwrap();
    let mut group = c.benchmark_group("state/double-double");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(2));
    for (name, path) in [
        ("body-fma", DdPath::Fma),
        ("body-portable", DdPath::Portable),
    ] {
        if !path.available() {
            eprintln!("{name}: this CPU lacks the path, skipped");
            continue;
        }
        for t in [1.0, 1e3, 1e6, 1.5e9] {
            group.bench_with_input(BenchmarkId::new(name, format!("t={t:e}")), &t, |b, t| {
                b.iter(|| black_box(motion.body_at_f64_on(path, black_box(*t))))
            });
        }
    }
    group.finish();
}

fn states(c: &mut Criterion) {
    bench_in::<f64>(c, "f64", 53);
    bench_in::<DoubleDouble>(c, "double-double", 106);
    bench_dd_body(c);
    for digits in [30, 100, 1000] {
        bench_in::<Float>(c, &format!("{digits}-digits"), bits_for_digits(digits));
    }
}

criterion_group!(benches, states);
criterion_main!(benches);
