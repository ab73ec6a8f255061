//! Accuracy of the double-double arithmetic and functions against MPFR at 200 bits.

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const REF_BITS: u32 = 200;
const SAMPLES: usize = 2000;
/// Required relative accuracy of every operation (2⁻¹⁰⁶ ≈ 1.2e-32; a few ulps allowed).
const TOL: f64 = 1e-30;

type Dd = DoubleDouble;

/// A random double-double with hi log-uniform in ±[2^lo_exp, 2^hi_exp] and a full lo.
fn random_dd(rng: &mut ChaCha8Rng, lo_exp: f64, hi_exp: f64, signed: bool) -> Dd {
    let mag = 2f64.powf(rng.gen_range(lo_exp..hi_exp));
    let sign = if signed && rng.gen_bool(0.5) {
        -1.0
    } else {
        1.0
    };
    let hi = sign * mag;
    // |lo| < ulp(hi)/2.
    let ulp = 2f64.powi(hi.abs().log2().floor() as i32 - 52);
    Dd::new(hi, rng.gen_range(-0.49..0.49) * ulp)
}

fn rel_err(x: &Dd, reference: &Float) -> f64 {
    let d = Float::with_val(REF_BITS, &x.to_float(REF_BITS) - reference);
    if reference.is_zero() {
        return d.to_f64().abs();
    }
    (d / reference).to_f64().abs()
}

/// Largest relative error of a unary operation over random inputs from `input`.
fn max_err_unary(
    seed: u64,
    input: impl Fn(&mut ChaCha8Rng) -> Dd,
    op: impl Fn(&Dd) -> Dd,
    reference: impl Fn(Float) -> Float,
) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..SAMPLES)
        .map(|_| {
            let x = input(&mut rng);
            rel_err(&op(&x), &reference(x.to_float(REF_BITS)))
        })
        .fold(0.0, f64::max)
}

fn max_err_binary(
    seed: u64,
    op: impl Fn(Dd, Dd) -> Dd,
    reference: impl Fn(Float, Float) -> Float,
) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..SAMPLES)
        .map(|_| {
            let x = random_dd(&mut rng, -30.0, 30.0, true);
            let y = random_dd(&mut rng, -30.0, 30.0, true);
            rel_err(
                &op(x, y),
                &reference(x.to_float(REF_BITS), y.to_float(REF_BITS)),
            )
        })
        .fold(0.0, f64::max)
}

#[test]
fn field_operations_are_accurate_to_106_bits() {
    let cases: [(&str, f64); 4] = [
        ("add", max_err_binary(1, |a, b| a + b, |a, b| a + b)),
        ("sub", max_err_binary(2, |a, b| a - b, |a, b| a - b)),
        ("mul", max_err_binary(3, |a, b| a * b, |a, b| a * b)),
        ("div", max_err_binary(4, |a, b| a / b, |a, b| a / b)),
    ];
    for (name, err) in cases {
        assert!(err < TOL, "{name}: max relative error {err:e}");
    }
}

#[test]
fn sums_of_one_sign_are_accurate_with_one_error_free_sum() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut worst: f64 = 0.0;
    for _ in 0..SAMPLES {
        let x = random_dd(&mut rng, -30.0, 30.0, true);
        let y = random_dd(&mut rng, -30.0, 30.0, false);
        let y = if x.hi < 0.0 { -y } else { y };
        let r = x.to_float(REF_BITS) + y.to_float(REF_BITS);
        worst = worst.max(rel_err(&x.add_same_sign(&y), &Float::with_val(REF_BITS, r)));
    }
    assert!(worst < TOL, "max relative error {worst:e}");
}

#[test]
fn subtraction_under_cancellation_stays_relative() {
    // x − y with y = x(1 + δ): the accurate sum keeps the relative accuracy of the result.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst: f64 = 0.0;
    for _ in 0..SAMPLES {
        let x = random_dd(&mut rng, -5.0, 5.0, true);
        let d = random_dd(&mut rng, -90.0, -10.0, true);
        let y = x * d.add_f64(1.0);
        let r = x.to_float(REF_BITS) - y.to_float(REF_BITS);
        worst = worst.max(rel_err(&(x - y), &Float::with_val(REF_BITS, r)));
    }
    assert!(worst < TOL, "max relative error {worst:e}");
}

#[test]
fn functions_are_accurate_to_about_32_digits() {
    let pos = |rng: &mut ChaCha8Rng| random_dd(rng, -40.0, 40.0, false);
    let angle = |rng: &mut ChaCha8Rng| random_dd(rng, -20.0, 7.0, true);
    let exp_arg = |rng: &mut ChaCha8Rng| random_dd(rng, -30.0, 9.4, true);
    let cases: [(&str, f64); 6] = [
        ("sqrt", max_err_unary(11, pos, |x| x.sqrt(), |x| x.sqrt())),
        (
            "recip_sqrt",
            max_err_unary(18, pos, |x| x.recip_sqrt(), |x| x.recip_sqrt()),
        ),
        ("sin", max_err_unary(12, angle, |x| x.sin(), |x| x.sin())),
        ("cos", max_err_unary(13, angle, |x| x.cos(), |x| x.cos())),
        ("exp", max_err_unary(14, exp_arg, |x| x.exp(), |x| x.exp())),
        (
            "ln",
            // Away from 1 (where ln is accurate absolutely, tested below).
            max_err_unary(
                15,
                |rng| {
                    let x = pos(rng);
                    if (x.hi - 1.0).abs() < 0.05 {
                        x.add_f64(0.5)
                    } else {
                        x
                    }
                },
                |x| x.ln(),
                |x| x.ln(),
            ),
        ),
    ];
    for (name, err) in cases {
        assert!(err < TOL, "{name}: max relative error {err:e}");
    }
}

