//! `rsts explicit`'s f64 rows (ω, α, β, γ, Ω) from the double-double closed form are the MPFR
//! rows rounded to f64, bit for bit: 300 random times (t up to 1e6, near 0, integers) in camera
//! I+, camera V's fourth torus (m < 0) and within 1e-9 of a curve of Σ. Teeth: the plain f64
//! closed form (what `explicit` printed before) differs from the MPFR rows on some of them.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_harness::rounded_explicit::RoundedExplicit;
use rsts_harness::Case;

#[test]
fn explicit_f64_rows_are_the_mpfr_rows_rounded() {
    let case = |m: f64, h: f64, torus: usize| {
        Case::binary([1.0, 0.5, m, h], torus, [0.4, 1.9], 1.0, 1).unwrap()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut f64_differs = 0;
    for c in [
        case(0.3, -0.375, 0),
        case(-0.7092, 1.5643, 3),
        case(0.0, 1.0 - 1e-9, 0),
    ] {
        let t_max = 1e6;
        let rounded = RoundedExplicit::new(&c, t_max).unwrap();
        let plain = ExplicitMotion::new_until(
            c.motion.a.to_f64(),
            c.motion.b.to_f64(),
            c.motion.m.to_f64(),
            c.motion.h.to_f64(),
            TorusChoice {
                torus: c.motion.torus,
                phase1: c.motion.phase1.to_f64(),
                phase2: c.motion.phase2.to_f64(),
            },
            t_max,
        )
        .unwrap();
        for k in 0..100 {
            let t = match k % 3 {
                0 => rng.gen_range(0.0..t_max),
                1 => rng.gen_range(-10.0..10.0),
                _ => rng.gen_range(0..100_000) as f64,
            };
            let fast = rounded.row(t);
            let exact = rounded.row_mpfr(t);
            assert_eq!(
                fast.map(f64::to_bits),
                exact.map(f64::to_bits),
                "{c:?} at t = {t}: {fast:?} vs {exact:?}"
            );
            let s = plain.at(&t);
            let vs = [&s.omega, &s.alpha, &s.beta, &s.gamma, &s.omega_fixed];
            let p: [f64; 15] = std::array::from_fn(|j| vs[j / 3][j % 3]);
            if p != exact {
                f64_differs += 1;
            }
        }
    }
    assert!(
        f64_differs > 30,
        "the plain f64 closed form differs on {f64_differs} rows only"
    );
}
