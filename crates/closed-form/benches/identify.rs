//! Time to identify one state (state → m, h, camera, torus, ψ₁, ψ₂, distance from N) in f64 and
//! at 30 and 50 digits, in camera I+ (one torus) and V (four tori, torus 3), and the parts: the
//! distance from N alone, the projection on N near a known motion (what the harness does per
//! sample) and one closed-form motion built (the identification builds a few).
//!
//!     cargo bench -p rsts-closed-form --bench identify

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rsts_closed_form::manifold::{distance, identify, Projector};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Fields, State};
use rug::Float;

fn bench_in<T: Scalar>(c: &mut Criterion, label: &str, bits: u32) {
    let x = |v: f64| T::from_f64(v, bits);
    let mut group = c.benchmark_group(format!("identify/{label}"));
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(2));
    for (camera, m, h, torus) in [("I+", 0.3, -0.375, 0), ("V", -0.7092, 1.5643, 3)] {
        let choice = TorusChoice {
            torus,
            phase1: 0.7,
            phase2: 2.1,
        };
        let motion = ExplicitMotion::new(x(1.0), x(0.5), x(m), x(h), choice).unwrap();
        let e = motion.at(&x(1.3));
        let state = State {
            omega: e.omega,
            alpha: e.alpha,
            beta: e.beta,
        };
        let fields = Fields {
            a: x(1.0),
            b: x(0.5),
        };
        group.bench_function(format!("{camera}/identify"), |bench| {
            bench.iter(|| identify(black_box(&fields.a), &fields.b, black_box(&state)).unwrap())
        });
        group.bench_function(format!("{camera}/distance"), |bench| {
            bench.iter(|| distance(black_box(&fields), black_box(&state)))
        });
        let projector = Projector::new(&motion).unwrap();
        let target = state.to_array();
        let guess = [x(0.71), x(2.09)];
        group.bench_function(format!("{camera}/project"), |bench| {
            bench.iter(|| projector.project(black_box(&target), &guess).unwrap())
        });
        group.bench_function(format!("{camera}/motion"), |bench| {
            bench.iter(|| {
                ExplicitMotion::new(x(1.0), x(0.5), black_box(x(m)), x(h), choice).unwrap()
            })
        });
    }
    group.finish();
}

fn all(c: &mut Criterion) {
    bench_in::<f64>(c, "f64", 53);
    for digits in [30, 50] {
        bench_in::<Float>(c, &format!("{digits}-digits"), bits_for_digits(digits));
    }
}

criterion_group!(benches, all);
criterion_main!(benches);
