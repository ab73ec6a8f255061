//! The lane kernel against the generic kernel (f64) and against MPFR (every part count), on
//! every code path: the same coefficients to a few units in the last place of their scale,
//! on random states, fields and orders. A path this CPU lacks is skipped with a report.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rug::Float;

use super::fast::{slot_coefficients, FastInput};
use super::layout::Layout;
use super::series::{from_lanes, to_lanes, LaneSeries, Row16, SlotCoefficients};
use super::simd::{portable::Portable, Isa, SimdPath};
use crate::equations::{Component, Param, Quadratic, VectorField, EULER_POISSON};
use crate::fields::Fields;
use crate::state::DIM;

/// Rows x₀ … x_order (natural order, P parts) of the lane kernel on `path` from row 0 `x0`.
fn series_on<const P: usize>(
    path: SimdPath,
    layout: &Layout,
    coef: &SlotCoefficients<P>,
    x0: &[[f64; P]; DIM],
    order: usize,
) -> Vec<[[f64; P]; DIM]> {
    #[inline(always)]
    unsafe fn inner<I: Isa, const P: usize>(
        layout: &Layout,
        coef: &SlotCoefficients<P>,
        x0: &[Row16; P],
        order: usize,
    ) -> Vec<[Row16; P]> {
        let mut s = LaneSeries::<I, P>::new(layout, coef, order, true);
        s.set(0, x0);
        s.advance(0, order);
        s.x.clone()
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2,fma")]
    unsafe fn avx512<const P: usize>(
        l: &Layout,
        c: &SlotCoefficients<P>,
        x: &[Row16; P],
        o: usize,
    ) -> Vec<[Row16; P]> {
        inner::<super::simd::avx512::Avx512, P>(l, c, x, o)
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn avx2<const P: usize>(
        l: &Layout,
        c: &SlotCoefficients<P>,
        x: &[Row16; P],
        o: usize,
    ) -> Vec<[Row16; P]> {
        inner::<super::simd::avx2::Avx2, P>(l, c, x, o)
    }
    assert!(path.available());
    let x0 = to_lanes(layout, x0);
    // SAFETY: the path is available on this CPU (asserted).
    let rows = unsafe {
        match path {
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => avx512(layout, coef, &x0, order),
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => avx2(layout, coef, &x0, order),
            _ => inner::<Portable, P>(layout, coef, &x0, order),
        }
    };
    rows.iter().map(|r| from_lanes(layout, r)).collect()
}

/// The paths to test on this CPU; the others are reported as skipped.
fn paths(test: &str) -> Vec<SimdPath> {
    SimdPath::ALL
        .into_iter()
        .filter(|p| {
            let ok = p.available();
            if !ok {
                rsts_io::report_skip(test, &format!("this CPU has no {p} path"));
            }
            ok
        })
        .collect()
}

/// A random state (|x| ≤ 1.5) and fields, each in P parts (successive residuals of a 300-bit
/// value, so the low parts are full).
fn random_input<const P: usize>(rng: &mut ChaCha8Rng) -> ([[Float; DIM]; 1], FastInput<P>) {
    let parts = |x: &Float| -> [f64; P] {
        let mut rest = x.clone();
        std::array::from_fn(|_| {
            let p = rest.to_f64();
            rest -= p;
            p
        })
    };
    let mut rand = |lo: f64, hi: f64| -> Float {
        Float::with_val(300, rng.gen_range(lo..hi)) / Float::with_val(300, 3)
            + Float::with_val(300, rng.gen_range(lo..hi)) * 1e-20
    };
    let x: [Float; DIM] = std::array::from_fn(|_| rand(-4.5, 4.5));
    let a = rand(1.5, 6.0);
    let b = a.clone() * rng.gen_range(0.0..1.0);
    let input = FastInput {
        x0: std::array::from_fn(|k| parts(&x[k])),
        a: parts(&a),
        b: parts(&b),
    };
    ([x], input)
}

/// Σ over the terms of f(x)ₙ of |c·p|·Σₘ|xᵢ,ₘ xⱼ,ₙ₋ₘ| (and |c·p·xᵢ,ₙ|), divided by n + 1: the
/// scale of the rounding errors of xₙ₊₁ (its condition), per component.
fn scale(
    table: &[Component; DIM],
    fields: &Fields<f64>,
    rows: &[[f64; DIM]],
    n: usize,
) -> [f64; DIM] {
    let p = |param: Param| match param {
        Param::One => 1.0,
        Param::A => fields.a,
        Param::B => fields.b,
    };
    std::array::from_fn(|k| {
        let mut s = 0.0;
        for t in table[k].quadratic {
            let sum: f64 = (0..=n)
                .map(|m| (rows[m][t.i] * rows[n - m][t.j]).abs())
                .sum();
            s += (t.c * p(t.param)).abs() * sum;
        }
        for t in table[k].linear {
            s += (t.c * p(t.param) * rows[n][t.i]).abs();
        }
        s / (n + 1) as f64
    })
}

/// max over orders and components of |kernel − reference| / (2^(−53P) · scale): the error in
/// units of the last place of the coefficients' scale, for the kernel built from `kernel_table`
/// against the generic kernel (in MPFR at 300 bits) built from `reference_table`.
fn ulps_against_mpfr<const P: usize>(
    path: SimdPath,
    kernel_table: &[Component; DIM],
    reference_table: &[Component; DIM],
    seed: u64,
    order: usize,
) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (_, input) = random_input::<P>(&mut rng);
    let layout = Layout::from_table(kernel_table).expect("the table fits");
    // SAFETY: the portable path runs anywhere.
    let coef = unsafe { slot_coefficients::<Portable, P>(&layout, &input) };
    let rows = series_on::<P>(path, &layout, &coef, &input.x0, order);
    let float = |x: &[f64; P]| -> Float {
        let mut f = Float::with_val(300, 0);
        for p in x {
            f += p;
        }
        f
    };
    let fields = Fields {
        a: float(&input.a),
        b: float(&input.b),
    };
    let field = VectorField::from_table(&fields, reference_table);
    let mp_rows: Vec<[Float; DIM]> = rows.iter().map(|r| r.each_ref().map(float)).collect();
    let f64_rows: Vec<[f64; DIM]> = mp_rows
        .iter()
        .map(|r| r.each_ref().map(|x| x.to_f64()))
        .collect();
    let f64_fields = Fields {
        a: fields.a.to_f64(),
        b: fields.b.to_f64(),
    };
    let mut out: [Float; DIM] = std::array::from_fn(|_| Float::with_val(300, 0));
    let mut scratch = crate::equations::CauchyScratch::new(&Float::with_val(300, 0));
    let ulp = 2f64.powi(-53 * P as i32);
    let mut worst: f64 = 0.0;
    for n in 0..order {
        field.taylor_coefficient_orders(&mp_rows[..=n], n, &mut out, &mut scratch);
        let s = scale(reference_table, &f64_fields, &f64_rows, n);
        for k in 0..DIM {
            let exact = Float::with_val(300, &out[k] / (n + 1) as u32);
            let err = Float::with_val(300, &mp_rows[n + 1][k] - &exact)
                .abs()
                .to_f64();
            worst = worst.max(err / (ulp * s[k]).max(f64::MIN_POSITIVE));
        }
    }
    worst
}

/// The Euler–Poisson table with the sign of ω̇₁'s quadratic term flipped.
fn broken_table() -> [Component; DIM] {
    static BROKEN: [Quadratic; 1] = [Quadratic {
        c: -0.5,
        param: Param::One,
        i: 1,
        j: 2,
    }];
    let mut table = EULER_POISSON;
    table[0].quadratic = &BROKEN;
    table
}

/// f64 (P = 1) on every path: x₁ … xₚ agree with the generic kernel (`VectorField::
/// taylor_coefficient_orders` in f64, the same rows as input) to a few ulp of their scale, on
/// random states, fields and orders up to 40; for the table and for a broken one (both through
/// the lane layout generated from them).
#[test]
fn f64_lane_coefficients_agree_with_the_generic_kernel_on_every_path() {
    for path in paths("f64_lane_coefficients_agree_with_the_generic_kernel_on_every_path") {
        let mut worst: f64 = 0.0;
        for table in [EULER_POISSON, broken_table()] {
            for seed in 0..6 {
                let order = [4, 19, 40][seed as usize % 3];
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let (_, input) = random_input::<1>(&mut rng);
                let layout = Layout::from_table(&table).unwrap();
                // SAFETY: the portable path runs anywhere.
                let coef = unsafe { slot_coefficients::<Portable, 1>(&layout, &input) };
                let rows = series_on::<1>(path, &layout, &coef, &input.x0, order);
                let rows: Vec<[f64; DIM]> = rows.iter().map(|r| r.map(|x| x[0])).collect();
                let fields = Fields {
                    a: input.a[0],
                    b: input.b[0],
                };
                let field = VectorField::from_table(&fields, &table);
                let mut out = [0.0; DIM];
                let mut scratch = crate::equations::CauchyScratch::new(&0.0);
                for n in 0..order {
                    field.taylor_coefficient_orders(&rows[..=n], n, &mut out, &mut scratch);
                    let s = scale(&table, &fields, &rows, n);
                    for k in 0..DIM {
                        let generic = out[k] / (n + 1) as f64;
                        let ulps = (rows[n + 1][k] - generic).abs() / (f64::EPSILON * s[k]);
                        worst = worst.max(ulps);
                    }
                }
            }
        }
        eprintln!("{path}: f64 lane kernel vs generic kernel: {worst:.2} ulp of the scale");
        assert!(worst <= 4.0, "{path}: {worst} ulp");
    }
}

/// Every part count on every path against MPFR at 300 bits (the generic kernel in
/// `rug::Float` from the kernel's own rows): f64 (P = 1), double-double (P = 2, the taylor-dd
/// kernel, orders up to 40) and triple-double (P = 3, the extended orders of taylor-dd) agree
/// to a few units of 2^(−53P) of their scale. The check fails on a kernel built from a
/// broken table.
#[test]
fn lane_coefficients_agree_with_mpfr_on_every_path() {
    let test = "lane_coefficients_agree_with_mpfr_on_every_path";
    for path in paths(test) {
        let mut worst = [0.0f64; 3];
        for seed in 0..4 {
            worst[0] = worst[0].max(ulps_against_mpfr::<1>(
                path,
                &EULER_POISSON,
                &EULER_POISSON,
                seed,
                30,
            ));
            worst[1] = worst[1].max(ulps_against_mpfr::<2>(
                path,
                &EULER_POISSON,
                &EULER_POISSON,
                seed,
                40,
            ));
            worst[2] = worst[2].max(ulps_against_mpfr::<3>(
                path,
                &EULER_POISSON,
                &EULER_POISSON,
                seed,
                4,
            ));
        }
        eprintln!("{path}: lane kernel vs MPFR, ulps of the scale for 1, 2, 3 parts: {worst:?}");
        assert!(
            worst[0] <= 4.0 && worst[1] <= 6.0 && worst[2] <= 6.0,
            "{path}: {worst:?}"
        );
        let wrong = ulps_against_mpfr::<2>(path, &broken_table(), &EULER_POISSON, 0, 10);
        assert!(wrong > 1e10, "{path}: a broken kernel passes ({wrong} ulp)");
    }
}

#[test]
fn simd_paths_resolve_from_the_environment_value() {
    assert_eq!(SimdPath::resolve(None).unwrap(), SimdPath::detect());
    assert_eq!(SimdPath::resolve(Some("")).unwrap(), SimdPath::detect());
    assert_eq!(
        SimdPath::resolve(Some("portable")).unwrap(),
        SimdPath::Portable
    );
    assert_eq!(
        SimdPath::resolve(Some(" PORTABLE ")).unwrap(),
        SimdPath::Portable
    );
    let e = SimdPath::resolve(Some("sse9")).unwrap_err().to_string();
    assert!(e.contains("unknown path"), "{e}");
    for p in [SimdPath::Avx2, SimdPath::Avx512] {
        match SimdPath::resolve(Some(p.as_str())) {
            Ok(q) => assert!(q == p && p.available()),
            Err(e) => {
                assert!(!p.available());
                assert!(e.to_string().contains("cannot run"), "{e}");
            }
        }
    }
    assert!(SimdPath::detect().available());
}
