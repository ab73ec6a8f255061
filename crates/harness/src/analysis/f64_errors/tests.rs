//! The kernel of f64 samples against the general double-double code (bit for bit) and against
//! MPFR at 300 bits (to the double-double bound).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rug::Float;

use super::*;
use crate::analysis::DdMeasure;
use crate::digits::sample_errors_dd;
use crate::metrics::sample_errors;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::vec3::{mul_bt, rotation_angle};

const MP: u32 = 300;

/// A double-double with a random low part (a value not on the f64 grid).
pub(super) fn dd(rng: &mut ChaCha8Rng, x: f64) -> Dd {
    Dd::from_f64_exact(x).add_f64(x * 1e-17 * rng.gen_range(-0.5..0.5))
}

/// Fields a > b with low parts (a decimal like 1.1 is not an f64).
pub(super) fn fields(rng: &mut ChaCha8Rng) -> Fields<Dd> {
    let a = rng.gen_range(0.5..3.0);
    let b = a * rng.gen_range(0.0..1.0);
    Fields {
        a: dd(rng, a),
        b: dd(rng, b),
    }
}

/// A random state (ω of size up to `w`, α, β orthonormal to f64 rounding) and an exact state
/// near it: each component moved by up to 10^`e` (e from −18 to −2), with a low part.
pub(super) fn sample(rng: &mut ChaCha8Rng, w: f64) -> ([f64; 9], State<Dd>) {
    let unit = |v: [f64; 3]| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / n)
    };
    let mut g = || rng.gen_range(-1.0..1.0);
    let alpha = unit([g(), g(), g()]);
    let p = [g(), g(), g()];
    let d = p[0] * alpha[0] + p[1] * alpha[1] + p[2] * alpha[2];
    let beta = unit(std::array::from_fn(|i| p[i] - d * alpha[i]));
    let omega = [w * g(), w * g(), w * g()];
    let x: [f64; 9] = std::array::from_fn(|k| [omega, alpha, beta][k / 3][k % 3]);
    let size = 10f64.powf(rng.gen_range(-18.0..-2.0));
    let y: [Dd; 9] = std::array::from_fn(|k| {
        let moved = x[k] + size * rng.gen_range(-1.0..1.0);
        dd(rng, moved)
    });
    (x, State::from_slice(&y))
}

/// `fields`, a random N and the initial integrals of `start`.
pub(super) fn dd_measure(rng: &mut ChaCha8Rng, fields: Fields<Dd>, start: &State<Dd>) -> DdMeasure {
    let i0 = integrals(&fields, start);
    DdMeasure {
        fields,
        n: ManifoldN {
            k: dd(rng, 0.3),
            p2: dd(rng, 1.7),
            r4m: dd(rng, -0.2),
        },
        initial_integrals: [i0.h, i0.k, i0.g],
    }
}

/// Every number of a sample's errors and digits but the orientation error is the general
/// code's, bit for bit, on 20 000 random samples (errors from 1e-18 to 1e-2, ω up to 3, fields
/// with low parts).
#[test]
fn f64_kernel_gives_the_numbers_of_the_general_code() {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    for n in 0..20_000 {
        let f = fields(&mut rng);
        let manifold = ManifoldN {
            k: dd(&mut rng, 0.3),
            p2: dd(&mut rng, 1.7),
            r4m: dd(&mut rng, -0.2),
        };
        let (x, exact) = sample(&mut rng, [0.1, 1.0, 3.0][n % 3]);
        let i0 = integrals(&f, &exact);
        let i0 = [i0.h, i0.k, i0.g];
        let ratio = [1.0, 1e-3][n % 2];
        let [(fast, fast_digits)] = f64_sample_errors::<1>(
            &f,
            &manifold,
            &i0,
            std::slice::from_ref(&exact),
            &[x],
            ratio,
        );
        let state = State::from_slice(&x.map(Dd::from_f64_exact));
        let (slow, _) = sample_errors(&f, &manifold, &i0, &exact, &state, false);
        let slow_digits = sample_errors_dd(&exact, &x, ratio);
        let bits = |e: &SampleErrors| {
            [
                e.state_error,
                e.drift_h,
                e.drift_k,
                e.drift_g,
                e.constraint_drift,
                e.off_n,
            ]
            .map(f64::to_bits)
        };
        assert_eq!(bits(&fast), bits(&slow), "sample {n}: {fast:?}\n{slow:?}");
        assert_eq!(
            [fast_digits.0.to_bits(), fast_digits.1.to_bits()],
            [slow_digits.0.to_bits(), slow_digits.1.to_bits()],
            "sample {n}"
        );
    }
}

