//! The limb-level MPFR kernel of taylor-mp (`integrators/taylor/mp.rs`) against an independent
//! exact evaluation of the table and against the generic MPFR path, on random series: random
//! orders, precisions of 1 to 16 limbs (odd limb counts and precisions that are not multiples
//! of 64 included), negative values, zeros, exponents spread from a few bits (Taylor-like decay)
//! to hundreds and thousands of bits; then whole taylor-mp runs with either kernel.
//!
//! The exact value: every product of two p-bit numbers is exact at 2p bits and every sum is
//! exact at a precision wider than the span of its terms, so the table evaluated term by term
//! at that precision is the exact f(x)ₙ; rounding it once to p bits gives what the kernel must
//! return bit for bit (it accumulates exact products in fixed point and rounds once).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_dynamics::equations::{CauchyScratch, Component, Param, Quadratic, EULER_POISSON};
use rsts_dynamics::integrators::{
    MpfrKernel, MpfrKernelChoice, OutputGrid, Problem, Propagator, Taylor, Tolerances,
};
use rsts_dynamics::{Fields, State, VectorField};
use rug::float::Round;
use rug::ops::AssignRound;
use rug::Float;

/// Precisions: 1, 2, 3, 5, 7 and 16 limbs; on and off limb boundaries.
const PRECISIONS: [u32; 10] = [53, 64, 65, 100, 129, 192, 307, 320, 420, 1000];

/// How the exponents of a random series are drawn.
#[derive(Clone, Copy, Debug)]
enum Spread {
    /// |x_m| ≈ 2^(−3m ± 6): the geometric decay of a Taylor series.
    Taylor,
    /// Exponents uniform in ±300 bits.
    Wide,
    /// Exponents uniform in ±3000 bits (beyond a 5-limb product).
    Huge,
}

/// A random p-bit number: uniform mantissa, random sign, exponent from `spread` for order m;
/// zero with probability `zeros`.
fn random_value(rng: &mut ChaCha8Rng, bits: u32, m: usize, spread: Spread, zeros: f64) -> Float {
    if rng.gen_bool(zeros) {
        return Float::new(bits);
    }
    // Mantissa: ⌈p/52⌉ + 1 chunks of 52 random bits, summed exactly, rounded once to p bits.
    let wide = bits + 128;
    let mut x = Float::with_val(wide, 0.5);
    for k in 0..(bits / 52 + 2) {
        let chunk = rng.gen_range(0u64..1 << 52) as f64;
        x += Float::with_val(wide, chunk) >> (53 + 52 * k as i32);
    }
    let exp = match spread {
        Spread::Taylor => -3 * m as i32 + rng.gen_range(-6..=6),
        Spread::Wide => rng.gen_range(-300..=300),
        Spread::Huge => rng.gen_range(-3000..=3000),
    };
    let mut x = Float::with_val(bits, x << exp);
    if rng.gen_bool(0.5) {
        x = -x;
    }
    x
}

fn random_series(
    rng: &mut ChaCha8Rng,
    bits: u32,
    len: usize,
    spread: Spread,
    zeros: f64,
) -> Vec<[Float; 9]> {
    (0..len)
        .map(|m| std::array::from_fn(|_| random_value(rng, bits, m, spread, zeros)))
        .collect()
}

/// Fields whose coefficients c·a, c·b are p-bit numbers whatever the precision they are formed
/// in (a, b rounded to p bits; the table's c are ±1, ±½): the kernel at p bits and the exact
/// evaluation at a wide precision then use the same coefficients.
fn fields(bits: u32, wide: u32) -> (Fields<Float>, Fields<Float>) {
    let a = Float::with_val(bits, 1.3);
    let b = Float::with_val(bits, -0.7) / 3u32;
    let narrow = Fields {
        a: a.clone(),
        b: b.clone(),
    };
    let exact = Fields {
        a: Float::with_val(wide, &a),
        b: Float::with_val(wide, &b),
    };
    (narrow, exact)
}

/// The exponent span of the products of a series (bits from the top of the largest to the
/// bottom of the smallest), to size an exact evaluation.
fn span_bits(series: &[[Float; 9]], bits: u32) -> u32 {
    let exps: Vec<i32> = series
        .iter()
        .flatten()
        .filter_map(|x| x.get_exp())
        .collect();
    let (lo, hi) = (
        exps.iter().min().copied().unwrap_or(0),
        exps.iter().max().copied().unwrap_or(0),
    );
    2 * (hi - lo) as u32 + 2 * bits + 64
}

