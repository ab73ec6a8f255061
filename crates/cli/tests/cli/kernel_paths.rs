//! Every code path of the Taylor kernels, forced through the environment as a user (or CI)
//! forces it: `RSTS_SIMD=avx512|avx2|portable` for taylor-f64 and taylor-dd, and
//! `RSTS_MPFR_KERNEL=limbs|generic` for taylor-mp, each run end to end through `rsts bench`.
//! A path this CPU cannot run is reported as skipped (rsts_io::report_skip) and must be refused
//! with exit 2; an unknown value is refused with exit 2 naming the variable.

use std::process::{Command, Output};

use rsts_dynamics::integrators::{SimdPath, SIMD_ENV};
use serde_json::Value;

const MPFR_ENV: &str = "RSTS_MPFR_KERNEL";

/// `rsts bench` (T = 10, 21 samples, one repeat) with one environment variable set.
fn bench_with(var: &str, value: &str, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args([
            "bench",
            "--t-end",
            "10",
            "--samples",
            "21",
            "--repeats",
            "1",
            "--format",
            "json",
        ])
        .args(extra)
        .env_remove(SIMD_ENV)
        .env_remove(MPFR_ENV)
        .env(var, value)
        .output()
        .expect("run the rsts binary")
}

/// (method, tolerance) → (max error, steps) of a successful run.
fn rows(out: &Output, what: &str) -> Vec<(String, f64, f64, u64)> {
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    doc["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["method"].as_str().unwrap().to_string(),
                r["tolerance"].as_f64().unwrap(),
                r["max_error"].as_f64().unwrap(),
                r["steps"].as_u64().unwrap(),
            )
        })
        .collect()
}

const LANE_ARGS: [&str; 4] = [
    "--methods",
    "taylor-f64,taylor-dd",
    "--tolerances",
    "1e-13,1e-28",
];

#[test]
fn every_simd_path_runs_end_to_end_and_agrees() {
    let mut runs = Vec::new();
    for path in SimdPath::ALL {
        let out = bench_with(SIMD_ENV, path.as_str(), &LANE_ARGS);
        if !path.available() {
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{path}: {err}");
            assert!(
                err.contains(SIMD_ENV) && err.contains("cannot run"),
                "{err}"
            );
            rsts_io::report_skip(
                "every_simd_path_runs_end_to_end_and_agrees",
                &format!("this CPU has no {path} path (refused with exit 2, as it should)"),
            );
            continue;
        }
        let rows = rows(&out, path.as_str());
        // taylor-f64 at 1e-13 (its 1e-28 row is below round-off, skipped), taylor-dd at both.
        assert_eq!(rows.len(), 3, "{path}: {rows:?}");
        for (method, tol, err, steps) in &rows {
            assert!(*steps > 0, "{path} {method}");
            let bound = if method == "taylor-f64" {
                1e-12
            } else {
                1e3 * tol
            };
            assert!(
                *err <= bound,
                "{path}: {method} at {tol:e}: error {err:e} > {bound:e}"
            );
        }
        runs.push((path, rows));
    }
    assert!(!runs.is_empty(), "the portable path always runs");
    // All paths take the same steps and reach the same errors to within round-off.
    let (first, reference) = &runs[0];
    for (path, rows) in &runs[1..] {
        for (a, b) in reference.iter().zip(rows) {
            assert_eq!((&a.0, a.1, a.3), (&b.0, b.1, b.3), "{first} vs {path}");
            assert!(
                (a.2 - b.2).abs() <= 0.1 * a.2.max(b.2),
                "{first} vs {path}: {a:?} / {b:?}"
            );
        }
    }
}

#[test]
fn unknown_kernel_names_are_refused_naming_the_variable() {
    for (var, extra) in [
        (SIMD_ENV, &LANE_ARGS[..]),
        (
            MPFR_ENV,
            &["--methods", "taylor-mp", "--tolerances", "1e-20"][..],
        ),
    ] {
        let out = bench_with(var, "sse9", extra);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{var}: {err}");
        assert!(err.contains(var) && err.contains("sse9"), "{var}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(out.stdout.is_empty(), "{var}: no partial document");
    }
}

#[test]
fn both_mpfr_kernels_run_end_to_end_and_agree() {
    let args = [
        "--methods",
        "taylor-mp",
        "--digits",
        "40",
        "--tolerances",
        "1e-30",
    ];
    let limbs = rows(&bench_with(MPFR_ENV, "limbs", &args), "limbs");
    let generic = rows(&bench_with(MPFR_ENV, "generic", &args), "generic");
    assert_eq!(limbs.len(), 1);
    let (l, g) = (&limbs[0], &generic[0]);
    assert_eq!(l.3, g.3, "same steps");
    assert!(l.2 <= 1e-28 && g.2 <= 1e-28, "{l:?} {g:?}");
    assert!((l.2 - g.2).abs() <= 0.1 * l.2.max(g.2), "{l:?} {g:?}");
}
