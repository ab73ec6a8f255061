//! `rsts convergence`: observed orders of methods of known order, run as external adapters
//! (crates/example-adapter-rk4 with `--tableau`), each sweep reaching from pre-asymptotic steps
//! into the round-off floor; every fit recomputed independently in Python from the rows.

use std::process::Command;

use serde_json::Value;

use crate::common;
use common::{adapter_command, adapter_rk4, exit_2, python_with, rsts, s, stderr, tmp};

fn json(args: &[&str]) -> Value {
    let mut all = vec!["convergence"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--format", "json"]);
    let out = rsts(&all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice(&out.stdout).expect("one JSON document on stdout")
}

/// Least squares of log10(max_error) against log10(step) over the rows inside each fit's window,
/// in plain Python (not our code): (slope, stderr) per method. `None` without python3.
fn python_fits(report: &Value) -> Option<Vec<(f64, f64)>> {
    const SCRIPT: &str = r#"
import json, math, sys
doc = json.load(sys.stdin)
for fit in doc["fits"]:
    lo, hi = fit["window"]
    pts = [(math.log10(r["step"]), math.log10(r["max_error"])) for r in doc["rows"]
           if r["method"] == fit["method"] and lo <= r["step"] <= hi]
    n = len(pts)
    mx = sum(x for x, _ in pts) / n
    my = sum(y for _, y in pts) / n
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    p = sum((x - mx) * (y - my) for x, y in pts) / sxx
    c = my - p * mx
    ssr = sum((y - c - p * x) ** 2 for x, y in pts)
    print(repr(p), repr(math.sqrt(ssr / (n - 2) / sxx)))
"#;
    let mut child = match Command::new("python3")
        .args(["-c", SCRIPT])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => {
            rsts_io::report_skip(
                "convergence fits against Python",
                &format!("no python3: {e}"),
            );
            return None;
        }
    };
    use std::io::Write;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(report.to_string().as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "python3 failed");
    Some(
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| {
                let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                (v[0], v[1])
            })
            .collect(),
    )
}

/// The fit of a report equals the independent one (slope and its standard error).
fn check_against_python(report: &Value) {
    let Some(fits) = python_fits(report) else {
        return;
    };
    let ours = report["fits"].as_array().unwrap();
    assert_eq!(fits.len(), ours.len());
    for (fit, (p, se)) in ours.iter().zip(fits) {
        let order = fit["order"].as_f64().unwrap();
        let stderr = fit["order_stderr"].as_f64().unwrap();
        assert!((order - p).abs() < 1e-9, "{fit}: Python {p}");
        assert!(
            (stderr - se).abs() < 1e-9 * se.max(1e-3),
            "{fit}: Python {se}"
        );
    }
}

/// Classical RK4 4, Heun 2, Kutta's RK3 3 and RK4 with a misplaced weight (true order 2), each
/// within ±0.1, with pre-asymptotic and round-off-floor steps in the sweep (both listed as
/// excluded, with why), and the fit equal to Python's over the window.
#[test]
fn known_methods_come_out_at_their_orders() {
    let adapter = adapter_rk4();
    for (tableau, halvings, order) in [
        ("rk4", "15", 4.0),
        ("heun", "20", 2.0),
        ("kutta3", "17", 3.0),
        ("rk4-wrong-weight", "20", 2.0),
    ] {
        let command = format!("{} --tableau {tableau}", s(&adapter));
        let step = if tableau == "rk4" { "1" } else { "0.5" };
        let report = json(&["--exec", &command, "--step", step, "--halvings", halvings]);
        let fit = &report["fits"][0];
        let p = fit["order"].as_f64().unwrap();
        assert!((p - order).abs() <= 0.1, "{tableau}: {fit}");
        let expected_name = if tableau == "rk4" {
            "example-rk4".to_string()
        } else {
            format!("example-{tableau}")
        };
        assert_eq!(fit["method"], expected_name.as_str());
        let whys: Vec<&str> = fit["excluded"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["why"].as_str().unwrap())
            .collect();
        assert!(
            whys.iter().any(|w| w.starts_with("pre-asymptotic")),
            "{tableau}: {whys:?}"
        );
        assert!(
            whys.iter().any(|w| w.starts_with("round-off floor")),
            "{tableau}: {whys:?}"
        );
        let rows = report["rows"].as_array().unwrap();
        assert_eq!(rows.len(), halvings.parse::<usize>().unwrap() + 1);
        check_against_python(&report);
    }
}

