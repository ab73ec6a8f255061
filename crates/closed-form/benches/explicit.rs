//! Time per closed-form state in f64, double-double and at 30, 100 and 1000 digits, at t = 1, 1e3, 1e6 and 1.5e9
//! (the cost must not grow with t: the phase is reduced modulo the period).
//!
//!     cargo bench -p rsts-closed-form --bench explicit

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, TorusChoice};
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

fn states(c: &mut Criterion) {
    bench_in::<f64>(c, "f64", 53);
    bench_in::<DoubleDouble>(c, "double-double", 106);
    for digits in [30, 100, 1000] {
        bench_in::<Float>(c, &format!("{digits}-digits"), bits_for_digits(digits));
    }
}

criterion_group!(benches, states);
criterion_main!(benches);