/// f(x)ₙ from `table`, every operation exact at `wide` bits (products of p-bit numbers and sums
/// within the span), each `scaled` quadratic term's Cauchy sum rounded to p bits first (the
/// kernel's rule for coefficients that are not ±2ʲ), then the component rounded once to p bits.
fn exact_coefficient(
    table: &[Component; 9],
    fields: &Fields<Float>,
    series: &[[Float; 9]],
    n: usize,
    bits: u32,
    wide: u32,
) -> [Float; 9] {
    let coefficient = |c: f64, param: Param| -> Float {
        let c = Float::with_val(wide, c);
        match param {
            Param::One => c,
            Param::A => c * &fields.a,
            Param::B => c * &fields.b,
        }
    };
    let is_power_of_two = |c: &Float| {
        let m = Float::with_val(wide, c.abs_ref());
        m.get_exp()
            .is_some_and(|e| m == Float::with_val(wide, 1) << (e - 1))
    };
    std::array::from_fn(|k| {
        let mut acc = Float::with_val(wide, 0);
        for q in table[k].quadratic {
            let c = coefficient(q.c, q.param);
            let mut s = Float::with_val(wide, 0);
            for m in 0..=n {
                s += Float::with_val(wide, &series[m][q.i] * &series[n - m][q.j]);
            }
            if !is_power_of_two(&c) {
                s = Float::with_val(wide, Float::with_val(bits, &s));
            }
            acc += Float::with_val(wide, &c * &s);
        }
        for l in table[k].linear {
            let c = coefficient(l.c, l.param);
            acc += Float::with_val(wide, &c * &series[n][l.i]);
        }
        let mut out = Float::new(bits);
        out.assign_round(&acc, Round::Nearest);
        out
    })
}

/// Same bits, or both zero (the sign of a zero result is not specified).
fn same(a: &Float, b: &Float) -> bool {
    (a.is_zero() && b.is_zero()) || (a == b && a.is_sign_negative() == b.is_sign_negative())
}

/// Σ over the table's terms of |c·xᵢ·xⱼ| (Cauchy) and |c·xᵢ|: the scale of the rounding errors
/// (64 bits are plenty for a bound; MPFR's exponent range covers the widest spreads).
fn magnitude(
    table: &[Component; 9],
    fields: &Fields<Float>,
    series: &[[Float; 9]],
    n: usize,
    k: usize,
) -> Float {
    let p = |c: f64, param: Param| -> Float {
        let c = Float::with_val(64, c);
        match param {
            Param::One => c,
            Param::A => c * &fields.a,
            Param::B => c * &fields.b,
        }
        .abs()
    };
    let mut sum = Float::with_val(64, 0);
    for q in table[k].quadratic {
        for m in 0..=n {
            sum +=
                p(q.c, q.param) * Float::with_val(64, &series[m][q.i] * &series[n - m][q.j]).abs();
        }
    }
    for l in table[k].linear {
        sum += p(l.c, l.param) * Float::with_val(64, series[n][l.i].abs_ref());
    }
    sum
}

/// One random case: the kernel (called in sequence for 0..=n, so rows are reused) equals the
/// correctly rounded exact value bit for bit; the generic path is within its error bound of it.
/// Returns how many components the generic path got not correctly rounded.
fn check_case(
    table: &[Component; 9],
    rng: &mut ChaCha8Rng,
    bits: u32,
    len: usize,
    spread: Spread,
    zeros: f64,
) -> usize {
    let series = random_series(rng, bits, len, spread, zeros);
    let wide = span_bits(&series, bits);
    let (narrow, exact_fields) = fields(bits, wide);
    let field = VectorField::from_table(&narrow, table);
    let mut kernel = MpfrKernel::new(&field, bits);
    let mut generic = CauchyScratch::new(&Float::new(bits));
    let mut out: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
    let mut plain: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
    let mut generic_misses = 0;
    for n in 0..len {
        kernel.coefficient(&series, n, &mut out);
        field.taylor_coefficient_orders(&series, n, &mut plain, &mut generic);
        let exact = exact_coefficient(table, &exact_fields, &series, n, bits, wide);
        for k in 0..9 {
            assert!(
                same(&out[k], &exact[k]),
                "{bits} bits, order {n}, component {k}, {spread:?}: kernel {} exact {}",
                out[k],
                exact[k]
            );
            // The generic path rounds each product and partial sum: (2n + 6) roundings of at
            // most 2^-p relative to the sum of |terms|.
            let bound = (magnitude(table, &exact_fields, &series, n, k) * (2 * n + 6) as u32)
                >> bits as i32;
            let diff = Float::with_val(wide, &plain[k] - &exact[k]).abs();
            assert!(
                diff <= bound,
                "{bits} bits, order {n}, component {k}: generic off by {diff} > {bound}"
            );
            generic_misses += usize::from(!same(&plain[k], &exact[k]));
        }
    }
    generic_misses
}

