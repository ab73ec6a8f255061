//! The batch of states is the scalar path's bit for bit, on both builds.

use super::*;
use crate::TorusChoice;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The bits of ω, α, β.
fn bits(b: &BodyState<DoubleDouble>) -> Vec<(u64, u64)> {
    b.omega
        .iter()
        .chain(&b.alpha)
        .chain(&b.beta)
        .map(|x| (x.hi.to_bits(), x.lo.to_bits()))
        .collect()
}

/// Random times of a motion: uniform up to 1e9, small of either sign, skewed towards 0, the
/// first turning points of both variables (a phase at a zero of sin: the Landen branch) and
/// times beyond the clock's range, shuffled so that such lanes sit among ordinary ones.
fn times(dd: &ExplicitMotion<DoubleDouble>, rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    let mut ts: Vec<f64> = (0..n)
        .map(|k| match k % 3 {
            0 => rng.gen_range(0.0..1e9),
            1 => rng.gen_range(-1e3..1e3),
            _ => 1e9 * rng.gen::<f64>().powi(8),
        })
        .collect();
    let d = DoubleDouble::from_f64_exact;
    for i in 0..2 {
        let turns = dd.turning_times(i, &d(0.0), &d(50.0), 100).unwrap();
        ts.extend(turns.iter().take(6).map(|(t, _)| t.hi));
    }
    ts.extend([0.0, 0.0, 2e12, -3e12, 5e12]);
    ts.shuffle(rng);
    // And a group of four that the scalar path takes alone, and a remainder of three.
    ts.extend([2e12, 0.0, -2e12, 0.0, 1.0, 2.0, 3.0]);
    ts
}

/// Over the nine cameras of a = 1, b = 0.5 (two tori and phases each), 108 000 times in all:
/// every state of the batch (AVX2 + FMA where the CPU has it, and the portable build) is the
/// scalar [`ExplicitMotion::body_at_f64`]'s bit for bit.
#[test]
fn batch_of_four_is_the_scalar_state_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let (mut compared, mut avx2) = (0, false);
    for (camera, m, h) in crate::EXAMPLE_POINTS_A1_B05 {
        for choice in [
            TorusChoice::default(),
            TorusChoice {
                torus: 0,
                phase1: 0.7,
                phase2: 2.1,
            },
        ] {
            let d = DoubleDouble::from_f64_exact;
            let dd = ExplicitMotion::new_until(d(1.0), d(0.5), d(m), d(h), choice, 1e13).unwrap();
            let ts = times(&dd, &mut rng, 6000);
            let scalar: Vec<_> = ts.iter().map(|&t| dd.body_at_f64(t)).collect();
            for path in [BatchPath::Portable, BatchPath::Avx2Fma] {
                let mut batch = Vec::new();
                if !dd.bodies_at_f64_on(path, &ts, &mut batch) {
                    continue;
                }
                avx2 |= path == BatchPath::Avx2Fma;
                assert_eq!(batch.len(), ts.len());
                for (k, (a, b)) in batch.iter().zip(&scalar).enumerate() {
                    assert_eq!(
                        bits(a),
                        bits(b),
                        "{camera:?} {path:?} t = {:e} (lane {})",
                        ts[k],
                        k % LANES
                    );
                }
                compared += usize::from(path == BatchPath::Portable) * ts.len();
            }
        }
    }
    assert!(compared >= 100_000, "{compared}");
    if !avx2 {
        rsts_io::report_skip(
            "batch_of_four_is_the_scalar_state_bit_for_bit (AVX2 + FMA build)",
            "this CPU lacks AVX2 or FMA",
        );
    }
}
