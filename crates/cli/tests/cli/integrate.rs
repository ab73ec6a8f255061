//! `rsts integrate` as a user runs it: the built binary with arguments, checking exit codes,
//! stderr messages and the JSON/CSV/table output.

use std::process::Output;

use serde_json::Value;

use crate::common;
use common::{rsts, rsts_command, stderr, stdout};

fn integrate(args: &[&str]) -> Output {
    rsts_command("integrate", args)
}

/// Run, insist on success, return stdout.
fn ok(args: &[&str]) -> String {
    let out = integrate(args);
    assert!(
        out.status.success(),
        "rsts integrate {args:?} failed ({:?}): {}",
        out.status.code(),
        stderr(&out)
    );
    stdout(&out)
}

fn json(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.extend_from_slice(&["--format", "json"]);
    let text = ok(&all);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("invalid JSON ({e}):\n{text}"))
}

fn num(v: &Value, what: &str) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"))
}

fn vec3(v: &Value, what: &str) -> [f64; 3] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("{what} is not an array: {v}"));
    assert_eq!(a.len(), 3, "{what} must have 3 components: {v}");
    std::array::from_fn(|i| num(&a[i], what))
}

/// A non-trivial state, valid to ~1e-16: ω, α = (cos θ, sin θ, 0), β = (−sin θ cos φ, cos θ cos φ, sin φ).
fn valid_state_args() -> Vec<String> {
    let (th, ph) = (0.7f64, 0.4f64);
    let alpha = [th.cos(), th.sin(), 0.0];
    let beta = [-th.sin() * ph.cos(), th.cos() * ph.cos(), ph.sin()];
    let v = |x: [f64; 3]| format!("{:?},{:?},{:?}", x[0], x[1], x[2]);
    vec![
        "--a".into(),
        "1.3".into(),
        "--b".into(),
        "0.6".into(),
        "--omega".into(),
        "-0.8,0.5,1.1".into(),
        "--alpha".into(),
        v(alpha),
        "--beta".into(),
        v(beta),
    ]
}

#[test]
fn default_case_runs_without_options() {
    let text = ok(&[]);
    assert!(text.contains("dop853"), "{text}");
    for col in ["t", "omega1", "beta3", "H", "K", "G"] {
        assert!(text.contains(col), "table lacks column {col}:\n{text}");
    }
}

#[test]
fn json_has_every_field_and_the_requested_grid() {
    let v = json(&["--t-end", "5", "--samples", "6"]);
    assert_eq!(num(&v["a"], "a"), 1.0);
    assert_eq!(num(&v["b"], "b"), 0.5);
    assert_eq!(v["method"], "dop853");
    let samples = v["samples"].as_array().expect("samples is an array");
    assert_eq!(samples.len(), 6);
    for (k, s) in samples.iter().enumerate() {
        let t = num(&s["t"], "t");
        assert!((t - k as f64).abs() < 1e-9, "sample {k} at t = {t}");
        for key in ["omega", "alpha", "beta"] {
            vec3(&s[key], key);
        }
        for key in ["H", "K", "G"] {
            num(&s[key], key);
        }
    }
    let first = &samples[0];
    assert_eq!(vec3(&first["omega"], "omega"), [0.3, -0.2, 0.5]);
    assert_eq!(vec3(&first["alpha"], "alpha"), [1.0, 0.0, 0.0]);
    assert_eq!(vec3(&first["beta"], "beta"), [0.0, 1.0, 0.0]);
    // H = ω₁² + ω₂² + ω₃²/2 − (aα₁ + bβ₂) at the default initial state.
    let h0 = 0.09 + 0.04 + 0.125 - (1.0 + 0.5);
    assert!((num(&first["H"], "H") - h0).abs() < 1e-15);
    let stats = &v["stats"];
    for key in ["accepted_steps", "rejected_steps", "rhs_evals"] {
        assert!(stats[key].is_u64(), "stats.{key} missing: {stats}");
    }
    assert!(stats["accepted_steps"].as_u64().unwrap() > 0);
    assert!(stats["rhs_evals"].as_u64().unwrap() > stats["accepted_steps"].as_u64().unwrap());
    assert!(num(&stats["integration_seconds"], "integration_seconds") >= 0.0);
}