/// Bit for bit the correctly rounded exact coefficients, over precisions of 1 to 16 limbs and
/// orders up to 40, with Taylor-like and wide exponent spreads, negative values and zeros. The
/// check has teeth: the generic MPFR path (many roundings) fails it on many components.
#[test]
fn limb_kernel_is_the_correctly_rounded_exact_sum() {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut generic_misses = 0;
    let mut cases = 0;
    for bits in PRECISIONS {
        for (spread, zeros) in [
            (Spread::Taylor, 0.0),
            (Spread::Taylor, 0.2),
            (Spread::Wide, 0.1),
        ] {
            let len = if bits > 500 {
                12
            } else {
                rng.gen_range(1..=40)
            };
            generic_misses += check_case(&EULER_POISSON, &mut rng, bits, len, spread, zeros);
            cases += 9 * len;
        }
    }
    eprintln!("generic path not correctly rounded on {generic_misses} of {cases} components");
    assert!(
        generic_misses > cases / 10,
        "the exact check should tell the generic path apart: {generic_misses} of {cases}"
    );
}

/// A table with a quadratic coefficient that is not a power of two (0.3·ω₂ω₃, and a·α₂ω₃) and a
/// quadratic term with a parameter goes through the rounded-sum path: still exactly the
/// documented rounding (the sum rounded, then the component rounded once).
#[test]
fn coefficients_that_are_not_powers_of_two() {
    static SCALED: [Quadratic; 2] = [
        Quadratic {
            c: 0.3,
            param: Param::One,
            i: 1,
            j: 2,
        },
        Quadratic {
            c: -1.0,
            param: Param::A,
            i: 4,
            j: 2,
        },
    ];
    let mut table = EULER_POISSON;
    table[0].quadratic = &SCALED;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for bits in [64, 200, 307] {
        check_case(&table, &mut rng, bits, 15, Spread::Taylor, 0.1);
    }
}

/// Exponents spread over thousands of bits: within the accumulator's reach (64 limbs beyond the
/// products) still bit for bit; beyond it, products far below the largest are dropped and the
/// error stays below the documented bound, far below the generic path's.
#[test]
fn widely_different_exponents() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for bits in [53, 128, 307] {
        let series = random_series(&mut rng, bits, 10, Spread::Huge, 0.0);
        let wide = span_bits(&series, bits);
        let (narrow, exact_fields) = fields(bits, wide);
        let field = VectorField::new(&narrow);
        let mut kernel = MpfrKernel::new(&field, bits);
        let mut out: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
        let mut exact_hits = 0;
        for n in 0..series.len() {
            kernel.coefficient(&series, n, &mut out);
            let exact = exact_coefficient(&EULER_POISSON, &exact_fields, &series, n, bits, wide);
            for k in 0..9 {
                let diff = Float::with_val(wide, &out[k] - &exact[k]).abs();
                let ulp = exact[k]
                    .get_exp()
                    .map(|e| Float::with_val(wide, 1) << (e - bits as i32))
                    .unwrap_or_else(|| Float::with_val(wide, 0));
                // Half an ulp of rounding plus the dropped products: below (products)·2^-4000
                // of the sum of their magnitudes.
                let dropped = (magnitude(&EULER_POISSON, &exact_fields, &series, n, k)
                    * (2 * n + 4) as u32)
                    >> 4000;
                let bound = ulp + dropped;
                assert!(diff <= bound, "{bits} bits order {n} comp {k}");
                exact_hits += usize::from(same(&out[k], &exact[k]));
            }
        }
        // Nearly all are still exactly rounded (the dropped products are negligible).
        assert!(exact_hits >= 80, "{bits} bits: {exact_hits} of 90 exact");
    }
}

