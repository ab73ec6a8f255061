//! External integrators (`--exec`, protocol rsts-integrator/1) in compare and bench: the compiled
//! example adapter (crates/example-adapter-rk4) measured like a built-in method, and every way a
//! child can misbehave (exit status, timeout, garbage, short answer) reported with its stderr.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common;
use common::{adapter_command, adapter_rk4, exit_2, python_with, rsts, stderr, tmp};

/// A shell script standing in for a misbehaving integrator.
fn script(name: &str, body: &str) -> String {
    let path = tmp(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    path.to_str().unwrap().to_string()
}

fn json(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.extend_from_slice(&["--format", "json"]);
    let out = rsts(&all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice(&out.stdout).expect("one JSON document on stdout")
}

const CASE: [&str; 8] = [
    "--t-end",
    "20",
    "--samples",
    "201",
    "--rtol",
    "1e-10",
    "--atol",
    "1e-10",
];

/// The adapter is RK4 with the step rule of the built-in rk4 (rtol^(1/4), at most 0.01, a whole
/// number of steps per interval): the same steps, and errors that agree to 1e-3 relative, while
/// everything came through a process and JSON.
#[test]
fn compare_runs_the_compiled_adapter_like_the_built_in_rk4() {
    let adapter = adapter_rk4();
    let mut args = vec!["compare", "--exec", adapter.to_str().unwrap()];
    args.extend_from_slice(&CASE);
    let ext = json(&args);
    let mut args = vec!["compare", "--method", "rk4"];
    args.extend_from_slice(&CASE);
    let ours = json(&args);
    assert_eq!(ext["method"], "example-rk4", "named by its answer");
    assert_eq!(ext["samples_compared"], 201);
    assert_eq!(ext["steps"], ours["steps"]);
    let (e, o) = (
        ext["max_state_error"].as_f64().unwrap(),
        ours["max_state_error"].as_f64().unwrap(),
    );
    assert!(e > 1e-13 && e < 1e-8, "adapter error {e:e}");
    assert!(
        (e - o).abs() < 1e-3 * o,
        "adapter {e:e}, built-in rk4 {o:e}"
    );
    let wall = ext["wall_seconds"]
        .as_f64()
        .expect("wall time of the process");
    let own = ext["integration_seconds"].as_f64().unwrap();
    assert!(own > 0.0 && wall >= own, "own {own}, wall {wall}");
    assert_eq!(ext["digits"], 36, "the request's digits");
    assert!(ours.get("wall_seconds").is_none());
}

/// bench --exec: the adapter's rows sit in the table and the SVG beside the built-in ones,
/// labelled by its name, dashed, with the process wall time in JSON.
#[test]
fn bench_rows_of_the_compiled_adapter() {
    let adapter = adapter_rk4();
    let svg = tmp("wp-exec.svg");
    let doc = json(&[
        "bench",
        "--methods",
        "dop853",
        "--exec",
        adapter.to_str().unwrap(),
        "--tolerances",
        "1e-4,1e-12",
        "--t-end",
        "10",
        "--samples",
        "21",
        "--repeats",
        "2",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    let rows = doc["rows"].as_array().unwrap();
    let ext: Vec<&Value> = rows
        .iter()
        .filter(|r| r["method"] == "example-rk4")
        .collect();
    assert_eq!(rows.len(), 4);
    assert_eq!(ext.len(), 2);
    let err = |r: &Value| r["max_error"].as_f64().unwrap();
    assert!(err(ext[1]) < 1e-3 * err(ext[0]), "{ext:?}");
    assert!(ext
        .iter()
        .all(|r| r["wall_seconds"].as_f64().unwrap() > 0.0));
    assert!(ext[1]["steps"].as_u64().unwrap() > ext[0]["steps"].as_u64().unwrap());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains(">example-rk4<"), "legend names the adapter");
    assert!(text.contains(">dop853<"));
    assert!(
        text.contains("stroke-dasharray"),
        "external rows are dashed"
    );
}

fn exec_fails(command: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "compare",
        "--exec",
        command,
        "--t-end",
        "1",
        "--samples",
        "21",
    ];
    args.extend_from_slice(extra);
    let err = exit_2(&rsts(&args), &args);
    assert!(!err.contains("panicked"), "{err}");
    err
}

#[test]
fn a_failing_child_is_named_with_the_end_of_its_stderr() {
    let s = script(
        "fails.sh",
        "cat > /dev/null\necho 'loading my integrator' >&2\necho 'ValueError: step too small' >&2\nexit 3",
    );
    let err = exec_fails(&s, &[]);
    assert!(err.contains(&format!("external integrator `{s}`")), "{err}");
    assert!(err.contains("exited with status 3"), "{err}");
    assert!(err.contains("| ValueError: step too small"), "{err}");
}

/// stdout that is not one JSON document is named as such with the offending text: a stray
/// line before the JSON (old: "line 1: the header lacks column(s) t, omega1, …", read as CSV)
/// and a NaN inside it (old: "invalid JSON: … at line 1 column 47").
#[test]
fn a_stray_line_and_a_nan_are_named() {
    let s = script(
        "stray.sh",
        "cat > /dev/null\necho 'step 1 of 100'\necho '{\"samples\": []}'",
    );
    let err = exec_fails(&s, &[]);
    assert!(
        err.contains("not one JSON document") && err.contains("\"step 1 of 100\""),
        "{err}"
    );
    let s = script(
        "nan.sh",
        "cat > /dev/null\necho '{\"samples\": [{\"t\": 0, \"omega\": [NaN, 0, 0]}]}'",
    );
    let err = exec_fails(&s, &[]);
    assert!(
        err.contains("NaN at line 1") && err.contains("sample 0") && err.contains("\"omega\""),
        "{err}"
    );
}

#[test]
fn garbage_and_short_answers_are_errors() {
    let s = script("garbage.sh", "echo 'hello, I am not JSON'");
    let err = exec_fails(&s, &[]);
    assert!(err.contains("not an rsts-integrator/1 answer"), "{err}");
    assert!(err.contains("hello, I am not JSON"), "{err}");
    assert!(err.contains("its stderr is empty"), "{err}");

    let s = script(
        "short.sh",
        r#"cat > /dev/null
echo '{"samples": [{"t": 0, "omega": [0.1, 0.2, 0.3], "alpha": [1, 0, 0], "beta": [0, 1, 0]}]}'"#,
    );
    let err = exec_fails(&s, &[]);
    assert!(
        err.contains("answered 1 samples for 21 requested times"),
        "{err}"
    );

    let s = script("empty.sh", "cat > /dev/null");
    let err = exec_fails(&s, &[]);
    assert!(err.contains("wrote no answer"), "{err}");

    let err = exec_fails("/nonexistent/integrator --fast", &[]);
    assert!(
        err.contains("cannot start `/nonexistent/integrator`"),
        "{err}"
    );
    let err = exec_fails("python3 'unbalanced", &[]);
    assert!(err.contains("--exec: cannot split"), "{err}");
}

/// A child that hangs is killed at the timeout with everything it started (its process
/// group), and the run ends soon after.
#[test]
fn a_hanging_child_is_killed_at_the_timeout_with_its_children() {
    let pidfile = tmp("hang.pid");
    let s = script(
        "hang.sh",
        &format!(
            "echo 'thinking...' >&2\nsleep 60 &\necho $! > {}\nwait",
            pidfile.display()
        ),
    );
    let started = Instant::now();
    let err = exec_fails(&s, &["--exec-timeout", "1"]);
    let took = started.elapsed();
    assert!(err.contains("no answer within 1 s"), "{err}");
    assert!(err.contains("| thinking..."), "{err}");
    assert!(took < Duration::from_secs(30), "took {took:?}");
    let pid = std::fs::read_to_string(&pidfile).unwrap();
    let proc = PathBuf::from(format!("/proc/{}", pid.trim()));
    // The grandchild `sleep 60` was killed with the group (give the kernel a moment).
    let deadline = Instant::now() + Duration::from_secs(5);
    while proc.exists() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(!proc.exists(), "sleep {} survived", pid.trim());
    let err = exec_fails(&s, &["--exec-timeout", "0"]);
    assert!(err.contains("--exec-timeout"), "{err}");
}

/// scipy's solve_ivp through compare --exec and bench --exec: DOP853 at 1e-10 is accurate,
/// RK45 at 1e-3 is at least 100x worse; the rows carry scipy's names.
#[test]
fn scipy_adapter_dop853_is_accurate_and_rk45_loose_is_not() {
    let Some(python) = python_with(
        "scipy",
        "scipy_adapter_dop853_is_accurate_and_rk45_loose_is_not",
    ) else {
        return;
    };
    let dop = adapter_command(&python, "scipy_adapter.py", "DOP853");
    let tight = json(&[
        "compare",
        "--exec",
        &dop,
        "--rtol",
        "1e-10",
        "--atol",
        "1e-10",
        "--t-end",
        "20",
        "--samples",
        "101",
    ]);
    assert_eq!(tight["method"], "scipy-DOP853");
    let e_tight = tight["max_state_error"].as_f64().unwrap();
    assert!(e_tight < 1e-6, "DOP853 at 1e-10: {e_tight:e}");
    let rk45 = adapter_command(&python, "scipy_adapter.py", "RK45");
    let doc = json(&[
        "bench",
        "--exec",
        &rk45,
        "--tolerances",
        "1e-3,1e-6",
        "--t-end",
        "20",
        "--samples",
        "101",
        "--repeats",
        "1",
    ]);
    let rows = doc["rows"].as_array().unwrap();
    assert!(rows.iter().all(|r| r["method"] == "scipy-RK45"), "{rows:?}");
    let e_loose = rows[0]["max_error"].as_f64().unwrap();
    assert!(
        e_loose >= 100.0 * e_tight,
        "RK45 at 1e-3: {e_loose:e}, DOP853 at 1e-10: {e_tight:e}"
    );
    assert!(rows[1]["max_error"].as_f64().unwrap() < e_loose);
}

/// heyoka through its adapter: same Taylor orders and steps as taylor-f64 and taylor-mp, so
/// the same steps and errors that agree where truncation dominates.
#[test]
fn heyoka_adapter_matches_our_taylor_methods() {
    let Some(python) = python_with("heyoka", "heyoka_adapter_matches_our_taylor_methods") else {
        return;
    };
    let f64_cmd = adapter_command(&python, "heyoka_adapter.py", "f64");
    let mp_cmd = adapter_command(&python, "heyoka_adapter.py", "mpfr");
    let quick = ["--t-end", "10", "--samples", "21", "--repeats", "1"];
    let run = |extra: &[&str]| {
        let mut args = vec!["bench"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&quick);
        json(&args)["rows"].as_array().unwrap().clone()
    };
    let f64_rows = run(&[
        "--methods",
        "taylor-f64",
        "--exec",
        &f64_cmd,
        "--tolerances",
        "1e-10",
    ]);
    let mp_rows = run(&[
        "--methods",
        "taylor-mp",
        "--exec",
        &mp_cmd,
        "--digits",
        "40",
        "--tolerances",
        "1e-30",
    ]);
    for (rows, theirs) in [(&f64_rows, "heyoka-f64"), (&mp_rows, "heyoka-mpfr-40d")] {
        assert_eq!(rows.len(), 2, "{rows:?}");
        let (a, b) = (&rows[0], &rows[1]);
        assert_eq!(b["method"], theirs);
        assert_eq!(a["steps"], b["steps"], "{rows:?}");
        let (ea, eb) = (
            a["max_error"].as_f64().unwrap(),
            b["max_error"].as_f64().unwrap(),
        );
        assert!(
            (ea / eb - 1.0).abs() < 0.1,
            "{} {ea:e}, {theirs} {eb:e}",
            a["method"]
        );
    }
    assert!(mp_rows[1]["max_error"].as_f64().unwrap() < 1e-30);
}

/// A suite names an adapter and uses it like a built-in method; `validate --exec` runs a
/// program through every case; a failing program is a run error naming it.
#[test]
fn suites_run_adapters_like_methods() {
    let adapter = adapter_rk4();
    let suite = tmp("adapters.toml");
    std::fs::write(
        &suite,
        format!(
            r#"name = "mine"
[defaults]
t_end = 5.0
samples = 21
closed_form = false
[adapters.my-rk4]
command = ["{}"]
timeout = 60
[[case]]
name = "I"
m = 0.3
h = -0.375
methods = ["dop853", "my-rk4"]
tolerances = [1e-10]
[case.thresholds]
max_state_error = 1e-6
"#,
            adapter.display()
        ),
    )
    .unwrap();
    let dir = tmp("suite-report");
    let out = rsts(&[
        "validate",
        "--suite",
        suite.to_str().unwrap(),
        "--report",
        dir.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    let runs = report["runs"].as_array().expect("runs");
    let mine = runs
        .iter()
        .find(|r| r["id"] == "I/t0/my-rk4@1e-10")
        .unwrap_or_else(|| panic!("{runs:?}"));
    assert_eq!(mine["status"], "pass");
    assert_eq!(mine["method"], "my-rk4");
    let e = mine["figures"]["max_state_error"].as_f64().unwrap();
    assert!(e > 0.0 && e < 1e-6, "{e:e}");

    // The whole suite through one program given on the command line; it fails: exit 1.
    let bad = script(
        "bad-adapter.sh",
        "cat > /dev/null\necho 'segfault in my code' >&2\nexit 139",
    );
    let dir = tmp("suite-exec");
    let out = rsts(&[
        "validate",
        "--suite",
        suite.to_str().unwrap(),
        "--report",
        dir.to_str().unwrap(),
        "--exec",
        &bad,
        "--exec-name",
        "mine",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("I/t0/mine@1e-10"), "{err}");
    let report = std::fs::read_to_string(dir.join("report.json")).unwrap();
    assert!(
        report.contains("segfault in my code"),
        "the run's error keeps the stderr"
    );

    // An adapter named like a built-in method, or without a program, is a suite error.
    for (text, expect) in [
        ("[adapters.dop853]\ncommand = [\"x\"]\n", "built-in"),
        ("[adapters.x]\ncommand = []\n", "command"),
    ] {
        let bad_suite = tmp("bad-adapters.toml");
        std::fs::write(
            &bad_suite,
            format!("{text}[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\n"),
        )
        .unwrap();
        let err = exit_2(
            &rsts(&["validate", "--suite", bad_suite.to_str().unwrap(), "--list"]),
            text,
        );
        assert!(err.contains(expect), "{text}: {err}");
    }
}

/// The example adapter with `"steps"` cut from its answer's stats, as a script `name`.
fn without_steps(name: &str) -> String {
    script(
        name,
        &format!(
            "'{}' | sed -E 's/\"steps\":[0-9]+,?//; s/,}}/}}/'",
            adapter_rk4().display()
        ),
    )
}

/// An adapter whose answer states no `stats.steps` (here the example adapter with the key cut
/// from its answer) is reported with its steps not known — null in JSON, an empty CSV cell,
/// n/a in the table — not as 0 steps; the evaluations it does state are kept.
#[test]
fn steps_an_adapter_does_not_state_are_not_known() {
    let adapter = adapter_rk4();
    let quiet = without_steps("no-steps.sh");
    let mut args = vec!["compare", "--exec", &quiet];
    args.extend_from_slice(&CASE);
    let doc = json(&args);
    assert!(doc["steps"].is_null(), "{}", doc["steps"]);
    assert!(doc["rejected_steps"].is_null(), "{}", doc["rejected_steps"]);
    // The full answer: the same run with its steps (RK4: 4 evaluations a step).
    let full = json(&[&["compare", "--exec", adapter.to_str().unwrap()][..], &CASE].concat());
    let steps = full["steps"].as_u64().expect("the full answer's steps");
    assert!(steps >= 2000, "{steps}");
    assert_eq!(doc["rhs_evals"], 4 * steps, "stated evaluations are kept");
    let csv = rsts(&[&args[..], &["--format", "csv"]].concat());
    let text = String::from_utf8(csv.stdout).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "steps")
        .expect("a steps column");
    assert_eq!(row[col], "", "{text}");
    let table = String::from_utf8(rsts(&args).stdout).unwrap();
    let line = table
        .lines()
        .find(|l| l.starts_with("steps (rejected)"))
        .expect("a steps line");
    assert!(line.contains("n/a (n/a)"), "{line}");
}

/// `rsts bench` does the same: a row of an adapter that states no steps has them null in JSON,
/// an empty CSV cell, n/a in the table; the evaluations it states are kept; a diagram against
/// steps leaves the row out and says so on stderr (main before this change printed 0 steps).
#[test]
fn bench_rows_of_an_adapter_stating_no_steps_say_not_known() {
    let adapter = adapter_rk4();
    let quiet = without_steps("bench-no-steps.sh");
    let svg = tmp("bench-no-steps.svg");
    let svg = svg.to_str().unwrap();
    let run = [
        "--tolerances",
        "1e-6",
        "--t-end",
        "5",
        "--samples",
        "11",
        "--repeats",
        "1",
    ];
    let args = [&["bench", "--exec", &quiet][..], &run].concat();
    let doc = json(&args);
    let row = &doc["rows"][0];
    assert!(row["steps"].is_null(), "{row}");
    let full = json(&[&["bench", "--exec", adapter.to_str().unwrap()][..], &run].concat());
    let steps = full["rows"][0]["steps"]
        .as_u64()
        .expect("the full answer's steps");
    assert_eq!(steps, 500, "step 0.01 over T = 5");
    assert_eq!(row["rhs_evals"], 4 * steps, "stated evaluations are kept");
    let text = String::from_utf8(rsts(&[&args[..], &["--format", "csv"]].concat()).stdout).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cells: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    assert_eq!(cells[col("steps")], "", "{text}");
    assert_eq!(cells[col("rhs_evals")], (4 * steps).to_string(), "{text}");
    let with_rk4 = ["--methods", "rk4", "--svg", svg, "--cost", "steps"];
    let out = rsts(&[&args[..], &with_rk4].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let drawn = std::fs::read_to_string(svg).unwrap();
    assert!(
        drawn.contains("rk4") && !drawn.contains("example-rk4"),
        "{drawn}"
    );
    let table = String::from_utf8(out.stdout.clone()).unwrap();
    let line = table
        .lines()
        .find(|l| l.trim_start().starts_with("example-rk4"))
        .expect("a row");
    let last: Vec<&str> = line.split_whitespace().rev().take(2).collect();
    assert_eq!(
        last,
        [(4 * steps).to_string().as_str(), "n/a"],
        "steps n/a, evaluations stated: {line}"
    );
    let err = stderr(&out);
    assert!(
        err.contains("example-rk4 left out of the diagram: its steps are not known"),
        "{err}"
    );
}
