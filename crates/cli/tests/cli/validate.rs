//! `rsts validate` as CI and a scheduler run it: the quick suite passes, a too-strict threshold
//! and a regression against a baseline exit 1 naming the run, three shards merge into the
//! unsharded report, and bad input exits 2 with a message.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;
use common::{rsts, s, stderr, tmp};

fn write(name: &str, text: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn read_report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// The report without its timing objects (the documented identity of reports).
fn without_timing(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                m.remove("timing");
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

/// A small suite: two cameras (one with two tori and two tolerances) and a point near Σ.
const SMALL: &str = r#"
name = "small"
[defaults]
t_end = 20.0
samples = 81
[defaults.thresholds]
max_state_error = 1e-3
max_drift = 1e-6
[[case]]
name = "I+"
camera = "I+"
m = 0.3
h = -0.375
methods = ["dop853", "dopri5"]
[[case]]
name = "II-"
camera = "II-"
m = -0.5573
h = 1.463
tori = "all"
tolerances = [1e-8, 1e-10]
[[case]]
name = "near-outer-b"
m = 0.2
place = { near = "outer-b", delta = 1e-6 }
"#;

#[test]
fn the_quick_suite_passes_with_a_report_table_and_plots() {
    let suite = concat!(env!("CARGO_MANIFEST_DIR"), "/../../validation/quick.toml");
    let dir = tmp("quick");
    let out = rsts(&["validate", "--suite", suite, "--report", s(&dir)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let r = read_report(&dir);
    let runs = r["runs"].as_array().unwrap();
    assert!(runs.len() > 100, "{}", runs.len());
    let cameras: std::collections::BTreeSet<&str> =
        runs.iter().map(|x| x["camera"].as_str().unwrap()).collect();
    for c in ["I+", "I-", "II+", "II-", "III", "IV+", "IV-", "V", "VI"] {
        assert!(
            cameras.contains(c),
            "camera {c} missing from the quick suite"
        );
    }
    assert!(runs.iter().all(|x| x["status"] == "pass"));
    // The tori of a point are mirror images (docs/closed-form.md): every run on torus k reports
    // what the same run on torus 0 does, to the last bit (why nightly.toml keeps torus 0 only).
    let mut copies = 0;
    for run in runs.iter().filter(|x| x["torus"] != 0) {
        let id = run["id"].as_str().unwrap();
        let first_id = format!(
            "{}/t0/{}",
            run["case"].as_str().unwrap(),
            id.rsplit('/').next().unwrap()
        );
        let first = runs
            .iter()
            .find(|x| x["id"] == first_id.as_str())
            .expect(&first_id);
        for key in [
            "figures",
            "closed_form",
            "normal",
            "phase_error",
            "error_split",
            "growth",
            "series",
        ] {
            assert_eq!(run[key], first[key], "{id} {key} against {first_id}");
        }
        copies += 1;
    }
    assert!(copies > 50, "{copies} runs on tori other than 0");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("| run | case | camera | method | max error | drift |"));
    assert_eq!(md.matches("| pass |").count(), runs.len());
    let plots = dir.join("plots");
    for f in ["diagram-a1-b0.5.svg", "work-precision-sweep-Ip.svg"] {
        let svg = std::fs::read_to_string(plots.join(f)).unwrap_or_else(|_| panic!("{f}"));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
    let diagram = std::fs::read_to_string(plots.join("diagram-a1-b0.5.svg")).unwrap();
    assert!(diagram.matches("class=\"case-point\"").count() >= 9);
    assert!(plots.join("error-camera-V-t3.svg").exists());
}

#[test]
fn a_too_strict_threshold_fails_naming_the_run_and_the_figure() {
    let suite = write(
        "strict.toml",
        &SMALL.replace("max_state_error = 1e-3", "max_state_error = 1e-16"),
    );
    let dir = tmp("strict");
    let out = rsts(&["validate", "--suite", s(&suite), "--report", s(&dir)]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("FAIL I+/t0/dop853@1e-12: max_state_error"),
        "{err}"
    );
    // The closed-form checks are not held to the integrators' threshold and still pass.
    let r = read_report(&dir);
    let cf = r["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["id"] == "I+/t0/closed-form")
        .unwrap();
    assert_eq!(cf["status"], "pass");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("**FAIL**: max_state_error"));
}

#[test]
fn a_baseline_with_errors_a_million_times_smaller_is_a_regression() {
    let suite = write("base.toml", SMALL);
    let dir = tmp("base");
    let out = rsts(&["validate", "--suite", s(&suite), "--report", s(&dir)]);
    assert!(out.status.success(), "{}", stderr(&out));
    // Timings zeroed (below the 5 ms floor, so no time is compared: the test does not depend on
    // the machine's load).
    let mut base = read_report(&dir);
    for run in base["runs"].as_array_mut().unwrap() {
        run["timing"]["integration_seconds"] = Value::from(0.0);
        run["timing"]["wall_seconds"] = Value::from(0.0);
    }
    // Against itself: no regression.
    let same = write("same-report.json", &serde_json::to_string(&base).unwrap());
    let again = tmp("again");
    let out = rsts(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&again),
        "--baseline",
        s(&same),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let r = read_report(&again);
    assert_eq!(r["baseline"]["runs_compared"], r["summary"]["runs"]);
    // A baseline a million times better in every error of one run.
    for run in base["runs"].as_array_mut().unwrap() {
        if run["id"] == "II-/t1/dop853@1e-8" {
            let f = &mut run["figures"];
            for k in ["max_state_error", "drift_H", "off_N"] {
                f[k] = Value::from(f[k].as_f64().unwrap() * 1e-6);
            }
        }
    }
    let old = write("old-report.json", &serde_json::to_string(&base).unwrap());
    let now = tmp("now");
    let out = rsts(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&now),
        "--baseline",
        s(&old),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("REGRESSION II-/t1/dop853@1e-8: max_state_error"),
        "{err}"
    );
    assert!(
        err.contains("REGRESSION II-/t1/dop853@1e-8: off_N"),
        "{err}"
    );
    assert!(!err.contains("REGRESSION I+"), "{err}");
    let r = read_report(&now);
    let regs = r["baseline"]["regressions"].as_array().unwrap();
    assert!(regs
        .iter()
        .all(|x| x["id"] == "II-/t1/dop853@1e-8" && x["kind"] == "error"));
}

#[test]
fn three_shards_merged_equal_the_unsharded_report() {
    let suite = write("shards.toml", SMALL);
    let full = tmp("full");
    let out = rsts(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&full),
        "--jobs",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut dirs = Vec::new();
    let mut sizes = Vec::new();
    for k in 1..=3 {
        let d = tmp(&format!("shard-{k}"));
        let spec = format!("{k}/3");
        let out = rsts(&[
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&d),
            "--shard",
            &spec,
            "--jobs",
            "1",
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let r = read_report(&d);
        assert_eq!(r["shard"]["k"], k);
        sizes.push(r["runs"].as_array().unwrap().len());
        dirs.push(d);
    }
    let merged = tmp("merged");
    let mut args = vec!["validate", "merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--report", s(&merged)]);
    let out = rsts(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let full_r = read_report(&full);
    let total = full_r["runs"].as_array().unwrap().len();
    assert_eq!(sizes.iter().sum::<usize>(), total);
    assert!(sizes.iter().all(|&n| n > 0 && n < total), "{sizes:?}");
    assert_eq!(without_timing(read_report(&merged)), without_timing(full_r));
    assert!(merged.join("report.md").exists());
    // A missing shard is an error, not a smaller report.
    let out = rsts(&[
        "validate",
        "merge",
        s(&dirs[0]),
        s(&dirs[2]),
        "--report",
        s(&tmp("partial")),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("missing shard(s) 2/3"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let dir = tmp("bad");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "--suite".into(),
                s(&write("bad.toml", "[[case]\nname=")).into(),
            ],
            "suite:",
        ),
        (
            vec![
                "--suite".into(),
                s(&write(
                    "method.toml",
                    "[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\nmethods = [\"euler\"]\n",
                ))
                .into(),
            ],
            "unknown method 'euler'",
        ),
        (
            vec![
                "--suite".into(),
                s(&write(
                    "sigma.toml",
                    "[[case]]\nname = \"c\"\nm = 0.0\nh = 2.0\n",
                ))
                .into(),
            ],
            "h = r²m + 2a",
        ),
        (
            vec![
                "--suite".into(),
                s(&write("ok.toml", SMALL)).into(),
                "--shard".into(),
                "4/3".into(),
            ],
            "need 1 <= K <= N",
        ),
        (
            vec![
                "--suite".into(),
                s(&write("ok2.toml", SMALL)).into(),
                "--baseline".into(),
                "/nonexistent/report.json".into(),
            ],
            "cannot read /nonexistent/report.json",
        ),
        (
            vec!["--suite".into(), "/nonexistent/suite.toml".into()],
            "cannot read suite",
        ),
    ];
    for (extra, expected) in cases {
        let mut args: Vec<String> = vec!["validate".into(), "--report".into(), s(&dir).into()];
        args.extend(extra);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = rsts(&refs);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}