/// Zeros everywhere give zero; a NaN operand takes the generic path and gives NaN where the
/// generic path does; calls out of sequence and a new series regather their rows.
#[test]
fn zeros_nan_and_out_of_sequence_calls() {
    let bits = 150;
    let (narrow, _) = fields(bits, 400);
    let field = VectorField::new(&narrow);
    let mut kernel = MpfrKernel::new(&field, bits);
    let mut out: [Float; 9] = std::array::from_fn(|_| Float::with_val(bits, 7));
    let zeros: Vec<[Float; 9]> = (0..4)
        .map(|_| std::array::from_fn(|_| Float::new(bits)))
        .collect();
    for n in 0..4 {
        kernel.coefficient(&zeros, n, &mut out);
        assert!(out.iter().all(Float::is_zero), "order {n}");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let series = random_series(&mut rng, bits, 12, Spread::Taylor, 0.0);
    let wide = span_bits(&series, bits);
    let (_, exact_fields) = fields(bits, wide);
    for n in [11, 3, 0, 7, 8, 2] {
        kernel.coefficient(&series, n, &mut out);
        let exact = exact_coefficient(&EULER_POISSON, &exact_fields, &series, n, bits, wide);
        for k in 0..9 {
            assert!(same(&out[k], &exact[k]), "order {n} comp {k}");
        }
    }
    let mut bad = series.clone();
    bad[2][4] = Float::with_val(bits, f64::NAN);
    let mut generic = CauchyScratch::new(&Float::new(bits));
    let mut plain: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
    for n in 0..6 {
        kernel.coefficient(&bad, n, &mut out);
        field.taylor_coefficient_orders(&bad, n, &mut plain, &mut generic);
        for k in 0..9 {
            assert_eq!(out[k].is_nan(), plain[k].is_nan(), "order {n} comp {k}");
            if !plain[k].is_nan() {
                assert!(same(&out[k], &plain[k]) || n < 2, "order {n} comp {k}");
            }
        }
        assert_eq!(out.iter().any(Float::is_nan), n >= 2, "order {n}");
    }
    // Back to a finite series: exact again.
    for n in 0..12 {
        kernel.coefficient(&series, n, &mut out);
        let exact = exact_coefficient(&EULER_POISSON, &exact_fields, &series, n, bits, wide);
        for k in 0..9 {
            assert!(same(&out[k], &exact[k]), "order {n} comp {k}");
        }
    }
}

/// Set in the child process of [`taylor_mp_runs_agree_with_either_kernel`] that checks the
/// environment variable.
const KERNEL_CHILD: &str = "RSTS_TEST_MPFR_KERNEL_CHILD";

/// Whole taylor-mp runs with the limb kernel and with the generic path take the same steps and
/// agree to the working precision (60 digits, T = 20): the limb kernel is the default, the
/// environment variable and `with_mpfr_kernel` choose either.
#[test]
fn taylor_mp_runs_agree_with_either_kernel() {
    if std::env::var_os(KERNEL_CHILD).is_some() {
        return kernel_from_the_environment();
    }
    let (bits, problem, tol) = kernel_problem();
    let grid = OutputGrid::new(20.0, 21).unwrap();
    let limbs = Taylor::new(tol)
        .with_mpfr_kernel(MpfrKernelChoice::Limbs)
        .propagate_grid(&problem, &grid)
        .unwrap();
    let generic = Taylor::new(tol)
        .with_mpfr_kernel(MpfrKernelChoice::Generic)
        .propagate_grid(&problem, &grid)
        .unwrap();
    assert_eq!(limbs.stats.accepted_steps, generic.stats.accepted_steps);
    let mut worst = 0.0f64;
    for (x, y) in limbs.states.iter().zip(&generic.states) {
        for (u, v) in x.to_array().iter().zip(y.to_array().iter()) {
            worst = worst.max(Float::with_val(bits, u - v).abs().to_f64());
        }
    }
    eprintln!("limb vs generic kernel over T = 20: {worst:e}");
    assert!(worst > 0.0 && worst < 1e-58, "{worst:e}");
    assert_eq!(MpfrKernelChoice::default(), MpfrKernelChoice::Limbs);
    // The environment variable, read when a run starts: the environment is the whole process's
    // and the other tests of this binary integrate at the same time, so this test runs again,
    // alone, in a child process of this binary that sets it.
    let child = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "taylor_mpfr::taylor_mp_runs_agree_with_either_kernel",
            "--exact",
            "--test-threads=1",
            "--nocapture",
        ])
        .env(KERNEL_CHILD, "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&child.stdout);
    assert!(
        child.status.success() && stdout.contains("1 passed"),
        "the child process:\n{stdout}\n{}",
        String::from_utf8_lossy(&child.stderr)
    );
}

