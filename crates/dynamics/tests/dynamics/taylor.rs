//! The Taylor integrators (f64 with compensated state, double-double, MPFR) against independent
//! references: a Taylor run at higher precision and tighter tolerance, and Dop853 (another
//! method, another evaluation path of the same table: `eval_into` instead of the Cauchy
//! products). Errors are measured in MPFR at 300 bits, as the maximum over all grid samples and
//! components of |x − x_ref|. Plus: convergence with the tolerance, conservation of H, K, G,
//! settings errors, and the checks failing on a broken table of equations.

use std::sync::OnceLock;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_dynamics::equations::{Component, Quadratic, EULER_POISSON};
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::integrators::{
    map_problem, map_solution, MethodConfig, MethodName, OutputGrid, Problem, Propagator, Solution,
    Taylor, Tolerances,
};
use rsts_dynamics::{DynamicsError, Fields, State, VectorField};
use rug::Float;

/// Precision at which errors are measured.
const CMP_BITS: u32 = 300;
const T_END: f64 = 20.0;
const SAMPLES: usize = 41;
/// Seeds of the initial states used throughout.
const SEEDS: [u64; 3] = [1, 2, 3];

/// A random state on the constraint manifold (α, β orthonormal) with |ωᵢ| ≤ 1.5.
fn random_state(seed: u64) -> State<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut v = || -> [f64; 3] { std::array::from_fn(|_| rng.gen_range(-1.0..1.0)) };
    let omega = v().map(|x| 1.5 * x);
    let a = v();
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let alpha = a.map(|x| x / n);
    let c = v();
    let d = c[0] * alpha[0] + c[1] * alpha[1] + c[2] * alpha[2];
    let c: [f64; 3] = std::array::from_fn(|i| c[i] - d * alpha[i]);
    let n = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let beta = c.map(|x| x / n);
    State { omega, alpha, beta }
}

fn problem(seed: u64) -> Problem<f64> {
    Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: random_state(seed),
    }
}

/// The problem at 300 bits, with α, β made orthonormal to 300 bits (the third integral G is
/// conserved only on |α| = |β| = 1, α·β = 0).
fn problem_mp(seed: u64) -> Problem<Float> {
    let mut p = map_problem(&problem(seed), |x| Float::with_val(CMP_BITS, *x));
    let dot = |u: &[Float; 3], v: &[Float; 3]| -> Float {
        Float::with_val(CMP_BITS, &u[0] * &v[0] + &u[1] * &v[1])
            + Float::with_val(CMP_BITS, &u[2] * &v[2])
    };
    let n = dot(&p.initial.alpha, &p.initial.alpha).sqrt();
    p.initial.alpha.iter_mut().for_each(|x| *x /= &n);
    let d = dot(&p.initial.alpha, &p.initial.beta);
    for i in 0..3 {
        let c = Float::with_val(CMP_BITS, &d * &p.initial.alpha[i]);
        p.initial.beta[i] -= c;
    }
    let n = dot(&p.initial.beta, &p.initial.beta).sqrt();
    p.initial.beta.iter_mut().for_each(|x| *x /= &n);
    p
}

fn config(method: MethodName, tol: f64, digits: Option<u32>) -> MethodConfig {
    let c = MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap();
    match digits {
        Some(d) => c.with_digits(d).unwrap(),
        None => c,
    }
}

fn run(
    method: MethodName,
    tol: f64,
    digits: Option<u32>,
    seed: u64,
    t_end: f64,
) -> Solution<Float> {
    let grid = OutputGrid::new(t_end, SAMPLES).unwrap();
    config(method, tol, digits)
        .propagate_mp(&problem_mp(seed), &grid)
        .unwrap_or_else(|e| panic!("{method} at {tol:e}: {e}"))
}

/// max over samples and components of |a − b|.
fn max_diff(a: &Solution<Float>, b: &Solution<Float>) -> f64 {
    // Same grid (Dop853 reports the times at which it evaluated its interpolant: the grid
    // times up to accumulated rounding).
    assert_eq!(a.times.len(), b.times.len());
    for (s, t) in a.times.iter().zip(&b.times) {
        assert!((s - t).abs() <= 1e-13 * s.abs().max(1.0), "{s} vs {t}");
    }
    let mut worst = Float::with_val(CMP_BITS, 0);
    for (x, y) in a.states.iter().zip(&b.states) {
        for (u, v) in x.to_array().iter().zip(y.to_array().iter()) {
            let d = Float::with_val(CMP_BITS, u - v).abs();
            if d > worst {
                worst = d;
            }
        }
    }
    worst.to_f64()
}

