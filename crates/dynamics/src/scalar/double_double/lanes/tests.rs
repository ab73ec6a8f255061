//! Each lane of [`DoubleDouble4`] is the scalar [`DoubleDouble`] operation bit for bit, on the
//! AVX2 + FMA build where the CPU has it and on the portable build.

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

type Dd = DoubleDouble;

/// A random double-double: hi of either sign over 2⁻⁶⁰…2⁶⁰, a full lo.
fn random(rng: &mut ChaCha8Rng) -> Dd {
    let hi = 2f64.powf(rng.gen_range(-60.0..60.0)) * if rng.gen_bool(0.5) { -1.0 } else { 1.0 };
    let ulp = 2f64.powi(hi.abs().log2().floor() as i32 - 52);
    Dd::new(hi, rng.gen_range(-0.49..0.49) * ulp)
}

/// Phases in turns over [0, 1) that hit every sixteenth, its edges and the quadrants.
fn random_turns(rng: &mut ChaCha8Rng) -> Dd {
    let x = match rng.gen_range(0..3) {
        0 => rng.gen_range(0.0..1.0),
        1 => f64::from(rng.gen_range(0..64u32)) / 64.0,
        _ => f64::from(rng.gen_range(0..32u32)) / 32.0 + rng.gen_range(-1e-9..1e-9),
    };
    let x = x.abs();
    Dd::new(x, rng.gen_range(-0.49..0.49) * f64::EPSILON * x / 2.0)
}

/// The bits of each lane.
fn bits(x: &DoubleDouble4) -> [(u64, u64); LANES] {
    x.lanes().map(|d| (d.hi.to_bits(), d.lo.to_bits()))
}

/// Every operation of four random lanes against the scalar one; the number of lanes compared.
#[inline(always)]
fn compare(seed: u64) -> usize {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut compared = 0;
    for _ in 0..3000 {
        let a: [Dd; LANES] = std::array::from_fn(|_| random(&mut rng));
        let b: [Dd; LANES] = std::array::from_fn(|_| random(&mut rng));
        let phi: [Dd; LANES] = std::array::from_fn(|_| random_turns(&mut rng));
        let (a4, b4, phi4) = (
            DoubleDouble4::from_lanes(a),
            DoubleDouble4::from_lanes(b),
            DoubleDouble4::from_lanes(phi),
        );
        let (s4, c4) = phi4.sin_cos_turns();
        let got = [
            a4 + b4,
            a4 - b4,
            a4 * b4,
            a4 / b4,
            a4.sqr(),
            Real::abs(&a4).add_same_sign(&Real::abs(&b4)),
            Real::sqrt(&Real::abs(&a4)),
            Real::abs(&a4),
            s4,
            c4,
        ];
        for i in 0..LANES {
            let (x, y) = (a[i], b[i]);
            let (s, c) = phi[i].sin_cos_turns();
            let want = [
                x + y,
                x - y,
                x * y,
                x / y,
                x.sqr(),
                Real::abs(&x).add_same_sign(&Real::abs(&y)),
                Real::sqrt(&Real::abs(&x)),
                Real::abs(&x),
                s,
                c,
            ];
            for (op, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(
                    bits(g)[i],
                    (w.hi.to_bits(), w.lo.to_bits()),
                    "operation {op}, lane {i}: {:?} vs {w:?}",
                    g.lane(i)
                );
                compared += 1;
            }
        }
    }
    compared
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn compare_avx2(seed: u64) -> usize {
    compare(seed)
}

#[test]
fn lanes_are_the_scalar_operations_bit_for_bit() {
    assert_eq!(compare(7), 3000 * LANES * 10);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        assert_eq!(unsafe { compare_avx2(8) }, 3000 * LANES * 10);
        return;
    }
    rsts_io::report_skip(
        "lanes_are_the_scalar_operations_bit_for_bit (AVX2 + FMA build)",
        "this CPU lacks AVX2 or FMA",
    );
}

/// A lane of zero, of a negative or a non-finite number takes the scalar special cases.
#[test]
fn special_lanes_take_the_scalar_special_cases() {
    let x = [
        Dd::ZERO,
        Dd::from_f64_exact(-2.0),
        Dd::from_f64_exact(f64::INFINITY),
        Dd::new(2.0, 1e-17),
    ];
    let r = Real::sqrt(&DoubleDouble4::from_lanes(x));
    for (i, x) in x.iter().enumerate() {
        let (g, w) = (r.lane(i), Real::sqrt(x));
        assert!(g == w || (g.hi.is_nan() && w.hi.is_nan()), "{g:?} vs {w:?}");
    }
    let turns = DoubleDouble4::from_lanes([Dd::from_f64_exact(f64::NAN), x[3], x[3], x[3]]);
    let (s, _) = turns.sin_cos_turns();
    assert!(s.hi[0].is_nan() && s.lane(1) == x[3].sin_cos_turns().0);
}