/// H, K, G of f64 states agree with MPFR at 300 bits (the same f64 state and the same
/// double-double fields) within 2⁻¹⁰⁰ of the size of their terms, on 20 000 random states.
/// Dropping any term, or the low part of a field, breaks it.
#[test]
fn f64_integrals_are_those_of_mpfr_to_the_double_double_bound() {
    let mut rng = ChaCha8Rng::seed_from_u64(2929);
    let mut worst = 0.0f64;
    for n in 0..20_000 {
        let f = fields(&mut rng);
        let (x, _) = sample(&mut rng, [0.1, 1.0, 3.0, 30.0][n % 4]);
        let fast = integrals_f64::<1>(&f, &x.map(|v| [v])).map(|v| v.lane(0));
        let mp = Fields {
            a: f.a.to_float(MP),
            b: f.b.to_float(MP),
        };
        let state = State::from_slice(&x.map(|v| Float::with_val(MP, v)));
        let exact = integrals(&mp, &state);
        // The size of the terms: (ω² + a + b)² bounds every product in H, K, G.
        let w2: f64 = x[..3].iter().map(|w| w * w).sum();
        let size = (1.0 + w2 + f.a.hi + f.b.hi).powi(2) * (1.0 + f.a.hi).powi(2);
        for (name, got, want) in [
            ("H", fast[0], exact.h),
            ("K", fast[1], exact.k),
            ("G", fast[2], exact.g),
        ] {
            let error = (got.to_float(MP) - &want).abs().to_f64() / size;
            worst = worst.max(error);
            assert!(
                error <= 2f64.powi(-100),
                "{name} of sample {n}: error {error:e} of the terms' size ({got} vs {want})"
            );
        }
    }
    assert!(worst > 0.0, "no rounding at all: the test does not measure");
}

/// The small-angle arctangent is that of MPFR within 4·2⁻¹⁰⁶ of the angle, from 1e-20 to
/// the switch to the general arctangent (2⁻¹⁴) and beyond.
#[test]
fn small_angle_is_the_arctangent_to_double_double_accuracy() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20_000 {
        let theta = 10f64.powf(rng.gen_range(-20.0..-1.0));
        let (sin, cos) = (dd(&mut rng, theta.sin()), dd(&mut rng, theta.cos()));
        let got = small_angle::<1>(sin.into(), cos.into())
            .lane(0)
            .to_float(MP);
        let want = sin.to_float(MP).atan2(&cos.to_float(MP));
        let error = ((got - &want) / &want).abs().to_f64();
        assert!(error <= 4.0 * 2f64.powi(-106), "θ = {theta:e}: {error:e}");
    }
}