#[test]
fn ln_near_one_is_accurate_absolutely() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let mut worst: f64 = 0.0;
    for _ in 0..SAMPLES {
        let x = random_dd(&mut rng, -60.0, -4.4, true).add_f64(1.0);
        let reference = x.to_float(REF_BITS).ln();
        let d = Float::with_val(REF_BITS, &x.ln().to_float(REF_BITS) - &reference);
        worst = worst.max(d.to_f64().abs());
    }
    assert!(worst < 1e-31, "max absolute error {worst:e}");
}

#[test]
fn atan2_is_accurate_in_every_quadrant() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut worst: f64 = 0.0;
    for _ in 0..SAMPLES {
        let y = random_dd(&mut rng, -20.0, 20.0, true);
        let x = random_dd(&mut rng, -20.0, 20.0, true);
        let reference = y.to_float(REF_BITS).atan2(&x.to_float(REF_BITS));
        worst = worst.max(rel_err(&y.atan2(&x), &reference));
    }
    assert!(worst < TOL, "atan2: max relative error {worst:e}");
    assert_eq!(Dd::ZERO.atan2(&Dd::from_f64_exact(-1.0)), Dd::PI);
    assert_eq!(Dd::ONE.atan2(&Dd::ZERO), Dd::PI.mul_f64(0.5));
}

#[test]
fn constants_match_mpfr() {
    use rug::float::Constant;
    let pi = Float::with_val(400, Constant::Pi);
    let ln2 = Float::with_val(400, Constant::Log2);
    for (parts, reference) in [(PI, pi.clone()), (LN2, ln2)] {
        let mut sum = Float::with_val(400, 0);
        for p in parts {
            sum += p;
        }
        let err = Float::with_val(400, &sum - &reference) / &reference;
        assert!(err.to_f64().abs() < 1e-48, "{parts:?}");
    }
    let eps = Dd::ONE.epsilon();
    assert!(Dd::ONE + eps > Dd::ONE);
    assert_eq!(eps.hi, 2f64.powi(-105));
}

#[test]
fn decimal_text_round_trips_to_full_precision() {
    let x = <Dd as Real>::parse("0.1", 0).unwrap();
    let tenth = Float::with_val(REF_BITS, Float::parse("0.1").unwrap());
    assert!(rel_err(&x, &tenth) < 2f64.powi(-106), "{x:?}");
    let third = Dd::ONE / Dd::from_f64_exact(3.0);
    let s = third.to_decimal(32);
    assert_eq!(s.matches('3').count(), 32, "{s}");
    let back = <Dd as Real>::parse(&s, 0).unwrap();
    assert!((back - third).abs().hi < 1e-32);
    assert!(<Dd as Real>::parse("not a number", 0).is_none());
    assert_eq!(Dd::from_f64_exact(-2.5).floor().hi, -3.0);
    assert_eq!(Dd::new(3.0, -1e-20).floor(), Dd::from_f64_exact(2.0));
}

/// The accuracy check is not vacuous: a "double-double" that multiplies in plain f64 fails it.
#[test]
fn accuracy_check_rejects_f64_arithmetic() {
    let err = max_err_binary(3, |a, b| Dd::from_f64_exact(a.hi * b.hi), |a, b| a * b);
    assert!(err > 1e-20, "f64 product passed as 106-bit: {err:e}");
    let err = max_err_unary(
        12,
        |rng| random_dd(rng, -20.0, 7.0, true),
        |x| Dd::from_f64_exact(x.hi.sin()),
        |x| x.sin(),
    );
    assert!(err > 1e-20, "f64 sine passed as 106-bit: {err:e}");
}

/// sin and cos of an angle in turns (2πx) are accurate relative to each value, also where it
/// is near 0: x tiny, and x within 2⁻⁶⁰ of a quarter turn (x − k/4 is exact, so the result
/// keeps its relative accuracy), over several turns of either sign.
#[test]
fn sin_cos_in_turns_is_accurate_relative_to_each_value() {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let two_pi = Float::with_val(REF_BITS, rug::float::Constant::Pi) * 2u32;
    let (mut worst_s, mut worst_c) = (0f64, 0f64);
    for k in 0..SAMPLES {
        let x = match k % 3 {
            0 => random_dd(&mut rng, -40.0, 1.6, true),
            1 => random_dd(&mut rng, -60.0, -20.0, true)
                .add_f64(f64::from(rng.gen_range(-12..12)) / 4.0),
            _ => Dd::new(rng.gen_range(-3.0..3.0), rng.gen_range(-1e-17..1e-17)),
        };
        let angle = Float::with_val(REF_BITS, &two_pi * &x.to_float(REF_BITS));
        let (s, c) = x.sin_cos_turns();
        worst_s = worst_s.max(rel_err(&s, &angle.clone().sin()));
        worst_c = worst_c.max(rel_err(&c, &angle.cos()));
    }
    assert!(
        worst_s < TOL && worst_c < TOL,
        "sin {worst_s:e}, cos {worst_c:e}"
    );
    let (s, c) = Dd::from_f64_exact(f64::NAN).sin_cos_turns();
    assert!(s.hi.is_nan() && c.hi.is_nan());
}
