//! `rsts validate` as CI and a scheduler run it: the quick suite passes, a too-strict threshold
//! and a regression against a baseline exit 1 naming the run, three shards merge into the
//! unsharded report, and bad input exits 2 with a message.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;
use common::{fails, ok, rsts, s, stderr, stdout, tmp};

fn write(name: &str, text: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn read_report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// The report without its timing objects, its time and a merge's parts (the documented identity
/// of reports).
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
    let top = v.as_object_mut().unwrap();
    top.remove("created");
    top.remove("parts");
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
    let history = tmp("merged.sqlite");
    let mut args = vec!["validate", "merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--report", s(&merged), "--history", s(&history)]);
    let out = rsts(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    // The merge is one night of the whole suite in the history.
    let doc: Value = serde_json::from_slice(
        &rsts(&["history", "regressions", s(&history), "--format", "json"]).stdout,
    )
    .unwrap();
    assert_eq!(doc["nights"], 1, "{doc:#}");
    assert_eq!(read_report(&merged)["parts"].as_array().unwrap().len(), 3);
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

/// SplitMix64 for the synthetic nights' timing noise (fixed seed).
struct Rng(u64);
impl Rng {
    /// Uniform in [1 − a, 1 + a].
    fn noise(&mut self, a: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
        1.0 + a * (2.0 * u - 1.0)
    }
}

/// Night k (1-based) of the synthetic histories: one a day from 2026-03-01 02:00 UTC.
fn night_time(k: usize) -> String {
    format!("2026-03-{k:02}T02:00:00Z")
}

/// Twelve nights made from one real report of the small suite: every time scaled by ±30 %
/// noise, dopri5 twice as slow from night 6 on, and I+'s dop853 error one ulp larger from night
/// 8 on. Returns the report directories.
fn synthetic_nights(base: &Value, root: &Path) -> Vec<PathBuf> {
    let mut rng = Rng(34);
    (1..=12)
        .map(|k| {
            let mut r = base.clone();
            r["created"] = Value::from(night_time(k));
            r["commit"] = Value::from(format!("commit{k:02}"));
            for run in r["runs"].as_array_mut().unwrap() {
                let slow = if run["method"] == "dopri5" && k >= 6 {
                    2.0
                } else {
                    1.0
                };
                let noise = rng.noise(0.3);
                for key in ["integration_seconds", "wall_seconds"] {
                    let t = run["timing"][key].as_f64().unwrap();
                    run["timing"][key] = Value::from(t * slow * noise);
                }
                if run["id"] == "I+/t0/dop853@1e-12" && k >= 8 {
                    let e = run["figures"]["max_state_error"].as_f64().unwrap();
                    run["figures"]["max_state_error"] =
                        Value::from(f64::from_bits(e.to_bits() + 1));
                }
            }
            let d = root.join(format!("night-{k:02}"));
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(
                d.join("report.json"),
                serde_json::to_string_pretty(&r).unwrap(),
            )
            .unwrap();
            std::fs::write(d.join("report.md"), format!("# night {k}\n")).unwrap();
            d
        })
        .collect()
}

/// A history of synthetic nights (one real report of the small suite, with ±30 % timing noise,
/// a planted 2× slowdown of dopri5 from night 6 and a one-ulp larger error of one run from night
/// 8): `rsts history regressions` finds exactly those two, dated; the dashboard shows them on
/// the overview and the trend page, and its pages open in headless Chromium without a console
/// error (screenshots in target/tmp/dashboard-check).
#[test]
fn a_history_finds_a_planted_slowdown_and_a_changed_bit_and_its_dashboard_renders_in_chromium() {
    let suite = write("history-small.toml", SMALL);
    let real = tmp("history-real");
    let out = rsts(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&real),
        "--jobs",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let base = read_report(&real);
    for key in ["created", "commit", "rsts_version", "environment"] {
        assert!(!base[key].is_null(), "report.json lacks {key}");
    }
    let root = tmp("history-nights");
    let _ = std::fs::remove_dir_all(&root);
    let nights = synthetic_nights(&base, &root);
    let db = root.join("history.sqlite");
    let mut args = vec!["history", "import"];
    args.extend(nights.iter().map(|d| s(d)));
    args.extend(["--history", s(&db)]);
    let out = rsts(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    // Imported twice: refused, nothing written.
    let again = rsts(&["history", "import", s(&nights[0]), "--history", s(&db)]);
    assert_eq!(again.status.code(), Some(2));
    assert!(
        stderr(&again).contains("already holds this report"),
        "{}",
        stderr(&again)
    );
    let out = rsts(&["history", "regressions", s(&db), "--format", "json"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["nights"], 12);
    let regs = doc["regressions"].as_array().unwrap();
    let found: Vec<(String, String, String, String)> = regs
        .iter()
        .map(|r| {
            let f = |k: &str| r[k].as_str().unwrap().to_string();
            (f("kind"), f("run_id"), f("metric"), f("first_bad_night"))
        })
        .collect();
    let want = |kind: &str, id: &str, metric: &str, k: usize| {
        (
            kind.to_string(),
            id.to_string(),
            metric.to_string(),
            night_time(k),
        )
    };
    assert_eq!(
        found,
        vec![
            want("accuracy", "I+/t0/dop853@1e-12", "max_state_error", 8),
            want("timing", "I+/t0/dopri5@1e-12", "seconds", 6),
        ],
        "{doc:#}"
    );
    assert_eq!(regs[0]["ulps"], 1);
    assert_eq!(regs[0]["last_good_commit"], "commit07");
    assert_eq!(regs[1]["last_good_night"], night_time(5));
    let ratio = regs[1]["after"].as_f64().unwrap() / regs[1]["before"].as_f64().unwrap();
    assert!(ratio > 1.4 && ratio < 2.9, "{ratio}");
    // The text form says the same, one line each.
    let text = stdout(&rsts(&["history", "regressions", s(&db)]));
    assert_eq!(text.matches("REGRESSION ").count(), 2, "{text}");

    let site = root.join("site");
    let out = rsts(&["dashboard", "--history", s(&db), "--out", s(&site)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    let cell = r#"<td class="cell regressed" data-case="I+" data-method="dopri5"><a href=""#;
    let at = index
        .find(cell)
        .unwrap_or_else(|| panic!("no regressed dopri5 cell: {index}"));
    let href = &index[at + cell.len()..];
    let trend = site.join(&href[..href.find('"').unwrap()]);
    let trend_html = std::fs::read_to_string(&trend).unwrap();
    assert!(trend_html.contains(r#"data-label="regression""#));
    // An unchanged cell is steady.
    assert!(
        index.contains(
            r#"<td class="cell steady" data-case="near-outer-b" data-method="closed-form">"#
        ),
        "{index}"
    );
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dashboard-check");
    let _ = std::fs::remove_dir_all(&shots);
    let check = std::process::Command::new("bash")
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scripts/check_dashboard.sh"
        ))
        .args(["--out", s(&shots)])
        .args(["--page", "overview", s(&site.join("index.html"))])
        .args([
            "--expect",
            r#"td.cell.regressed[data-case="I+"][data-method="dopri5"]"#,
        ])
        .args(["--expect", "tr.regression"])
        .args(["--page", "trend", s(&trend)])
        .args([
            "--expect",
            r#"figure.plot.time g.series[data-label="regression"] circle"#,
        ])
        .args(["--expect", "p.regression"])
        .args(["--page", "night", s(&site.join("night/6.html"))])
        .args(["--expect", r#"ul.files a[href$="report.md"]"#])
        .output()
        .expect("run bash");
    match check.status.code() {
        Some(2) => {
            return rsts_io::report_skip(
                "a_history_finds_a_planted_slowdown_and_a_changed_bit_and_its_dashboard_renders_in_chromium",
                &format!("no headless Chromium: {}", stderr(&check).trim()),
            )
        }
        code => assert_eq!(code, Some(0), "{}{}", stdout(&check), stderr(&check)),
    }
    let report: Value = serde_json::from_slice(&check.stdout).unwrap();
    for page in report["results"].as_array().unwrap() {
        assert_eq!(page["ok"], true, "{page:#}");
        assert!(shots
            .join(format!("{}.png", page["name"].as_str().unwrap()))
            .exists());
    }
    assert!(
        report["results"][1]["plots"].as_u64().unwrap() >= 3,
        "{report:#}"
    );
}

/// Missing, foreign, newer and locked histories: exit 2 with a message, the file unchanged and
/// nothing else written (no report directory from a refused `validate --history`).
#[test]
fn bad_histories_exit_2_and_nothing_is_written() {
    let suite = write("bad-history.toml", SMALL);
    let d = tmp("bad-history");
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let missing = d.join("missing.sqlite");
    let err = fails(&["history", "regressions", s(&missing)]);
    assert!(err.contains("does not exist"), "{err}");
    let err = fails(&[
        "dashboard",
        "--history",
        s(&missing),
        "--out",
        s(&d.join("site")),
    ]);
    assert!(err.contains("does not exist"), "{err}");
    assert!(!missing.exists() && !d.join("site").exists());
    // Not a database: validate refuses before running anything.
    let notes = d.join("notes.txt");
    std::fs::write(&notes, "my notes, not a history\n".repeat(40)).unwrap();
    let report = d.join("report");
    let err = fails(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&report),
        "--history",
        s(&notes),
    ]);
    assert!(err.contains("is not an rsts history"), "{err}");
    assert!(!report.exists(), "a report was written");
    assert_eq!(
        std::fs::read_to_string(&notes).unwrap(),
        "my notes, not a history\n".repeat(40)
    );
    // A history of a newer schema (user_version, bytes 60..64 of the header, raised).
    let db = d.join("h.sqlite");
    ok(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&report),
        "--history",
        s(&db),
    ]);
    let mut bytes = std::fs::read(&db).unwrap();
    let v = u32::from_be_bytes(bytes[60..64].try_into().unwrap());
    bytes[60..64].copy_from_slice(&(v + 1).to_be_bytes());
    let future = d.join("future.sqlite");
    std::fs::write(&future, &bytes).unwrap();
    for args in [
        vec!["history", "regressions", s(&future)],
        vec!["history", "import", s(&report), "--history", s(&future)],
        vec![
            "dashboard",
            "--history",
            s(&future),
            "--out",
            s(&d.join("site")),
        ],
    ] {
        let err = fails(&args);
        assert!(err.contains("a history of a newer rsts"), "{args:?}: {err}");
    }
    assert_eq!(std::fs::read(&future).unwrap(), bytes);
    // Locked by another writer (Python's sqlite3 holds the write lock).
    let Some(python) = ["python3", "python"].into_iter().find(|p| {
        std::process::Command::new(p)
            .args(["-c", "import sqlite3"])
            .output()
            .is_ok_and(|o| o.status.success())
    }) else {
        return rsts_io::report_skip(
            "bad_histories_exit_2_and_nothing_is_written",
            "no python3 with sqlite3 to hold a lock (the rest passed)",
        );
    };
    let mut holder = std::process::Command::new(python)
        .args(["-c", "import sqlite3, sys, time\nc = sqlite3.connect(sys.argv[1], isolation_level=None)\nc.execute('BEGIN IMMEDIATE')\nprint('locked', flush=True)\ntime.sleep(60)", s(&db)])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(
        &mut std::io::BufReader::new(holder.stdout.take().unwrap()),
        &mut line,
    )
    .unwrap();
    assert_eq!(line.trim(), "locked");
    let second = d.join("report-2");
    let err = fails(&[
        "validate",
        "--suite",
        s(&suite),
        "--report",
        s(&second),
        "--history",
        s(&db),
    ]);
    holder.kill().unwrap();
    holder.wait().unwrap();
    assert!(err.contains("is locked by another writer"), "{err}");
    assert!(!second.exists());
    let doc: Value = serde_json::from_slice(
        &rsts(&["history", "regressions", s(&db), "--format", "json"]).stdout,
    )
    .unwrap();
    assert_eq!(doc["nights"], 1);
}

/// `rsts validate --history` killed (SIGKILL) in the middle of its night's insert: the history
/// opens and holds the nights before, and takes the next one.
#[test]
fn a_writer_killed_mid_insert_leaves_the_nights_before() {
    use std::io::BufRead;
    let suite = write("killed.toml", SMALL);
    let d = tmp("killed");
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let db = d.join("h.sqlite");
    for k in 1..=2 {
        ok(&[
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&d.join(format!("r{k}"))),
            "--history",
            s(&db),
        ]);
    }
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args([
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&d.join("r3")),
            "--history",
            s(&db),
        ])
        .env("RSTS_HISTORY_PAUSE_MID_INSERT", "60")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    let mut paused = false;
    for line in lines {
        if line.unwrap().contains("history: paused mid-insert") {
            paused = true;
            break;
        }
    }
    assert!(paused, "the writer never reached the middle of its insert");
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let doc: Value = serde_json::from_slice(
        &rsts(&["history", "regressions", s(&db), "--format", "json"]).stdout,
    )
    .unwrap();
    assert_eq!(doc["nights"], 2, "{doc:#}");
    ok(&["history", "import", s(&d.join("r3")), "--history", s(&db)]);
    let doc: Value = serde_json::from_slice(
        &rsts(&["history", "regressions", s(&db), "--format", "json"]).stdout,
    )
    .unwrap();
    assert_eq!(doc["nights"], 3);
}
