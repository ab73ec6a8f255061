//! `--dense K` of `rsts compare`: the dense output inside the integrator's own steps against the
//! closed form, apart from the step ends — for the built-ins and for adapters (the example RK4 with
//! its Hermite interpolant and with a deliberately low-order linear one); bad input exits 2.

use serde_json::Value;

use crate::common;
use common::{
    adapter_command, adapter_rk4, command_json, exit_2, json_doc, python_with, rsts_command,
};

fn compare(args: &[&str]) -> Value {
    let mut all = vec!["--t-end", "5", "--samples", "11"];
    all.extend_from_slice(args);
    command_json("compare", &all)
}

fn errors(doc: &Value) -> (f64, f64) {
    let f = |k: &str| doc[k].as_f64().unwrap_or_else(|| panic!("no {k} in {doc}"));
    (f("dense_max_error"), f("step_max_error"))
}

/// The built-ins' interpolants keep the dense error at the level of the step ends; the JSON
/// states K and the steps, the table has its line, the CSV its columns.
#[test]
fn builtins_report_dense_and_step_errors() {
    for (method, tol) in [
        ("rk4", "1e-10"),
        ("dopri5", "1e-9"),
        ("dop853", "1e-11"),
        ("taylor-f64", "1e-12"),
        ("taylor-dd", "1e-12"),
        ("taylor-mp", "1e-12"),
    ] {
        let doc = compare(&[
            "--method", method, "--rtol", tol, "--atol", tol, "--dense", "3",
        ]);
        assert_eq!(doc["dense"], 3, "{doc}");
        assert!(doc["dense_steps"].as_u64().unwrap() >= 10, "{doc}");
        let (dense, step) = errors(&doc);
        assert!(step > 0.0 && step < 1e-6, "{method}: {doc}");
        assert!(
            dense < 30.0 * step,
            "{method}: dense {dense:e}, steps {step:e}"
        );
    }
    let table = rsts_command(
        "compare",
        &["--t-end", "5", "--samples", "11", "--dense", "2"],
    );
    let text = String::from_utf8(table.stdout).unwrap();
    assert!(text.contains("dense output: max error"), "{text}");
    let csv = rsts_command(
        "compare",
        &[
            "--t-end",
            "5",
            "--samples",
            "11",
            "--dense",
            "2",
            "--format",
            "csv",
        ],
    );
    let header = String::from_utf8(csv.stdout).unwrap();
    assert!(
        header.lines().next().unwrap().contains("dense_max_error"),
        "{header}"
    );
}

/// An interpolant of lower order shows up: the example RK4's chord (linear, error O(h²)) makes
/// the dense error far larger than the step ends', its Hermite cubic does not; halving the step
/// divides the dense error by about 2² and 2⁴ (the observed orders of the two interpolants).
#[test]
fn a_low_order_interpolant_shows_up_with_its_order() {
    let rk4 = adapter_rk4();
    let run = |interp: &str, step: &str| {
        let cmd = format!("{} --interpolant {interp} --step {step}", rk4.display());
        errors(&compare(&["--exec", &cmd, "--dense", "3"]))
    };
    let (lin1, step1) = run("linear", "0.02");
    let (lin2, _) = run("linear", "0.01");
    let (her1, her_step1) = run("hermite", "0.02");
    let (her2, _) = run("hermite", "0.01");
    assert_eq!(
        step1, her_step1,
        "the interpolant does not change the steps"
    );
    assert!(lin1 > 1000.0 * step1, "linear {lin1:e} vs steps {step1:e}");
    assert!(
        her1 < 3.0 * her_step1,
        "hermite {her1:e} vs steps {her_step1:e}"
    );
    let (p_lin, p_her) = ((lin1 / lin2).log2(), (her1 / her2).log2());
    assert!((p_lin - 2.0).abs() < 0.3, "linear: observed order {p_lin}");
    assert!((p_her - 4.0).abs() < 0.5, "hermite: observed order {p_her}");
}