/// The 60-digit Taylor reference of each seed over T = 20 (shared by the tests).
fn reference(seed: u64) -> &'static Solution<Float> {
    static REFS: OnceLock<Vec<Solution<Float>>> = OnceLock::new();
    let refs = REFS.get_or_init(|| {
        SEEDS
            .iter()
            .map(|&s| run(MethodName::TaylorMp, 1e-60, Some(60), s, T_END))
            .collect()
    });
    &refs[SEEDS.iter().position(|&s| s == seed).unwrap()]
}

#[test]
fn taylor_mp_at_60_digits_agrees_with_80_digits_to_1e_55() {
    let seed = SEEDS[0];
    let fine = run(MethodName::TaylorMp, 1e-75, Some(80), seed, T_END);
    let err = max_diff(reference(seed), &fine);
    eprintln!("taylor-mp 60 digits vs 80 digits: {err:e}");
    assert!(err < 1e-55, "60 vs 80 digits: {err:e}");
    assert!(fine.stats.accepted_steps > 10 && fine.stats.rhs_evals > 0);
}

#[test]
fn taylor_f64_and_dop853_agree_with_the_60_digit_run() {
    for seed in SEEDS {
        let reference = reference(seed);
        let taylor = run(MethodName::TaylorF64, 1e-15, None, seed, T_END);
        let err = max_diff(reference, &taylor);
        eprintln!("seed {seed}: taylor-f64 1e-15 vs mp: {err:e}");
        assert!(err < 1e-13, "seed {seed}: taylor-f64 at 1e-15: {err:e}");
        let dop = run(MethodName::Dop853, 1e-13, None, seed, T_END);
        let err = max_diff(reference, &dop);
        eprintln!("seed {seed}: dop853 1e-13 vs mp: {err:e}");
        assert!(err < 1e-11, "seed {seed}: dop853 at 1e-13: {err:e}");
    }
}

#[test]
fn taylor_dd_agrees_with_the_60_digit_run_to_1e_26() {
    for seed in SEEDS {
        let dd = run(MethodName::TaylorDd, 1e-28, None, seed, T_END);
        let err = max_diff(reference(seed), &dd);
        eprintln!("seed {seed}: taylor-dd 1e-28 vs mp: {err:e}");
        assert!(err < 1e-26, "seed {seed}: taylor-dd at 1e-28: {err:e}");
    }
}

/// Issue 2, "done when": Dop853 in f64 at rtol = atol = 1e-12 follows an independent 40-digit
/// Taylor integration of the same state to better than 1e-8 over t = 50.
#[test]
fn dop853_at_1e_12_follows_the_40_digit_taylor_run_over_t_50() {
    for seed in SEEDS {
        let taylor = run(MethodName::TaylorMp, 1e-40, Some(40), seed, 50.0);
        let dop = run(MethodName::Dop853, 1e-12, None, seed, 50.0);
        let err = max_diff(&taylor, &dop);
        eprintln!("seed {seed}: dop853 1e-12 vs taylor-mp 40 digits, t = 50: {err:e}");
        assert!(err < 1e-8, "seed {seed}: {err:e}");
    }
}