/// The motion of [`taylor_mp_runs_agree_with_either_kernel`] (a = 1, b = 1/2) at 60 digits: the
/// precision in bits, the problem and the tolerances.
fn kernel_problem() -> (u32, Problem<Float>, Tolerances) {
    let bits = rsts_dynamics::scalar::bits_for_digits(60);
    let f = |x: f64| Float::with_val(bits, x);
    let (s, c) = 0.3f64.sin_cos();
    let problem = Problem {
        fields: Fields {
            a: f(1.0),
            b: f(0.5),
        },
        initial: State {
            omega: [f(0.4), f(-0.7), f(1.1)],
            alpha: [f(c), f(s), f(0.0)],
            beta: [f(-s), f(c), f(0.0)],
        },
    };
    (bits, problem, Tolerances::new(1e-60, 1e-60).unwrap())
}

/// The environment variable chooses the kernel (run alone in the child process of
/// [`taylor_mp_runs_agree_with_either_kernel`]: setting it races with nothing).
fn kernel_from_the_environment() {
    let (_, problem, tol) = kernel_problem();
    let short = OutputGrid::new(2.0, 3).unwrap();
    let run = || Taylor::new(tol).propagate_grid(&problem, &short);
    std::env::set_var(MpfrKernelChoice::ENV, "generic");
    let from_env = run().unwrap();
    std::env::set_var(MpfrKernelChoice::ENV, "fast");
    let err = run().unwrap_err().to_string();
    std::env::remove_var(MpfrKernelChoice::ENV);
    assert!(
        err.contains("RSTS_MPFR_KERNEL") && err.contains("fast"),
        "{err}"
    );
    let explicit = Taylor::new(tol)
        .with_mpfr_kernel(MpfrKernelChoice::Generic)
        .propagate_grid(&problem, &short)
        .unwrap();
    let default = run().unwrap();
    assert_eq!(
        from_env.states, explicit.states,
        "generic from the environment"
    );
    assert_ne!(default.states, explicit.states, "limbs by default");
}

/// Cancellation down to a tiny product: α̇₁ = α₂ω₃ − α₃ω₂ at order 1 with α₂,₀ω₃,₁ = α₃,₀ω₂,₁ = 1
/// leaves α₂,₁ω₃,₀ = 2^-e. The exact sum is 2^-e: found exactly while e is within the
/// accumulator's reach (64 limbs beyond the products), dropped (0, inside the documented bound
/// of (products)·2^(−64·64)) beyond it. A kernel with a narrower accumulator fails the first.
#[test]
fn cancellation_leaves_a_tiny_exact_term() {
    let bits = 307;
    let (narrow, _) = fields(bits, 400);
    let field = VectorField::new(&narrow);
    let mut kernel = MpfrKernel::new(&field, bits);
    let one = Float::with_val(bits, 1);
    for (e, kept) in [(100, true), (2000, true), (3900, true), (6000, false)] {
        let mut series: Vec<[Float; 9]> = (0..2)
            .map(|_| std::array::from_fn(|_| Float::new(bits)))
            .collect();
        // indices: ω = 0..3, α = 3..6
        series[0][4] = one.clone(); // α₂,₀
        series[1][2] = one.clone(); // ω₃,₁
        series[0][5] = one.clone(); // α₃,₀
        series[1][1] = one.clone(); // ω₂,₁
        series[1][4] = Float::with_val(bits, 1) >> e; // α₂,₁
        series[0][2] = one.clone(); // ω₃,₀
        let mut out: [Float; 9] = std::array::from_fn(|_| Float::new(bits));
        kernel.coefficient(&series, 0, &mut out);
        kernel.coefficient(&series, 1, &mut out);
        let tiny = Float::with_val(bits, 1) >> e;
        if kept {
            assert_eq!(out[3], tiny, "2^-{e}");
        } else {
            assert!(out[3].is_zero() || out[3] == tiny, "2^-{e}: {}", out[3]);
        }
    }
}

/// taylor-mp picks the limb kernel up to MAX_DEFAULT_LIMBS limbs of precision (where it is
/// faster, docs/benchmarks.md) and the generic path beyond.
#[test]
fn default_kernel_up_to_the_measured_crossover() {
    use rsts_dynamics::integrators::MPFR_MAX_DEFAULT_LIMBS as MAX;
    let (narrow, _) = fields(64, 128);
    let field = VectorField::new(&narrow);
    let widest = 64 * MAX as u32;
    assert!(MpfrKernel::by_default(&field, widest).is_some());
    assert!(MpfrKernel::by_default(&field, widest + 1).is_none());
    assert!(MpfrKernel::by_default(&field, 53).is_some());
}
