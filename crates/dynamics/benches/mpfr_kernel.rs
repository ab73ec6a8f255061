//! The MPFR Taylor coefficient kernels side by side: one full Taylor recursion x₀ → x₁ … xₚ of
//! the Euler–Poisson equations (a = 1, b = 0.5, the state of the integrators bench), as
//! taylor-mp computes it once per step, with the limb-level kernel (`integrators/taylor/mp.rs`)
//! and with the generic path (every product and partial sum rounded), at 30, 90 and 300 digits
//! with the Jorba–Zou order of the tolerance 10^-(digits − 20):
//!
//!     cargo bench -p rsts-dynamics --bench mpfr_kernel
//!
//! The recursion costs 14·p(p+1)/2 multiply-adds; divide the time by that for ns per product.

use std::time::Duration;

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use rsts_dynamics::equations::CauchyScratch;
use rsts_dynamics::integrators::{MpfrKernel, Taylor};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Fields, VectorField};
use rug::Float;

/// x₀ and the recursion's rows, filled by `recursion`.
fn start(bits: u32, order: usize) -> Vec<[Float; 9]> {
    let (s, c) = 0.3f64.sin_cos();
    let x0 = [0.4, -0.7, 1.1, c, s, 0.0, -s, c, 0.0];
    let mut series = vec![std::array::from_fn(|_| Float::new(bits)); order + 1];
    series[0] = std::array::from_fn(|i| Float::with_val(bits, x0[i]));
    series
}

/// x_{n+1} = f(x)ₙ/(n + 1) for n < order, with `coefficient` computing f(x)ₙ.
fn recursion(
    series: &mut [[Float; 9]],
    out: &mut [Float; 9],
    mut coefficient: impl FnMut(&[[Float; 9]], usize, &mut [Float; 9]),
) {
    for n in 0..series.len() - 1 {
        coefficient(series, n, out);
        for (s, o) in series[n + 1].iter_mut().zip(out.iter()) {
            s.clone_from(o);
            *s /= (n + 1) as u32;
        }
    }
}

fn kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("mpfr Taylor recursion");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for digits in [30u32, 90, 150, 200, 300] {
        let bits = bits_for_digits(digits);
        let order = Taylor::order_for(10f64.powi(-(digits as i32 - 20)));
        let fields = Fields {
            a: Float::with_val(bits, 1),
            b: Float::with_val(bits, 0.5),
        };
        let field = VectorField::new(&fields);
        let mut series = start(bits, order);
        let mut out: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
        let label = format!("{digits} digits, order {order}");
        let mut kernel = MpfrKernel::new(&field, bits);
        group.bench_function(BenchmarkId::new("limbs", &label), |b| {
            b.iter(|| {
                recursion(&mut series, &mut out, |s, n, o| kernel.coefficient(s, n, o));
                black_box(&series[order]);
            })
        });
        let mut scratch = CauchyScratch::new(&Float::new(bits));
        group.bench_function(BenchmarkId::new("generic", &label), |b| {
            b.iter(|| {
                recursion(&mut series, &mut out, |s, n, o| {
                    field.taylor_coefficient_orders(s, n, o, &mut scratch)
                });
                black_box(&series[order]);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