/// Least-squares slope of ln(error) against ln(tolerance).
fn slope(tols: &[f64], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = tols.iter().map(|t| t.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// The global error is proportional to the tolerance (local error ≈ ε per step, about the same
/// number of steps): the fitted slope of ln(error) against ln(ε) over four decades lies in
/// [0.8, 1.25], for f64 (1e-6 … 1e-12) and double-double (1e-16 … 1e-25). The band allows for
/// the order p = ⌈−ln ε/2⌉ + 1 moving in integer jumps (the step and the step count change
/// a little with p).
#[test]
fn error_falls_in_proportion_to_the_tolerance() {
    let seed = SEEDS[1];
    let reference = reference(seed);
    for (method, tols) in [
        (MethodName::TaylorF64, [1e-6, 1e-8, 1e-10, 1e-12]),
        (MethodName::TaylorDd, [1e-16, 1e-19, 1e-22, 1e-25]),
    ] {
        let errs: Vec<f64> = tols
            .iter()
            .map(|&tol| max_diff(reference, &run(method, tol, None, seed, T_END)))
            .collect();
        let k = slope(&tols, &errs);
        eprintln!("{method}: errors {errs:?} at {tols:?}: slope {k}");
        assert!(
            (0.8..=1.25).contains(&k),
            "{method}: slope {k} from errors {errs:?}"
        );
        // And the error is of the order of the tolerance at all (not just proportional).
        for (tol, err) in tols.iter().zip(&errs) {
            assert!(
                *err < 1e4 * tol && *err > 1e-3 * tol,
                "{method} at {tol:e}: {err:e}"
            );
        }
    }
}

#[test]
fn integrals_are_conserved_to_working_precision_along_the_mp_run() {
    for seed in SEEDS {
        let sol = reference(seed);
        let f = &problem_mp(seed).fields;
        let i0 = integrals(f, &sol.states[0]);
        let mut worst: f64 = 0.0;
        for s in &sol.states {
            let i = integrals(f, s);
            for (a, b) in [(&i.h, &i0.h), (&i.k, &i0.k), (&i.g, &i0.g)] {
                let scale = b.clone().abs().to_f64().max(1.0);
                worst = worst.max(Float::with_val(CMP_BITS, a - b).abs().to_f64() / scale);
            }
            // The geometric integrals: |α|² − 1, |β|² − 1, α·β.
            for c in s.constraint_residuals() {
                worst = worst.max(c.abs().to_f64());
            }
        }
        eprintln!("seed {seed}: integral drift {worst:e}");
        // 60 digits of working precision, tolerance 1e-60.
        assert!(worst < 1e-56, "seed {seed}: integrals drift by {worst:e}");
    }
}

#[test]
fn high_and_low_precision_outputs_agree() {
    // propagate_f64 and propagate_mp run the same computation for the f64 methods and round the
    // same high-precision result for the others.
    let grid = OutputGrid::new(2.0, 5).unwrap();
    for method in MethodName::ALL {
        let cfg = config(method, 1e-10, None);
        let cfg = if method == MethodName::Rk4 {
            MethodConfig::new(method, cfg.tolerances, Some(1e-3)).unwrap()
        } else {
            cfg
        };
        let lo = cfg.propagate_f64(&problem(1), &grid).unwrap();
        let p = map_problem(&problem(1), |x| Float::with_val(CMP_BITS, *x));
        let hi = cfg.propagate_mp(&p, &grid).unwrap();
        assert_eq!(lo.times, hi.times, "{method}");
        for (a, b) in lo.states.iter().zip(&hi.states) {
            for (x, y) in a.to_array().iter().zip(b.to_array().iter()) {
                assert!(
                    (x - y.to_f64()).abs() <= 1e-15 * x.abs().max(1.0),
                    "{method}"
                );
            }
        }
        assert_eq!(method.as_str().parse::<MethodName>().unwrap(), method);
        assert_eq!(lo.method, method.as_str());
    }
}

#[test]
fn bad_settings_give_errors() {
    let grid = OutputGrid::new(1.0, 3).unwrap();
    let p = problem(1);
    // Tolerance below the unit round-off the method can deliver: 2^-(53 + 8) for taylor-f64 and
    // 2^-(106 + 8) for taylor-dd (compensated state), 2^-bits for taylor-mp.
    let e = config(MethodName::TaylorF64, 1e-20, None).propagate_f64(&p, &grid);
    assert!(matches!(e, Err(DynamicsError::Settings(_))), "{e:?}");
    assert!(config(MethodName::TaylorF64, 1e-18, None)
        .propagate_f64(&p, &grid)
        .is_ok());
    let e = config(MethodName::TaylorDd, 1e-36, None).propagate_f64(&p, &grid);
    assert!(matches!(e, Err(DynamicsError::Settings(_))), "{e:?}");
    assert!(config(MethodName::TaylorDd, 1e-34, None)
        .propagate_f64(&p, &grid)
        .is_ok());
    let e = config(MethodName::TaylorMp, 1e-40, Some(30)).propagate_f64(&p, &grid);
    assert!(matches!(e, Err(DynamicsError::Settings(_))), "{e:?}");
    // Digits out of range.
    let c = MethodConfig::new(
        MethodName::TaylorMp,
        Tolerances::new(1e-9, 1e-9).unwrap(),
        None,
    );
    assert!(c.clone().unwrap().with_digits(5).is_err());
    assert!(c.unwrap().with_digits(1_000_000).is_err());
    // Tolerances set by hand to nonsense.
    let t = Taylor::new(Tolerances {
        rtol: -1.0,
        atol: 1e-9,
    });
    assert!(t.propagate_grid(&p, &grid).is_err());
    // A non-finite state.
    let mut bad = p.clone();
    bad.initial.omega[0] = f64::NAN;
    assert!(Taylor::new(Tolerances::new(1e-9, 1e-9).unwrap())
        .propagate_grid(&bad, &grid)
        .is_err());
}

#[test]
fn zero_length_and_single_sample_grids() {
    let p = problem(2);
    let t = Taylor::new(Tolerances::new(1e-12, 1e-12).unwrap());
    let sol = t
        .propagate_grid(&p, &OutputGrid::new(0.0, 1).unwrap())
        .unwrap();
    assert_eq!(sol.states, vec![p.initial.clone()]);
    let sol = t
        .propagate_grid(&p, &OutputGrid::new(3.0, 2).unwrap())
        .unwrap();
    assert_eq!(sol.times, vec![0.0, 3.0]);
    assert_eq!(sol.states[0], p.initial);
}

/// The euler–Poisson table with the sign of ω̇₁'s quadratic term flipped.
fn broken_table() -> [Component; 9] {
    static BROKEN: [Quadratic; 1] = [Quadratic {
        c: -0.5,
        param: rsts_dynamics::equations::Param::One,
        i: 1,
        j: 2,
    }];
    let mut table = EULER_POISSON;
    table[0].quadratic = &BROKEN;
    table
}

/// The checks above fail on wrong equations: the Taylor integrator fed a broken table (one sign
/// of one quadratic term) disagrees with Dop853 on the right table by far more than the 1e-12
/// of the agreement test, and does not conserve the energy (the run is short: the broken
/// equations no longer conserve anything and the solution grows quickly).
#[test]
fn the_checks_fail_on_a_broken_table() {
    let seed = SEEDS[0];
    let t_end = 2.0;
    let grid = OutputGrid::new(t_end, SAMPLES).unwrap();
    let p = problem(seed);
    let broken = VectorField::from_table(&p.fields, &broken_table());
    let sol = Taylor::new(Tolerances::new(1e-15, 1e-15).unwrap())
        .propagate_field(broken, &p, &grid)
        .unwrap();
    let sol = map_solution(sol, |x| Float::with_val(CMP_BITS, *x));
    let dop = run(MethodName::Dop853, 1e-13, None, seed, t_end);
    let err = max_diff(&sol, &dop);
    eprintln!("broken table: deviation {err:e}");
    assert!(err > 1e-3, "broken table not detected: {err:e}");
    let h0 = integrals(&p.fields, &p.initial).h;
    let drift = sol
        .states
        .iter()
        .map(|s| (integrals(&p.fields, &s.map(|x| x.to_f64())).h - h0).abs())
        .fold(0.0, f64::max);
    eprintln!("broken table: energy drift {drift:e}");
    assert!(
        drift > 1e-3,
        "energy conserved by a broken table: {drift:e}"
    );
}

/// The compensated state pushes the f64 error floor down: at tolerance 1e-15 over t = 200, the
/// error against a 40-digit run is several times smaller than with plain summation of the
/// state (geometric mean of the ratio over the seeds at least 3; with compensation switched
/// off in both runs the ratio is 1 and this fails).
#[test]
fn compensated_summation_lowers_the_f64_error_floor() {
    let t_end = 200.0;
    let grid = OutputGrid::new(t_end, SAMPLES).unwrap();
    let taylor = Taylor::new(Tolerances::new(1e-15, 1e-15).unwrap());
    let widen = |x: &f64| Float::with_val(CMP_BITS, *x);
    let mut log_ratio = 0.0;
    for seed in SEEDS {
        let reference = run(MethodName::TaylorMp, 1e-40, Some(40), seed, t_end);
        let p = map_problem(&problem_mp(seed), |x| x.to_f64());
        let comp = map_solution(taylor.propagate_grid(&p, &grid).unwrap(), widen);
        let plain = taylor.uncompensated().propagate_grid(&p, &grid).unwrap();
        let plain = map_solution(plain, widen);
        let (ec, ep) = (max_diff(&reference, &comp), max_diff(&reference, &plain));
        eprintln!("seed {seed}: error compensated {ec:e}, plain {ep:e}");
        assert!(ec < 1e-12, "seed {seed}: compensated error {ec:e}");
        log_ratio += (ep / ec).ln() / SEEDS.len() as f64;
    }
    let ratio = log_ratio.exp();
    assert!(ratio >= 3.0, "compensation gains only a factor {ratio}");
}

/// Cross-check against an external reference trajectory (format `rsts-reference-1`, see
/// scripts/heyoka_reference.py, which writes one with heyoka in MPFR):
/// `RSTS_REFERENCE="$PWD/ref.json" cargo test --release --workspace --test dynamics -- --ignored
/// taylor::external_reference` (cargo runs the test in crates/dynamics, so a relative path is read from
/// there; `--workspace` reuses the build of scripts/test.sh).
/// Runs taylor-mp at 50 digits and taylor-f64 at 1e-15 from the file's initial state (parsed at
/// 300 bits) and requires agreement to 1e-40 and 1e-13 at every sample.
#[test]
#[ignore = "needs RSTS_REFERENCE=<reference JSON file>"]
fn external_reference_agrees() {
    let path = std::env::var("RSTS_REFERENCE").expect("set RSTS_REFERENCE to a reference file");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "RSTS_REFERENCE={path}: {e} (read from {}, where cargo runs this test: give an \
             absolute path, e.g. \"$PWD/out/ref.json\")",
            std::env::current_dir().unwrap().display()
        )
    });
    let json: serde_json::Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("RSTS_REFERENCE={path}: not JSON: {e}"));
    assert_eq!(
        json["format"], "rsts-reference-1",
        "{path}: not an rsts-reference-1 file"
    );
    let num = |v: &serde_json::Value| -> Float {
        let s = v.as_str().expect("numbers are decimal strings");
        Float::with_val(CMP_BITS, Float::parse(s).unwrap())
    };
    let times: Vec<f64> = json["times"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| num(t).to_f64())
        .collect();
    let states: Vec<State<Float>> = json["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let x: Vec<Float> = s.as_array().unwrap().iter().map(num).collect();
            State::from_slice(&x)
        })
        .collect();
    let n = times.len();
    let grid = OutputGrid::new(times[n - 1], n).unwrap();
    for (k, t) in times.iter().enumerate() {
        assert!(
            (grid.time(k) - t).abs() <= 1e-15 * t.max(1.0),
            "times must be evenly spaced"
        );
    }
    let reference = Solution {
        method: "reference",
        times: grid.times(),
        states,
        stats: Default::default(),
    };
    let problem = Problem {
        fields: Fields {
            a: num(&json["a"]),
            b: num(&json["b"]),
        },
        initial: reference.states[0].clone(),
    };
    for (method, tol, digits, bound) in [
        (MethodName::TaylorMp, 1e-50, Some(50), 1e-40),
        (MethodName::TaylorF64, 1e-15, None, 1e-13),
    ] {
        let sol = config(method, tol, digits)
            .propagate_mp(&problem, &grid)
            .unwrap();
        let err = max_diff(&reference, &sol);
        eprintln!("{method} vs {path}: {err:e}");
        assert!(err < bound, "{method}: {err:e}");
    }
}

