//! Convergence cases in validation suites: `convergence = { steps, order }` runs built-in
//! methods at fixed steps and `min_order` holds their observed order.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;
use common::{exit_2, rsts, s, stderr, tmp};

const SUITE: &str = r#"
name = "orders"
[[case]]
name = "order-rk4"
m = 0.3
h = -0.375
t_end = 10.0
samples = 11
closed_form = false
methods = ["rk4"]
convergence = { steps = [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625] }
[case.thresholds]
min_order = 3.9

[[case]]
name = "order-taylor"
m = 0.3
h = -0.375
t_end = 10.0
samples = 11
closed_form = false
methods = ["taylor-f64"]
convergence = { steps = [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625], order = 6 }
[case.thresholds]
min_order = 5.8
"#;

fn write(name: &str, text: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// The orders are held (rk4 4, taylor-f64 at order 6 six) and reported with their window;
/// a min_order above the true order fails naming the run and the order.
#[test]
fn min_order_holds_the_observed_order() {
    let dir = tmp("orders");
    let out = rsts(&[
        "validate",
        "--suite",
        s(&write("orders.toml", SUITE)),
        "--report",
        s(&dir),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let r = report(&dir);
    let runs = r["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    let order = |id: &str| {
        let run = runs.iter().find(|x| x["id"] == id).unwrap();
        assert_eq!(run["status"], "pass", "{run}");
        run["convergence"]["order"].as_f64().unwrap()
    };
    assert!((order("order-rk4/t0/rk4/order") - 4.0).abs() < 0.1);
    assert!((order("order-taylor/t0/taylor-f64-p6/order") - 6.0).abs() < 0.2);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("observed order 4.0"), "{md}");

    let strict = write(
        "strict-orders.toml",
        &SUITE.replace("min_order = 3.9", "min_order = 4.5"),
    );
    let dir = tmp("strict-orders");
    let out = rsts(&["validate", "--suite", s(&strict), "--report", s(&dir)]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("FAIL order-rk4/t0/rk4/order: observed order"),
        "{err}"
    );
    assert!(err.contains("< min_order 4.5"), "{err}");
}

/// Bad convergence cases are suite errors: min_order without convergence, a Taylor method
/// without an order, too few steps, an unknown field.
#[test]
fn bad_convergence_cases_are_refused() {
    for (bad, why) in [
        (
            SUITE.replace(
                "convergence = { steps = [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625] }",
                "",
            ),
            "min_order holds convergence cases only",
        ),
        (SUITE.replace(", order = 6 }", " }"), "--order"),
        (
            SUITE.replace(
                "[0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625]",
                "[0.5, 0.25]",
            ),
            "at least 3 distinct steps",
        ),
        (
            SUITE.replace(", order = 6 }", ", order = 6, tol = 1 }"),
            "unknown field",
        ),
    ] {
        let out = rsts(&[
            "validate",
            "--suite",
            s(&write("bad-orders.toml", &bad)),
            "--list",
        ]);
        let err = exit_2(&out, why);
        assert!(err.contains(why), "{why}: {err}");
    }
}
