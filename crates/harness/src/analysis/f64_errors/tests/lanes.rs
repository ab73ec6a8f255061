//! The kernel in four lanes gives each sample the numbers of the kernel in one lane, bit for
//! bit, on the AVX2 + FMA build and on the portable one.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::BatchPath;

use super::super::*;
use super::{dd, dd_measure, fields, measured_bits, on_constraints, sample};
use crate::analysis::f64_samples::{evaluated, measure_all_on, measure_portable};
use crate::analysis::Evaluated;

/// A sample of one of the kinds the batch must handle alike: near its exact state (errors
/// 1e-18 to 1e-2: the small-angle series), on the constraints (errors up to 1: large angles,
/// the general arctangent), unrelated (angles up to π), equal to its exact state (no error at
/// all), or with a NaN or an infinity in the data or in the exact state.
fn any_sample(rng: &mut ChaCha8Rng) -> ([f64; 9], State<Dd>) {
    let kind = rng.gen_range(0..20);
    match kind {
        0..=9 => sample(rng, [0.1, 1.0, 3.0][kind % 3]),
        10..=13 => on_constraints(rng),
        14 | 15 => {
            let (x, _) = sample(rng, 1.0);
            let (_, exact) = sample(rng, 1.0);
            (x, exact)
        }
        16 => {
            let (_, exact) = sample(rng, 1.0);
            (exact.to_array().map(|v| v.hi), exact)
        }
        _ => {
            let (mut x, exact) = sample(rng, 1.0);
            let mut y = exact.to_array();
            let odd = [f64::NAN, f64::INFINITY, -f64::INFINITY][rng.gen_range(0..3)];
            let k = rng.gen_range(0..9);
            if kind == 17 {
                x[k] = odd;
            } else {
                y[k] = Dd::from_f64_exact(odd);
            }
            (x, State::from_slice(&y))
        }
    }
}

/// The bits of what is compared ([`measured_bits`]).
fn bits(ev: &Evaluated) -> [u64; 9] {
    measured_bits(&ev.errors, ev.digits)
}

/// Batches of 1 to 70 samples (groups of four and a remainder) of every kind mixed in a
/// group, 120 000 samples in all: each sample's errors and digits in four lanes are those of
/// the kernel in one lane, bit for bit, on the AVX2 build (skipped on a CPU without it) and
/// on the portable one. Returns the number of samples compared on `path`.
fn compare(path: BatchPath, seed: u64) -> usize {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut compared = 0;
    let mut out = Vec::new();
    while compared < 120_000 {
        let fields = fields(&mut rng);
        let (_, start) = sample(&mut rng, 1.0);
        let m = dd_measure(&mut rng, fields, &start);
        let len = rng.gen_range(1..=70);
        let (xs, exact): (Vec<[f64; 9]>, Vec<State<Dd>>) =
            (0..len).map(|_| any_sample(&mut rng)).unzip();
        let ratio = [1.0, 1e-3][compared % 2];
        out.clear();
        if !measure_all_on(path, &m, &exact, &xs, ratio, false, &mut out) {
            return 0;
        }
        assert_eq!(out.len(), len);
        for (n, ((ev, x), e)) in out.iter().zip(&xs).zip(&exact).enumerate() {
            let one = evaluated(measure_portable(&m, e, x, ratio, false));
            assert_eq!(
                bits(ev),
                bits(&one),
                "{path:?}, sample {n} of {len}: x = {x:?}\n{:?}\n{:?}",
                ev.errors,
                one.errors
            );
        }
        compared += len;
    }
    compared
}

#[test]
fn four_lanes_give_the_bits_of_one_lane_on_the_portable_build() {
    assert!(compare(BatchPath::Portable, 31) >= 100_000);
}

#[test]
fn four_lanes_give_the_bits_of_one_lane_on_the_avx2_build() {
    if compare(BatchPath::Avx2Fma, 3131) == 0 {
        rsts_io::report_skip(
            "four_lanes_give_the_bits_of_one_lane_on_the_avx2_build",
            "this CPU has no AVX2 and FMA: only the portable build runs",
        );
    }
}

/// Every lane of a group is its own sample: a group of four different samples and the same
/// samples placed at other lanes (rotated) give each sample the numbers of one lane, and
/// the four lanes differ (a kernel that copied one lane into the others fails).
#[test]
fn each_lane_of_a_group_is_its_own_sample() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let f = fields(&mut rng);
    let n = ManifoldN {
        k: dd(&mut rng, 0.3),
        p2: dd(&mut rng, 1.7),
        r4m: dd(&mut rng, -0.2),
    };
    let i0 = [dd(&mut rng, 0.5), dd(&mut rng, 0.7), dd(&mut rng, 0.9)];
    for _ in 0..1_000 {
        let (x, e): (Vec<[f64; 9]>, Vec<State<Dd>>) = (0..5).map(|_| sample(&mut rng, 1.0)).unzip();
        let got = f64_sample_errors::<4>(&f, &n, &i0, &e[..4], &x[..4], 1.0);
        let rotated = f64_sample_errors::<4>(&f, &n, &i0, &e[1..], &x[1..], 1.0);
        for i in 0..4 {
            let [alone] = f64_sample_errors::<1>(&f, &n, &i0, &e[i..], &x[i..], 1.0);
            assert_eq!(format!("{:?}", got[i]), format!("{:?}", alone));
            if i > 0 {
                assert_eq!(format!("{:?}", got[i]), format!("{:?}", rotated[i - 1]));
            }
            assert_ne!(got[i].0.drift_h, got[(i + 1) % 4].0.drift_h, "lane {i}");
        }
    }
}