/// The buffered coefficient routine used by the integrator agrees with the plain
/// `taylor_coefficient` (both from the one table), and J·v with the Jacobian matrix times v.
#[test]
fn buffered_coefficients_and_jvp_match_the_plain_forms() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let fields = Fields::new(1.3, 0.7).unwrap();
    let field = VectorField::new(&fields);
    let len = 12;
    let series: Vec<Vec<f64>> = (0..9)
        .map(|_| (0..len).map(|_| rng.gen_range(-1.0..1.0)).collect())
        .collect();
    let mut out = vec![0.0; 9];
    let mut scratch = 0.0;
    for n in 0..len {
        let plain = field.taylor_coefficient(&series, n);
        field.taylor_coefficient_into(&series, n, &mut out, &mut scratch);
        for (a, b) in plain.iter().zip(&out) {
            assert!(
                (a - b).abs() <= 1e-14 * (n as f64 + 1.0),
                "order {n}: {a} vs {b}"
            );
        }
    }
    let x: [f64; 9] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
    let v: [f64; 9] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
    let jac = field.jacobian(&x);
    let jv = field.jacobian_vector_product(&x, &v);
    for (row, w) in jac.iter().zip(&jv) {
        let expected: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
        assert!((expected - w).abs() < 1e-14, "{expected} vs {w}");
    }
}