/// K out of range, a file, an adapter that ignores `dense`.
#[test]
fn bad_dense_input_exits_2_with_a_message() {
    let base = ["--t-end", "2", "--samples", "3"];
    for (extra, needle) in [
        (&["--dense", "0"][..], "--dense: K must be between 1 and 64"),
        (
            &["--dense", "65"][..],
            "--dense: K must be between 1 and 64",
        ),
    ] {
        let out = rsts_command("compare", &[&base[..], extra].concat());
        let err = exit_2(&out, extra);
        assert!(err.contains(needle), "{err}");
        assert!(out.stdout.is_empty());
    }
    let out = rsts_command("check", &["x.csv", "--dense", "3"]);
    assert!(exit_2(&out, "check --dense").contains("a trajectory file does not say"));
    let cmd = format!("{} --ignore-dense", adapter_rk4().display());
    let out = rsts_command(
        "compare",
        &[&base[..], &["--exec", &cmd, "--dense", "2"]].concat(),
    );
    let err = exit_2(&out, "adapter without dense");
    assert!(
        err.contains("example-adapter-rk4 --ignore-dense")
            && err.contains("has no \"stats.step_times\""),
        "{err}"
    );
}

/// `bench --dense K`: every row carries the dense check (JSON fields, table columns); the
/// adapter's chord shows up in its rows only; K out of range exits 2.
#[test]
fn bench_rows_carry_the_dense_check() {
    let rk4 = adapter_rk4();
    let linear = format!("{} --interpolant linear", rk4.display());
    let args = [
        "--methods",
        "dopri5",
        "--exec",
        &linear,
        "--tolerances",
        "1e-6,1e-8",
        "--t-end",
        "5",
        "--samples",
        "51",
        "--repeats",
        "1",
        "--dense",
        "2",
    ];
    let out = rsts_command("bench", &[&args[..], &["--format", "json"]].concat());
    let doc = json_doc(&out);
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4, "{doc}");
    for row in rows {
        assert_eq!(row["dense"], 2, "{row}");
        let (dense, step) = errors(row);
        match row["method"].as_str().unwrap() {
            "dopri5" => assert!(dense < 30.0 * step, "{row}"),
            "example-rk4-linear" => assert!(dense > 1000.0 * step, "{row}"),
            other => panic!("unexpected row {other}"),
        }
    }
    let table = rsts_command("bench", &args);
    let text = String::from_utf8(table.stdout).unwrap();
    assert!(text.contains("dense max error"), "{text}");
    let bad = rsts_command(
        "bench",
        &["--methods", "taylor-dd", "--dense", "0", "--t-end", "5"],
    );
    assert!(exit_2(&bad, "bench --dense 0").contains("--dense: K must be between 1 and 64"));
}

/// heyoka answers `"dense": K` from its continuous output (`ta.update_d_output`: the Taylor
/// polynomial of each of its steps, full order): in f64 and in MPFR its dense error is of the
/// order of its error at the step ends, and it takes about the steps of rsts' taylor-f64 (the
/// same Jorba–Zou step rule). Skips with a message when heyoka is missing.
#[test]
fn heyoka_answers_dense_from_its_taylor_polynomials() {
    let Some(python) = python_with("heyoka", "heyoka_answers_dense_from_its_taylor_polynomials")
    else {
        return;
    };
    let tol = ["--rtol", "1e-10", "--atol", "1e-10", "--dense", "3"];
    let ours = compare(&[&tol[..], &["--method", "taylor-f64"]].concat());
    let our_steps = ours["dense_steps"].as_f64().unwrap();
    for scalar in ["f64", "mpfr"] {
        let cmd = adapter_command(&python, "heyoka_adapter.py", scalar);
        let doc = compare(&[&tol[..], &["--exec", &cmd]].concat());
        let steps = doc["dense_steps"].as_f64().unwrap();
        let (dense, step) = errors(&doc);
        assert!(step > 0.0 && step < 1e-8, "heyoka {scalar}: {doc}");
        assert!(
            dense <= 10.0 * step,
            "heyoka {scalar}: dense {dense:e}, steps {step:e}"
        );
        assert!(
            (steps / our_steps - 1.0).abs() < 0.2,
            "heyoka {scalar}: {steps} steps, taylor-f64 {our_steps}"
        );
    }
}