/// Floors judged against round-off (issue 33): RK4 with the weight of k2 off by 4e-10 stops near
/// 1e-9, "above round-off" in the JSON and the table, and `--strict` exits 1 after writing the
/// report; the classical RK4 swept into its floor is "round-off" and passes `--strict`; RK4 with
/// an order condition off by 1e-5 has two regimes, order 4 then order 2 (the fit's order).
/// (Before: the first was "observed order 3.99", its floor "round-off floor", and no --strict.)
#[test]
fn floors_are_judged_against_round_off() {
    let adapter = adapter_rk4();
    let exec = |t: &str| format!("{} --tableau {t}", s(&adapter));
    let run = |t: &str, extra: &[&str]| {
        let mut a = vec![
            "convergence".to_string(),
            "--exec".into(),
            exec(t),
            "--step".into(),
            "0.5".into(),
            "--halvings".into(),
            "13".into(),
        ];
        a.extend(extra.iter().map(|x| x.to_string()));
        let a: Vec<&str> = a.iter().map(|x| x.as_str()).collect();
        rsts(&a)
    };
    let out = run("rk4-off-weight", &["--strict", "--format", "json"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("above round-off"), "{}", stderr(&out));
    let report: Value = serde_json::from_slice(&out.stdout).expect("the report, whole");
    let floor = &report["fits"][0]["floor"];
    assert_eq!(floor["kind"], "above round-off", "{floor}");
    assert!(floor["error"].as_f64().unwrap() > 1e3 * floor["expected_round_off"].as_f64().unwrap());
    let table = String::from_utf8(run("rk4-off-weight", &[]).stdout).unwrap();
    assert!(table.contains("above round-off"), "{table}");
    assert!(!table.contains("round-off floor"), "{table}");

    let out = run("rk4", &["--strict", "--format", "json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["fits"][0]["floor"]["kind"], "round-off", "{report}");

    let report = json(&[
        "--exec",
        &exec("rk4-near"),
        "--step",
        "0.5",
        "--halvings",
        "13",
    ]);
    let fit = &report["fits"][0];
    let regimes = fit["regimes"].as_array().unwrap();
    assert_eq!(regimes.len(), 2, "{fit}");
    let order = |r: &Value| r["order"].as_f64().unwrap();
    assert!((order(&regimes[0]) - 4.0).abs() < 0.2, "{fit}");
    assert!((order(&regimes[1]) - 2.0).abs() < 0.1, "{fit}");
    assert_eq!(fit["order"], regimes[1]["order"]);
    assert!(
        regimes[1]["window"][1].as_f64() < regimes[0]["window"][0].as_f64(),
        "{fit}"
    );
}

/// Day-one defaults (issue 33, item 6): no steps runs the default sweep 0.5 … 0.5/2⁸ (said on
/// stderr; before: "--steps or --step with --halvings: give the fixed steps to run", exit 2);
/// taylor-f64 without --order is refused with an order suggested (before: "needs a fixed order
/// (--order P)" only); the table prints the order's uncertainty with two significant digits.
#[test]
fn defaults_for_a_newcomer() {
    let out = rsts(&["convergence", "--methods", "rk4,dopri5"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("default sweep"), "{}", stderr(&out));
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(table.contains("rk4: observed order 4."), "{table}");
    let out = rsts(&["convergence", "--methods", "rk4", "--format", "json"]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let steps: Vec<f64> = report["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["step"].as_f64().unwrap())
        .collect();
    assert_eq!(steps.len(), 9);
    assert_eq!(steps[0], 0.5);
    assert_eq!(steps[8], 0.5 / 256.0);
    let err = exit_2(
        &rsts(&["convergence", "--methods", "taylor-f64"]),
        "taylor without --order",
    );
    assert!(err.contains("try --order 8"), "{err}");
    // Two significant digits of the uncertainty: "± 0.0053", never "± 0.00".
    assert!(
        !table.contains("± 0.00 ") && !table.contains("± 0.000 "),
        "{table}"
    );
}

/// An adapter that answers the same whatever the step (its own --step wins over the request's)
/// is refused with exit 2, naming it; nothing is fitted.
#[test]
fn an_adapter_that_ignores_the_step_is_refused() {
    let command = format!("{} --step 0.01", s(&adapter_rk4()));
    let out = rsts(&[
        "convergence",
        "--exec",
        &command,
        "--steps",
        "0.5,0.25,0.125",
    ]);
    let err = exit_2(&out, &command);
    assert!(
        err.contains("example-adapter-rk4") && err.contains("do not change with the step"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

/// The built-ins: every format and the SVG; rk4 of order 4 (Python agrees with the fit).
#[test]
fn built_ins_in_every_format() {
    let svg = tmp("convergence.svg");
    let report = json(&[
        "--methods",
        "rk4,taylor-f64",
        "--order",
        "5",
        "--step",
        "0.5",
        "--halvings",
        "7",
        "--svg",
        s(&svg),
    ]);
    let fits = report["fits"].as_array().unwrap();
    assert_eq!(fits[0]["method"], "rk4");
    assert!((fits[0]["order"].as_f64().unwrap() - 4.0).abs() < 0.1);
    assert_eq!(fits[1]["method"], "taylor-f64-p5");
    assert!((fits[1]["order"].as_f64().unwrap() - 5.0).abs() < 0.2);
    check_against_python(&report);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") || text.starts_with("<?xml"));
    assert!(text.contains("rk4 fit: order"));
    let csv = rsts(&[
        "convergence",
        "--steps",
        "0.5,0.25,0.125",
        "--format",
        "csv",
    ]);
    assert!(csv.status.success());
    let csv = String::from_utf8(csv.stdout).unwrap();
    assert_eq!(
        csv.lines().next().unwrap(),
        "method,step,max_error,final_error,steps,rhs_evals"
    );
    assert_eq!(csv.lines().count(), 4);
    let table = rsts(&["convergence", "--steps", "0.5,0.25,0.125"]);
    assert!(String::from_utf8(table.stdout)
        .unwrap()
        .contains("rk4: observed order"));
}

/// Bad input: too few steps, a step above the sample spacing, Taylor without an order, an order
/// for rk4 alone — each exit 2 naming the option.
#[test]
fn bad_input_names_the_option() {
    for (args, option) in [
        (vec!["--steps", "0.5,0.25"], "--steps"),
        (vec!["--steps", "2,0.5,0.25"], "--steps"),
        (
            vec!["--methods", "taylor-f64", "--steps", "0.5,0.25,0.125"],
            "--order",
        ),
        (
            vec![
                "--methods",
                "rk4",
                "--order",
                "4",
                "--steps",
                "0.5,0.25,0.125",
            ],
            "--order",
        ),
        (vec!["--step", "0.5", "--halvings", "1"], "--halvings"),
    ] {
        let mut all = vec!["convergence"];
        all.extend_from_slice(&args);
        let err = exit_2(&rsts(&all), &args);
        assert!(err.contains(option), "{args:?}: {err}");
    }
}

/// scipy's RK45 at fixed steps (its control off) against our dopri5 at fixed steps: the same
/// tableau, so the same errors step by step above the floor, and order 5 for both; heyoka at
/// tolerance 1e-3 (order 5) comes out at 5. Skipped without scipy / heyoka.
#[test]
fn scipy_and_heyoka_take_the_fixed_step() {
    if let Some(python) = python_with("scipy", "scipy_and_heyoka_take_the_fixed_step (scipy)") {
        let rk45 = adapter_command(&python, "scipy_adapter.py", "RK45");
        let report = json(&[
            "--methods",
            "dopri5",
            "--exec",
            &rk45,
            "--step",
            "0.5",
            "--halvings",
            "6",
        ]);
        let rows = report["rows"].as_array().unwrap();
        let (ours, theirs): (Vec<&Value>, Vec<&Value>) =
            rows.iter().partition(|r| r["method"] == "dopri5");
        assert_eq!(ours.len(), 7);
        for (a, b) in ours.iter().zip(&theirs) {
            let (ea, eb) = (
                a["max_error"].as_f64().unwrap(),
                b["max_error"].as_f64().unwrap(),
            );
            assert!((ea - eb).abs() <= 0.01 * ea, "{a} against {b}");
        }
        for fit in report["fits"].as_array().unwrap() {
            assert!((fit["order"].as_f64().unwrap() - 5.0).abs() < 0.1, "{fit}");
        }
        check_against_python(&report);
        let radau = adapter_command(&python, "scipy_adapter.py", "Radau");
        let err = exit_2(
            &rsts(&["convergence", "--exec", &radau, "--steps", "0.5,0.25,0.125"]),
            "Radau",
        );
        assert!(err.contains("Radau cannot take a fixed step"), "{err}");
    }
    if let Some(python) = python_with("heyoka", "scipy_and_heyoka_take_the_fixed_step (heyoka)") {
        let hy = adapter_command(&python, "heyoka_adapter.py", "f64");
        let report = json(&[
            "--exec",
            &hy,
            "--exec-tolerance",
            "1e-3",
            "--step",
            "0.125",
            "--halvings",
            "6",
        ]);
        let fit = &report["fits"][0];
        assert!((fit["order"].as_f64().unwrap() - 5.0).abs() < 0.1, "{fit}");
        let err = exit_2(
            &rsts(&["convergence", "--exec", &hy, "--steps", "1,0.5,0.25"]),
            "heyoka at step 1",
        );
        assert!(err.contains("too large for its order"), "{err}");
    }
}