/// The integrator's kernel (`taylor_coefficient_orders`: series order by order, factors gathered
/// per order, the term list derived from the table at compile time) gives bit-for-bit the
/// coefficients of the plain buffered table evaluation `taylor_coefficient_into` on random
/// series, called in sequence n = 0, 1, … and out of sequence; a table other than
/// EULER_POISSON (the broken one) goes through the run-time term list and agrees as well.
#[test]
fn order_major_kernel_matches_the_table_evaluation() {
    use rsts_dynamics::equations::CauchyScratch;
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let fields = Fields::new(1.3, 0.7).unwrap();
    for field in [
        VectorField::new(&fields),
        VectorField::from_table(&fields, &broken_table()),
    ] {
        for len in [1, 2, 7, 20, 33] {
            let series: Vec<Vec<f64>> = (0..9)
                .map(|_| (0..len).map(|_| rng.gen_range(-1.0..1.0)).collect())
                .collect();
            let rows: Vec<[f64; 9]> = (0..len)
                .map(|m| std::array::from_fn(|i| series[i][m]))
                .collect();
            let mut out = vec![0.0; 9];
            let mut scratch = 0.0;
            let mut fast = [0.0; 9];
            let mut cauchy = CauchyScratch::new(&0.0);
            let check = |n: usize, out: &[f64], fast: &[f64; 9]| {
                for (a, b) in out.iter().zip(fast) {
                    assert_eq!(
                        a.to_bits() & !(1 << 63),
                        b.to_bits() & !(1 << 63),
                        "order {n}"
                    );
                    assert!(a == b, "order {n}: {a} vs {b}");
                }
            };
            for n in 0..len {
                field.taylor_coefficient_into(&series, n, &mut out, &mut scratch);
                field.taylor_coefficient_orders(&rows, n, &mut fast, &mut cauchy);
                check(n, &out, &fast);
            }
            // Out of sequence (a fresh gather of all rows).
            for n in (0..len).rev() {
                field.taylor_coefficient_into(&series, n, &mut out, &mut scratch);
                field.taylor_coefficient_orders(&rows, n, &mut fast, &mut cauchy);
                check(n, &out, &fast);
            }
        }
    }
}

/// Per-step time of taylor-f64 at 1e-15 over T = 100 (the benchmark case): best of 300 runs of
/// the integrator's own clock. `cargo test -p rsts-dynamics --release --test dynamics -- --ignored
/// taylor::taylor_f64_per_step_time --nocapture`.
#[test]
#[ignore]
fn taylor_f64_per_step_time() {
    let (s, c) = 0.3f64.sin_cos();
    let problem = Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: State {
            omega: [0.4, -0.7, 1.1],
            alpha: [c, s, 0.0],
            beta: [-s, c, 0.0],
        },
    };
    let grid = OutputGrid::new(100.0, 101).unwrap();
    let cfg = MethodConfig::new(
        MethodName::TaylorF64,
        Tolerances::new(1e-15, 1e-15).unwrap(),
        None,
    )
    .unwrap();
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..300 {
        let sol = cfg.propagate_f64(&problem, &grid).unwrap();
        best = best.min(sol.stats.integration_seconds);
        steps = sol.stats.accepted_steps;
    }
    eprintln!(
        "taylor-f64 1e-15: {steps} steps, best {:.3} ms, {:.3} µs/step",
        best * 1e3,
        best * 1e6 / steps as f64
    );
}
