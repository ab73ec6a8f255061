//! The 100-digit state (the MPFR path: the phase clock without a division, sn and cn without
//! the last dn, the radicals' constant signs applied as signs) is the motion to its working
//! precision: every value of `ExplicitMotion::at` (ω, α, β, γ, Ω, Q′, Q″, ω′, ω″ and the
//! separated coordinates) agrees with the same motion built at 130 digits to 1e-95 of
//! max(1, |value|), at random times up to 1e9 over the nine cameras of a = 1, b = 0.5 and camera
//! V's fourth torus. The check has teeth: the state at t + 1e-92 fails it (a wrong sign of a
//! radical, which both precisions would share, fails the round trips of tests/closed_form/identify.rs).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rug::Float;

use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rsts_dynamics::scalar::bits_for_digits;

fn values(s: &ExplicitState<Float>) -> Vec<&Float> {
    let c = &s.coords;
    let mut out = vec![&c.x, &c.s2, &c.f1, &c.g1, &c.f2, &c.g2];
    for v in [
        &s.omega,
        &s.alpha,
        &s.beta,
        &s.gamma,
        &s.omega_fixed,
        &s.omega_prime,
        &s.omega_second_1,
        &s.omega_second_2,
    ] {
        out.extend(v.iter());
    }
    for m in [&s.q_prime, &s.q_second] {
        out.extend(m.iter().flatten());
    }
    out
}

/// The largest |x − y|/max(1, |y|) over the values of two states.
fn deviation(x: &ExplicitState<Float>, y: &ExplicitState<Float>) -> f64 {
    values(x)
        .into_iter()
        .zip(values(y))
        .map(|(a, b)| {
            let d = Float::with_val(b.prec(), a - b).to_f64().abs();
            d / b.to_f64().abs().max(1.0)
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_100_digit_state_is_the_motion_to_its_precision() {
    let (bits, hi) = (bits_for_digits(100), bits_for_digits(130));
    let mut points: Vec<(String, f64, f64, usize)> = EXAMPLE_POINTS_A1_B05
        .iter()
        .map(|(camera, m, h)| (format!("{camera:?}"), *m, *h, 0))
        .collect();
    points.push(("camera V, torus 3".into(), -0.7092, 1.5643, 3));
    let mut rng = ChaCha8Rng::seed_from_u64(100);
    let mut worst: f64 = 0.0;
    for (what, m, h, torus) in &points {
        let choice = TorusChoice {
            torus: *torus,
            phase1: 0.7,
            phase2: 2.1,
        };
        let build = |bits: u32| {
            let f = |x: f64| Float::with_val(bits, x);
            ExplicitMotion::new_until(f(1.0), f(0.5), f(*m), f(*h), choice, 1e9).unwrap()
        };
        let (motion, exact) = (build(bits), build(hi));
        for k in 0..30 {
            let t = match k % 3 {
                0 => rng.gen_range(0.0..1e9),
                1 => rng.gen_range(-50.0..50.0),
                _ => rng.gen_range(0..1_000_000u64) as f64,
            };
            let got = motion.at(&Float::with_val(bits, t));
            let want = exact.at(&Float::with_val(hi, t));
            let dev = deviation(&got, &want);
            assert!(dev < 1e-95, "{what}: t = {t:e}: off by {dev:e}");
            worst = worst.max(dev);
            if k == 0 {
                let later = Float::with_val(bits, t) + Float::with_val(bits, 1e-92);
                let dev = deviation(&motion.at(&later), &want);
                assert!(
                    dev > 1e-95,
                    "{what}: the state at t + 1e-92 passes ({dev:e})"
                );
            }
        }
    }
    eprintln!("largest relative difference from 130 digits: {worst:e}");
}