#[test]
fn csv_has_a_header_and_one_row_per_sample() {
    for (n, t_end) in [(1usize, 3.0), (2, 3.0), (17, 3.0), (4, 0.0)] {
        let ns = n.to_string();
        let ts = t_end.to_string();
        let text = ok(&["--samples", &ns, "--t-end", &ts, "--format", "csv"]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), n + 1, "N = {n}:\n{text}");
        let header: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(header.len(), 13);
        assert_eq!(header[0], "t");
        assert_eq!(&header[10..], ["H", "K", "G"]);
        for row in &lines[1..] {
            let fields: Vec<f64> = row
                .split(',')
                .map(|x| x.parse().unwrap_or_else(|_| panic!("bad number {x:?}")))
                .collect();
            assert_eq!(fields.len(), 13, "{row}");
        }
        let last_t: f64 = lines[n].split(',').next().unwrap().parse().unwrap();
        let expected = if n == 1 { 0.0 } else { t_end };
        assert!(
            (last_t - expected).abs() < 1e-9,
            "N = {n}: last t = {last_t}"
        );
    }
}

#[test]
fn energy_of_every_sample_stays_within_1e_9_of_the_first() {
    let state = valid_state_args();
    let mut args: Vec<&str> = state.iter().map(String::as_str).collect();
    args.extend_from_slice(&["--t-end", "30", "--samples", "61"]);
    for method in ["dop853", "dopri5"] {
        let mut a = args.clone();
        a.extend_from_slice(&["--method", method]);
        let v = json(&a);
        let samples = v["samples"].as_array().unwrap();
        assert_eq!(samples.len(), 61);
        let h0 = num(&samples[0]["H"], "H");
        for s in samples {
            let h = num(&s["H"], "H");
            assert!(
                (h - h0).abs() < 1e-9,
                "{method}: H = {h} at t = {} vs H(0) = {h0}",
                s["t"]
            );
        }
    }
}

/// The bound above is not vacuous: a coarse fixed-step RK4 breaks it.
#[test]
fn coarse_rk4_violates_the_energy_bound() {
    let state = valid_state_args();
    let mut args: Vec<&str> = state.iter().map(String::as_str).collect();
    args.extend_from_slice(&[
        "--t-end",
        "30",
        "--samples",
        "61",
        "--method",
        "rk4",
        "--step",
        "0.25",
    ]);
    let v = json(&args);
    let samples = v["samples"].as_array().unwrap();
    let h0 = num(&samples[0]["H"], "H");
    let worst = samples
        .iter()
        .map(|s| (num(&s["H"], "H") - h0).abs())
        .fold(0.0, f64::max);
    assert!(worst > 1e-7, "rk4 with step 0.25 drifted only {worst:e}");
}

#[test]
fn table_reports_steps_and_drift() {
    let text = ok(&["--format", "table"]);
    assert!(text.contains("accepted"), "{text}");
    assert!(text.contains("max drift"), "{text}");
    // header + rule + 11 rows
    let rows = text
        .lines()
        .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .count();
    assert_eq!(rows, 11, "{text}");
}

