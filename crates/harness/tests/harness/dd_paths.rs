//! The two builds of the double-double state (FMA instructions, chosen at run time, and the
//! portable build for any x86-64) give the same bits: every double-double value and every
//! correctly rounded f64 row, in the nine cameras of a = 1, b = 0.5 and within 1e-9 of Σ, at
//! random times up to 1e9. Skipped (with a message) on a CPU without FMA, where only the
//! portable build runs.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rug::Float;

use rsts_closed_form::{BatchPath, DdPath, ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rsts_harness::rounded_reference::DdReference;
use rsts_harness::Case;

/// The reference of a case in double-double, calibrated against MPFR at 164 bits.
fn reference(m: f64, h: f64) -> DdReference {
    let case = {
        let mut c = Case::default_i_plus();
        c.motion.m = rsts_closed_form::Decimal::from_f64(m).unwrap();
        c.motion.h = rsts_closed_form::Decimal::from_f64(h).unwrap();
        c.motion.phase1 = rsts_closed_form::Decimal::from_f64(0.7).unwrap();
        c.motion.phase2 = rsts_closed_form::Decimal::from_f64(2.1).unwrap();
        c
    };
    let f = |x: f64| Float::with_val(164, x);
    let choice = TorusChoice {
        torus: 0,
        phase1: case.motion.phase1.to_f64(),
        phase2: case.motion.phase2.to_f64(),
    };
    let mp = ExplicitMotion::new_until(
        f(case.motion.a.to_f64()),
        f(case.motion.b.to_f64()),
        f(m),
        f(h),
        choice,
        1e9,
    )
    .unwrap();
    DdReference::new(&case, 1e9, |t| {
        let s = mp.at(&f(t));
        let v = [&s.omega, &s.alpha, &s.beta];
        std::array::from_fn(|k| v[k / 3][k % 3].clone())
    })
    .unwrap()
}

#[test]
fn fma_and_portable_double_double_give_the_same_bits() {
    assert!(DdPath::Portable.available());
    if !DdPath::Fma.available() {
        rsts_io::report_skip(
            "fma_and_portable_double_double_give_the_same_bits",
            "this CPU has no FMA: only the portable build runs",
        );
        return;
    }
    let mut points: Vec<(f64, f64)> = EXAMPLE_POINTS_A1_B05
        .iter()
        .map(|(_, m, h)| (*m, *h))
        .collect();
    points.push((0.0, 1.0 - 1e-9));
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut rows = 0;
    for (m, h) in points {
        let dd = reference(m, h);
        for k in 0..4000 {
            let t = match k % 3 {
                0 => rng.gen_range(0.0..1e9),
                1 => rng.gen_range(-1e3..1e3),
                _ => 1e9 * rng.gen::<f64>().powi(8),
            };
            let fma = dd.values_on(DdPath::Fma, t).unwrap();
            let portable = dd.values_on(DdPath::Portable, t).unwrap();
            let bits = |v: &[_; 9]| {
                v.map(|x: rsts_dynamics::scalar::DoubleDouble| (x.hi.to_bits(), x.lo.to_bits()))
            };
            assert_eq!(bits(&fma), bits(&portable), "m = {m}, h = {h}, t = {t:e}");
            let (a, b) = (
                dd.rounded_on(DdPath::Fma, t).unwrap(),
                dd.rounded_on(DdPath::Portable, t).unwrap(),
            );
            assert_eq!(
                a.map(|r| r.map(f64::to_bits)),
                b.map(|r| r.map(f64::to_bits))
            );
            // The default path is the FMA one here.
            assert_eq!(dd.rounded(t), a);
            rows += usize::from(a.is_some());
        }
    }
    assert!(rows > 39_000, "{rows} rows decided in double-double");
}

/// `DdReference::states` (four samples at once, on AVX2 + FMA where the CPU has them, and the
/// portable build) is `DdReference::state` of each time bit for bit, for the batch sizes of
/// check's chunks (64) and a remainder.
#[test]
fn batches_of_states_are_the_state_of_each_time() {
    let bits = |s: &rsts_dynamics::State<rsts_dynamics::scalar::DoubleDouble>| {
        s.to_array().map(|x| (x.hi.to_bits(), x.lo.to_bits()))
    };
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let mut avx2 = false;
    for (_, m, h) in EXAMPLE_POINTS_A1_B05.iter().take(3) {
        let dd = reference(*m, *h);
        let ts: Vec<f64> = (0..64 * 20 + 3).map(|_| rng.gen_range(-1e3..1e6)).collect();
        for path in [BatchPath::Portable, BatchPath::Avx2Fma] {
            let Some(states) = dd.states_on(path, &ts) else {
                continue;
            };
            avx2 |= path == BatchPath::Avx2Fma;
            for (s, t) in states.iter().zip(&ts) {
                assert_eq!(bits(s), bits(&dd.state(*t)), "{path:?} t = {t:e}");
            }
        }
        assert_eq!(dd.states(&ts).len(), ts.len());
    }
    if !avx2 {
        rsts_io::report_skip(
            "batches_of_states_are_the_state_of_each_time (AVX2 + FMA build)",
            "this CPU lacks AVX2 or FMA",
        );
    }
}