/// The kernel compiled with FMA instructions (what `check` runs on such a processor) and the
/// portable build give the same bits, errors and digits, on 5 000 random samples.
#[test]
fn fma_and_portable_builds_of_the_errors_give_the_same_bits() {
    #[cfg(target_arch = "x86_64")]
    {
        use crate::analysis::f64_samples::{measure_fma, measure_portable};
        if !std::arch::is_x86_feature_detected!("fma") {
            rsts_io::report_skip(
                "fma_and_portable_builds_of_the_errors_give_the_same_bits",
                "this CPU has no FMA: only the portable build runs",
            );
            return;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(2921);
        for n in 0..5_000 {
            let fields = fields(&mut rng);
            let (x, exact) = sample(&mut rng, [0.1, 1.0, 3.0][n % 3]);
            let m = dd_measure(&mut rng, fields, &exact);
            // SAFETY: the processor has FMA (checked above).
            let (a, _, da) = unsafe { measure_fma(&m, &exact, &x, 1e-3, false) };
            let (b, _, db) = measure_portable(&m, &exact, &x, 1e-3, false);
            assert_eq!(measured_bits(&a, da), measured_bits(&b, db), "sample {n}");
        }
    }
}

/// The bits of a sample's errors and of its two digits' errors, any NaN as one (the sign of a
/// NaN is not a number: the kernel itself, inlined into two callers, gives NaNs of either
/// sign, as x86 passes on the NaN of an addition's first operand).
pub(super) fn measured_bits(e: &SampleErrors, d: (f64, f64)) -> [u64; 9] {
    [
        e.state_error,
        e.orientation_error,
        e.drift_h,
        e.drift_k,
        e.drift_g,
        e.constraint_drift,
        e.off_n,
        d.0,
        d.1,
    ]
    .map(|v| if v.is_nan() { f64::NAN } else { v }.to_bits())
}

/// An exact state in double-double on the constraints (α̃, β̃ orthonormal within 2⁻¹⁰⁶: made
/// in MPFR) and f64 data near it, each component moved by up to 10^`e`, e from −18 to 0.
pub(super) fn on_constraints(rng: &mut ChaCha8Rng) -> ([f64; 9], State<Dd>) {
    let mp = |v: [f64; 3]| v.map(|c| Float::with_val(MP, c));
    let dot = |u: &[Float; 3], v: &[Float; 3]| {
        Float::with_val(MP, &u[0] * &v[0])
            + Float::with_val(MP, &u[1] * &v[1])
            + Float::with_val(MP, &u[2] * &v[2])
    };
    let unit = |v: [Float; 3]| {
        let n = dot(&v, &v).sqrt();
        v.map(|c| c / &n)
    };
    let mut g = || rng.gen_range(-1.0..1.0);
    let alpha = unit(mp([g(), g(), g()]));
    let p = mp([g(), g(), g()]);
    let d = dot(&p, &alpha);
    let beta = unit(std::array::from_fn(|i| {
        Float::with_val(MP, &p[i] - &d * &alpha[i])
    }));
    let omega = [g(), g(), g()];
    let size = 10f64.powf(rng.gen_range(-18.0..0.0));
    let y: [Dd; 9] = std::array::from_fn(|k| match k / 3 {
        0 => Dd::from_f64_exact(omega[k]),
        1 => Dd::from_float(&alpha[k % 3]),
        _ => Dd::from_float(&beta[k % 3]),
    });
    let x: [f64; 9] = std::array::from_fn(|k| y[k].hi + size * rng.gen_range(-1.0..1.0));
    (x, State::from_slice(&y))
}

/// The orientation error of f64 data is the rotation angle of Q Q̃ᵀ in MPFR at 300 bits
/// within 2⁻¹⁰⁰ of itself, on 20 000 random samples with angles from ~1e-18 to ~1; the general
/// double-double code (entries of R ≈ I) is not, for the small angles of exact data.
#[test]
fn orientation_error_is_that_of_mpfr_to_the_double_double_bound() {
    let mut rng = ChaCha8Rng::seed_from_u64(1729);
    let (mut worst, mut worst_general) = (0.0f64, 0.0f64);
    for n in 0..20_000 {
        let (x, exact) = on_constraints(&mut rng);
        let y = exact.to_array();
        let delta: [Dd; 9] = std::array::from_fn(|k| Dd::from_f64_exact(x[k]) - y[k]);
        let got =
            orientation_error::<1>(&x.map(|v| [v]), &y.map(Into::into), &delta.map(Into::into))
                .lane(0);
        let wide = |s: &State<Dd>| s.map(|v| v.to_float(MP));
        let state = State::from_slice(&x.map(Dd::from_f64_exact));
        let r = mul_bt(&wide(&state).orientation(), &wide(&exact).orientation());
        let want = rotation_angle(&r);
        let relative = |v: Dd| ((v.to_float(MP) - &want) / &want).abs().to_f64();
        let error = relative(got);
        worst = worst.max(error);
        assert!(
            error <= 2f64.powi(-100),
            "sample {n}: θ = {want:e}, error {error:e}"
        );
        let general = rotation_angle(&mul_bt(&state.orientation(), &exact.orientation()));
        worst_general = worst_general.max(relative(general));
    }
    eprintln!("worst relative error: {worst:e}, of the general code {worst_general:e}");
    assert!(worst > 0.0, "no rounding at all: the test does not measure");
    assert!(
        worst_general > 2f64.powi(-60),
        "the general code is as accurate: {worst_general:e}"
    );
}

mod lanes;