/// Each bad input: exit code 2, nothing on stdout, `error: ` on stderr naming the problem.
#[test]
fn bad_input_is_rejected_with_a_clear_message() {
    let cases: &[(&[&str], &[&str])] = &[
        (&["--a", "0.5", "--b", "1"], &["--a/--b", "b <= a"]),
        (&["--b", "-0.5"], &["--a/--b", "b must be non-negative"]),
        (&["--b=-0.5"], &["--a/--b", "b must be non-negative"]),
        (&["--a", "0"], &["--a/--b", "a must be positive"]),
        (&["--a", "-1"], &["--a/--b", "a must be positive"]),
        (&["--a", "NaN"], &["--a <A>", "finite"]),
        (&["--b", "nan"], &["--b <B>", "finite"]),
        (&["--a", "inf"], &["--a <A>", "finite"]),
        (&["--a", "1e999"], &["--a <A>", "finite"]),
        (&["--a", "abc"], &["--a <A>", "not a number"]),
        (&["--omega", "1,NaN,0"], &["--omega", "finite"]),
        (&["--alpha", "inf,0,0"], &["--alpha", "finite"]),
        (&["--beta", "0,1,-inf"], &["--beta", "finite"]),
        (&["--omega", "1,2"], &["--omega", "exactly 3"]),
        (&["--omega", "1,2,3,4"], &["--omega", "exactly 3"]),
        (&["--alpha", "1"], &["--alpha", "exactly 3"]),
        (&["--beta", ""], &["--beta", "exactly 3"]),
        (&["--omega", "1,x,3"], &["--omega", "not a number"]),
        (&["--alpha", "2,0,0"], &["--alpha", "|alpha| must be 1"]),
        (
            &["--alpha", "1.000001,0,0"],
            &["--alpha", "|alpha| must be 1"],
        ),
        (&["--beta", "0,0.5,0"], &["--beta", "|beta| must be 1"]),
        (&["--beta", "1,0,0"], &["--beta", "orthogonal"]),
        (&["--rtol", "0"], &["--rtol", "rtol must be a positive"]),
        (&["--rtol", "-1e-8"], &["--rtol", "rtol must be a positive"]),
        (&["--atol", "0"], &["--atol", "atol must be a positive"]),
        (&["--rtol", "NaN"], &["--rtol", "finite"]),
        (&["--t-end", "inf"], &["--t-end", "finite"]),
        (&["--t-end", "NaN"], &["--t-end", "finite"]),
        (&["--t-end", "-1"], &["--t-end", "non-negative"]),
        (&["--samples", "0"], &["--samples", "at least 1"]),
        (&["--samples", "-3"], &["--samples", "whole number"]),
        (&["--samples", "2.5"], &["--samples", "whole number"]),
        (&["--method", "euler"], &["--method", "euler", "dop853"]),
        (&["--format", "xml"], &["--format", "xml", "json"]),
        (&["--method", "rk4", "--step", "0"], &["--step", "positive"]),
        (&["--no-such-option"], &["--no-such-option"]),
    ];
    for (args, needles) in cases {
        let out = integrate(args);
        let err = stderr(&out);
        assert_eq!(
            out.status.code(),
            Some(2),
            "rsts integrate {args:?}: exit {:?}, stderr: {err}",
            out.status.code()
        );
        assert!(err.starts_with("error: "), "rsts integrate {args:?}: {err}");
        assert!(
            !err.contains("panicked"),
            "rsts integrate {args:?} panicked: {err}"
        );
        assert!(
            out.stdout.is_empty(),
            "rsts integrate {args:?} printed output"
        );
        for needle in *needles {
            assert!(
                err.contains(needle),
                "rsts integrate {args:?}: stderr lacks {needle:?}: {err}"
            );
        }
    }
}

#[test]
fn help_shows_an_example_for_each_subcommand() {
    let top = rsts(&["--help"]);
    assert!(top.status.success());
    let top = stdout(&top);
    assert!(
        top.contains("Examples:") && top.contains("rsts integrate"),
        "{top}"
    );
    let sub = rsts(&["integrate", "--help"]);
    assert!(sub.status.success());
    let sub = stdout(&sub);
    assert!(sub.contains("Examples:"), "{sub}");
    assert!(sub.contains("rsts integrate --a"), "{sub}");
}

#[test]
fn missing_subcommand_is_an_error() {
    let out = rsts(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!stderr(&out).contains("panicked"));
}
