//! The f64 reference from the double-double closed form is today's MPFR reference rounded to
//! f64, bit for bit: every camera of a = 1, b = 0.5, the seven regimes within 1e-9 of a curve of
//! Σ, a field pair far from b = a/2, at random times up to 1e9 (uniform, integers, near 0).
//!
//! Rows: 120 000 by default (about 7 s in release on two loaded cores, the MPFR rows being the
//! cost); `RSTS_ROUNDED_SAMPLES=1000000` runs the 10⁶ of docs/benchmarks.md. The state columns
//! must be equal bit for bit, H, K, G (constants of N rounded once) within an ulp of MPFR's.
//! The test has teeth: the f64 closed form (no double-double, no Ziv test) differs from the
//! MPFR state on nearly every row, and it is asserted to.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use rsts_closed_form::{ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rsts_harness::reference::ReferenceTable;
use rsts_harness::Case;

fn cases() -> Vec<(String, Case)> {
    let case = |a: f64, b: f64, m: f64, h: f64, torus: usize| {
        Case::binary([a, b, m, h], torus, [0.7, 2.1], 1.0, 1).unwrap()
    };
    let mut out: Vec<(String, Case)> = EXAMPLE_POINTS_A1_B05
        .iter()
        .map(|(camera, m, h)| (format!("{camera:?}"), case(1.0, 0.5, *m, *h, 0)))
        .collect();
    // Within 1e-9 of each curve of Σ (as tests/closed_form/hard_regimes.rs of the closed form).
    let (r2, p2, d) = (0.75, 1.25, 1e-9);
    let hyperbola = |m: f64| -(1.0 + 2.0 * p2 * m * m) / (2.0 * m);
    for (what, m, h) in [
        ("h = r²m − 2a", 1.0, r2 - 2.0 + d),
        ("h = −r²m − 2b", 0.0, -1.0 + d),
        ("hyperbola", -1.0, hyperbola(-1.0) - d),
        ("h = r²m + 2a, below", 0.0, 2.0 - d),
        ("h = r²m + 2a, above", 0.0, 2.0 + d),
        ("h = −r²m + 2b, below", 0.0, 1.0 - d),
        ("h = −r²m + 2b, above", 0.0, 1.0 + d),
    ] {
        out.push((what.into(), case(1.0, 0.5, m, h, 0)));
    }
    out.push(("b = 0.999, m < 0".into(), case(1.0, 0.999, -0.5, 1.5, 0)));
    out.push((
        "camera V, torus 3".into(),
        case(1.0, 0.5, -0.7092, 1.5643, 3),
    ));
    out
}

fn random_time(rng: &mut ChaCha8Rng, k: usize) -> f64 {
    match k % 4 {
        0 => rng.gen_range(0.0..1e9),
        1 => rng.gen_range(-1e3..1e3),
        2 => rng.gen_range(0..1_000_000_000u64) as f64,
        _ => 1e9 * rng.gen::<f64>().powi(8),
    }
}

#[test]
fn double_double_rows_are_the_mpfr_rows_rounded_bit_for_bit() {
    let total: usize = std::env::var("RSTS_ROUNDED_SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(120_000);
    let cases = cases();
    let per_case = total.div_ceil(cases.len());
    let mut fallbacks = 0;
    let mut naive_misses = 0;
    for (c, (what, case)) in cases.iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(c as u64);
        let times: Vec<f64> = (0..per_case).map(|k| random_time(&mut rng, k)).collect();
        let table = ReferenceTable::new(case, &[1e9], None).unwrap();
        assert!(table.has_dd(), "{what}: no double-double motion");
        // The f64 closed form, for the teeth of the test.
        let choice = TorusChoice {
            torus: case.motion.torus,
            phase1: case.motion.phase1.to_f64(),
            phase2: case.motion.phase2.to_f64(),
        };
        let f64_motion = ExplicitMotion::new(
            case.motion.a.to_f64(),
            case.motion.b.to_f64(),
            case.motion.m.to_f64(),
            case.motion.h.to_f64(),
            choice,
        )
        .unwrap();
        let (misses, falls): (Vec<usize>, Vec<usize>) = times
            .par_iter()
            .map(|&t| {
                let mpfr = table.row(t).unwrap();
                let fast = table.row_f64(t).unwrap();
                for k in 0..10 {
                    assert_eq!(
                        fast[k].to_bits(),
                        mpfr[k].to_f64().to_bits(),
                        "{what}: t = {t:e}, column {k}: {:e} vs {:e}",
                        fast[k],
                        mpfr[k].to_f64()
                    );
                }
                // H, K, G: the constants of N rounded once; MPFR's carry noise in the last bits
                // (a tie may round either way, a zero comes out as ~1e-100): one ulp apart at
                // most.
                for k in 10..13 {
                    let m = mpfr[k].to_f64();
                    let ulp = f64::EPSILON * m.abs().max(fast[k].abs()) + 1e-40;
                    assert!(
                        (fast[k] - m).abs() <= ulp,
                        "{what}: column {k}: {} vs {m}",
                        fast[k]
                    );
                }
                let e = f64_motion.at(&t);
                let naive = e.omega.iter().chain(&e.alpha).chain(&e.beta);
                let miss = naive
                    .zip(&mpfr[1..10])
                    .any(|(x, y)| x.to_bits() != y.to_f64().to_bits());
                let fell = table.dd_rounded(t).is_none();
                (usize::from(miss), usize::from(fell))
            })
            .unzip();
        naive_misses += misses.iter().sum::<usize>();
        fallbacks += falls.iter().sum::<usize>();
    }
    let n = per_case * cases.len();
    eprintln!(
        "{n} rows equal; {fallbacks} went to MPFR; the f64 closed form differs on {naive_misses}"
    );
    assert!(naive_misses > n / 10, "{naive_misses} of {n}");
    // Ziv's test decides nearly every row in double-double (else the fast path is not used).
    assert!(fallbacks * 1000 < n, "{fallbacks} of {n} rows went to MPFR");
}
