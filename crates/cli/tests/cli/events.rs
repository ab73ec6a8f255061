//! `rsts events` as a user runs it: every format, digits as decimal strings, and exit 2 naming
//! the option on bad input.

use serde_json::Value;

use crate::common;
use common::{adapter_rk4, command_json, exit_2, json_doc, python_with, rsts_command};

fn events_json(args: &[&str]) -> Value {
    command_json("events", args)
}

#[test]
fn json_csv_and_table_list_the_same_events_in_time_order() {
    let args = ["--event", "omega3:up", "--event", "s1", "--t-end", "15"];
    let doc = events_json(&args);
    assert_eq!(doc["case"]["camera"], "I+");
    let events = doc["events"].as_array().unwrap();
    assert!(events.len() >= 4, "{doc}");
    let times: Vec<f64> = events.iter().map(|e| e["t"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    for e in events {
        let dir = e["direction"].as_str().unwrap();
        match e["name"].as_str().unwrap() {
            // omega3 is a state component: it vanishes at its events, upward as asked.
            "omega3" => {
                assert_eq!(dir, "up");
                assert!(e["state"]["omega"][2].as_f64().unwrap().abs() < 1e-14);
            }
            "s1" => assert!(dir == "up" || dir == "down"),
            other => panic!("unexpected event {other}"),
        }
        assert_eq!(e["state"]["alpha"].as_array().unwrap().len(), 3);
    }
    let csv = rsts_command("events", &[&args[..], &["--format", "csv"]].concat());
    let text = String::from_utf8(csv.stdout).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("t,omega1,omega2,omega3,alpha1"));
    let csv_times: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(csv_times, times);
    let table = rsts_command("events", &args);
    let table = String::from_utf8(table.stdout).unwrap();
    assert!(
        table.contains(&format!("events found:   {}", times.len())),
        "{table}"
    );
}

#[test]
fn digits_give_decimal_strings_that_agree_with_f64() {
    let args = [
        "--m", "-0.7092", "--h", "1.5643", "--torus", "3", "--event", "gamma3",
    ];
    let f64_doc = events_json(&args);
    let mp_doc = events_json(&[&args[..], &["--digits", "40"]].concat());
    let (a, b) = (
        f64_doc["events"].as_array().unwrap(),
        mp_doc["events"].as_array().unwrap(),
    );
    assert_eq!(a.len(), b.len());
    assert!(!a.is_empty());
    for (x, y) in a.iter().zip(b) {
        let s = y["t"].as_str().expect("a decimal string at --digits");
        assert!(
            s.trim_start_matches('-').replace('.', "").len() >= 40,
            "{s}"
        );
        let t: f64 = s.parse().unwrap();
        // f64 output is the 40-digit time correctly rounded.
        assert_eq!(x["t"].as_f64().unwrap(), t);
    }
}

#[test]
fn bad_input_exits_2_naming_the_option() {
    for (args, needle) in [
        (vec!["--event", "omega4"], "--event 'omega4': unknown event"),
        (vec!["--event", "omega1:sideways"], "unknown direction"),
        (vec!["--event", "s1", "--event", "s1:up"], "asked for twice"),
        (
            vec!["--event", "s1", "--t-start", "5", "--t-end", "5"],
            "--t-end",
        ),
        (vec!["--event", "s1", "--t-end", "-1"], "is empty"),
        (vec!["--event", "s1", "--digits", "3"], "--digits"),
        (vec!["--event", "s1", "--m", "0.3", "--h", "-5"], "--m/--h"),
        (vec!["--event", "s1", "--t-end", "1e9"], "--t-end"),
        (vec![], "--event"),
    ] {
        let out = rsts_command("events", &args);
        let err = exit_2(&out, &args);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(out.stdout.is_empty());
    }
}

/// Done-when of docs/events.md: heyoka in MPFR at 40 digits, locating the events with its own
/// nt_event machinery through scripts/adapters/heyoka_adapter.py, finds the same events as
/// `rsts_closed_form::events` and the same times to 40 digits, on three cameras (V: m < 0).
#[test]
fn heyoka_mpfr_event_times_agree_to_40_digits() {
    use rsts_closed_form::events::{exact_events, working_bits, EventSpec};
    use rsts_closed_form::{ExplicitMotion, TorusChoice};
    use rsts_dynamics::Real;
    use rug::Float;
    let Some(python) = python_with("heyoka", "heyoka_mpfr_event_times_agree_to_40_digits") else {
        return;
    };
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scripts/adapters/heyoka_adapter.py");
    let names = ["omega1", "omega3", "alpha2", "beta1", "gamma3"];
    let specs: Vec<EventSpec> = names.iter().map(|n| n.parse().unwrap()).collect();
    let bits = working_bits(Some(40));
    let t_end = 10.0;
    for (m, h, torus, camera) in [
        (0.3, -0.375, 0, "I+"),
        (-0.7092, 1.5643, 3, "V"),
        (0.05, 1.058, 0, "II+"),
    ] {
        let f = |x: f64| Float::with_val(bits, x);
        let choice = TorusChoice {
            torus,
            phase1: 0.3,
            phase2: 0.7,
        };
        let motion = ExplicitMotion::new(f(1.0), f(0.5), f(m), f(h), choice).unwrap();
        assert_eq!(motion.camera.label(), camera);
        let exact = exact_events(&motion, &specs, &f(0.0), &f(t_end)).unwrap();
        let s0 = motion.at(&f(0.0));
        let dec = |v: &[Float; 3]| v.iter().map(|x| x.to_decimal(60)).collect::<Vec<_>>();
        let request = serde_json::json!({
            "protocol": "rsts-integrator/1", "a": "1", "b": "0.5", "digits": 40,
            "rtol": 1e-40, "atol": 1e-40, "times": [0.0, t_end],
            "initial": {"omega": dec(&s0.omega), "alpha": dec(&s0.alpha), "beta": dec(&s0.beta)},
            "events": names.iter().map(|n| serde_json::json!({"name": n, "direction": "both"})).collect::<Vec<_>>(),
        });
        let mut child = std::process::Command::new(&python)
            .arg(&script)
            .arg("mpfr")
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(request.to_string().as_bytes())
            .unwrap();
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success());
        let answer: Value = serde_json::from_slice(&out.stdout).unwrap();
        let found = answer["events"].as_array().unwrap();
        assert_eq!(found.len(), exact.len(), "{camera}: {found:?}");
        assert!(exact.len() >= 5, "{camera}: only {} events", exact.len());
        let mut worst = 0f64;
        for (e, d) in exact.iter().zip(found) {
            assert_eq!(d["name"], e.name.as_str(), "{camera}");
            let t = Float::with_val(bits, Float::parse(d["t"].as_str().unwrap()).unwrap());
            worst = worst.max(Float::with_val(bits, &t - &e.t).abs().to_f64());
        }
        eprintln!(
            "{camera}: {} events, largest |t_heyoka - t_exact| = {worst:e}",
            exact.len()
        );
        assert!(worst < 1e-38, "{camera}: {worst:e}");
    }
}

/// `check --events`: a trajectory with the exact events less one is reported with exactly one
/// missed event and the others' time errors; bad events files exit 2 naming the line.
#[test]
fn check_events_reports_one_missed_event_and_names_bad_lines() {
    let dir = common::tmp("events-check");
    let traj = dir.with_file_name("events-traj.csv");
    let reference = rsts_command(
        "reference",
        &[
            "--m",
            "-0.7092",
            "--h",
            "1.5643",
            "--torus",
            "2",
            "--t-end",
            "12",
            "--samples",
            "241",
            "--format",
            "csv",
        ],
    );
    assert!(reference.status.success());
    std::fs::write(&traj, &reference.stdout).unwrap();
    let exact = events_json(&[
        "--m", "-0.7092", "--h", "1.5643", "--torus", "2", "--event", "gamma2", "--event",
        "alpha1", "--t-end", "12",
    ]);
    let all = exact["events"].as_array().unwrap();
    assert!(all.len() >= 4, "{exact}");
    let mut csv = String::from("name,t\n");
    for (i, e) in all.iter().enumerate() {
        if i != 2 {
            // Detected a little late: 1e-7.
            let t = e["t"].as_f64().unwrap() + 1e-7;
            csv.push_str(&format!("{},{t:?}\n", e["name"].as_str().unwrap()));
        }
    }
    let events = dir.with_file_name("events-detected.csv");
    std::fs::write(&events, &csv).unwrap();
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    let motion = ["--m", "-0.7092", "--h", "1.5643", "--torus", "2"];
    let run = |extra: &[&str]| {
        let mut args = vec![p(&traj)];
        args.extend(motion.iter().map(|s| s.to_string()));
        args.extend(extra.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        rsts_command("check", &refs)
    };
    let out = run(&[
        "--events",
        &p(&events),
        "--event",
        "alpha1",
        "--format",
        "json",
    ]);
    let doc = json_doc(&out);
    let ev = &doc["events"];
    assert_eq!(ev["exact"].as_u64().unwrap() as usize, all.len(), "{ev}");
    assert_eq!(ev["missed"], 1);
    assert_eq!(ev["spurious"], 0);
    assert_eq!(ev["matched"].as_u64().unwrap() as usize, all.len() - 1);
    let worst = ev["max_time_error"].as_f64().unwrap();
    assert!((worst - 1e-7).abs() < 1e-12, "{worst:e}");
    let missed: Vec<&Value> = ev["per_event"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["t_detected"].is_null())
        .collect();
    assert_eq!(missed.len(), 1);
    assert_eq!(missed[0]["t_exact"], all[2]["t"]);
    // The same events in reverse order (as a file grouped by event may list them): read and
    // sorted, the same report (before issue 33: refused, "list events in time order").
    let mut lines: Vec<&str> = csv.lines().skip(1).collect();
    lines.reverse();
    let reversed = dir.with_file_name("events-reversed.csv");
    std::fs::write(&reversed, format!("name,t\n{}\n", lines.join("\n"))).unwrap();
    let out = run(&[
        "--events",
        &p(&reversed),
        "--event",
        "alpha1",
        "--format",
        "json",
    ]);
    assert_eq!(&json_doc(&out)["events"], ev);
    // CI: a missed event fails (exit 1).
    let out = run(&["--events", &p(&events), "--max-event-error", "1e-3"]);
    assert_eq!(out.status.code(), Some(1));
    // Bad files: exit 2 naming the line.
    for (text, needle) in [
        (
            "name,t\nomega1,0.5\nomega7,0.6\n",
            "line 3: unknown event 'omega7'",
        ),
        // Events out of time order are read and sorted (issue 33); a time that is not finite
        // is refused.
        (
            "name,t\nomega1,0.5\nomega1,inf\n",
            "line 3: the time is not a finite number",
        ),
    ] {
        let bad = dir.with_file_name("events-bad.txt");
        std::fs::write(&bad, text).unwrap();
        let out = run(&["--events", &p(&bad)]);
        let err = exit_2(&out, text);
        assert!(err.contains(needle), "{err}");
        assert!(out.stdout.is_empty());
    }
}

fn compare_events(args: &[&str]) -> Value {
    let mut all = vec![
        "--t-end",
        "20",
        "--samples",
        "201",
        "--event",
        "omega1",
        "--event",
        "gamma2",
    ];
    all.extend_from_slice(args);
    command_json("compare", &all)["events"].clone()
}

/// compare --event: a built-in method (events located in its samples by Hermite interpolation)
/// finds every event; the example RK4 adapter answers events through the protocol, and with
/// `--drop-event 3` exactly one is missed while the others keep their time errors.
#[test]
fn compare_event_for_built_ins_and_an_adapter_that_drops_one() {
    let built_in = compare_events(&["--method", "dop853", "--rtol", "1e-10", "--atol", "1e-10"]);
    let exact = built_in["exact"].as_u64().unwrap();
    assert!(exact >= 6, "{built_in}");
    assert_eq!(built_in["missed"], 0, "{built_in}");
    assert_eq!(built_in["spurious"], 0);
    // Hermite interpolation between samples 0.1 apart: errors of order h^4.
    assert!(
        built_in["max_time_error"].as_f64().unwrap() < 1e-4,
        "{built_in}"
    );
    let rk4 = adapter_rk4();
    let exec = format!("{}", rk4.display());
    let full = compare_events(&["--exec", &exec, "--rtol", "1e-10", "--atol", "1e-10"]);
    assert_eq!(full["exact"].as_u64().unwrap(), exact);
    assert_eq!(full["missed"], 0, "{full}");
    let worst = full["max_time_error"].as_f64().unwrap();
    assert!(worst < 1e-8, "{full}");
    let dropped = format!("{} --drop-event 3", rk4.display());
    let one_less = compare_events(&["--exec", &dropped, "--rtol", "1e-10", "--atol", "1e-10"]);
    assert_eq!(one_less["missed"], 1, "{one_less}");
    assert_eq!(one_less["spurious"], 0);
    assert_eq!(one_less["matched"].as_u64().unwrap(), exact - 1);
    // The missed one is the fourth exact event; the others keep their errors.
    let per: Vec<&Value> = one_less["per_event"].as_array().unwrap().iter().collect();
    let missed: Vec<&&Value> = per.iter().filter(|p| p["t_detected"].is_null()).collect();
    assert_eq!(missed.len(), 1);
    let full_per = full["per_event"].as_array().unwrap();
    assert_eq!(missed[0]["t_exact"], full_per[3]["t_exact"]);
    // CI: --max-event-error fails on the missed event (exit 1), passes the full answer.
    let base = [
        "--t-end",
        "20",
        "--samples",
        "201",
        "--event",
        "omega1",
        "--event",
        "gamma2",
    ];
    let tol = [
        "--rtol",
        "1e-10",
        "--atol",
        "1e-10",
        "--max-event-error",
        "1e-6",
    ];
    let run =
        |cmd: &str| rsts_command("compare", &[&base[..], &tol[..], &["--exec", cmd]].concat());
    assert_eq!(run(&exec).status.code(), Some(0));
    assert_eq!(run(&dropped).status.code(), Some(1));
    // The built-ins cannot locate s1, s2: refused naming the option.
    let out = rsts_command("compare", &["--event", "s1"]);
    assert!(exit_2(&out, "s1").contains("--event: s1"));
}

/// bench --event: every row carries the events' counts (built-in: located in an extra run's
/// samples; adapter: answered); a row with a dropped event fails --max-event-error (exit 1).
#[test]
fn bench_event_columns_and_max_event_error() {
    let rk4 = adapter_rk4();
    let dropped = format!("{} --drop-event 0", rk4.display());
    let base = [
        "--methods",
        "dop853",
        "--tolerances",
        "1e-8",
        "--t-end",
        "20",
        "--samples",
        "201",
        "--repeats",
        "1",
        "--event",
        "omega1",
    ];
    let out = rsts_command(
        "bench",
        &[&base[..], &["--exec", &dropped, "--format", "json"]].concat(),
    );
    let doc = json_doc(&out);
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    let (ours, theirs) = (&rows[0]["events"], &rows[1]["events"]);
    assert_eq!(ours["exact"], theirs["exact"]);
    assert!(ours["exact"].as_u64().unwrap() >= 5, "{ours}");
    assert_eq!(ours["missed"], 0, "{ours}");
    assert_eq!(theirs["missed"], 1, "{theirs}");
    assert!(theirs["max_time_error"].as_f64().unwrap() < 1e-6);
    let table = rsts_command("bench", &[&base[..], &["--exec", &dropped]].concat());
    assert!(String::from_utf8_lossy(&table.stdout).contains("max event error"));
    let out = rsts_command(
        "bench",
        &[
            &base[..],
            &["--exec", &dropped, "--max-event-error", "1e-3"],
        ]
        .concat(),
    );
    assert_eq!(out.status.code(), Some(1));
}

/// compare --event --mcap: `/events` (foxglove.Log) and `/events/markers` carry one message per
/// exact event, the dropped one marked as not detected.
#[test]
fn compare_log_has_the_events_channels() {
    let path = common::tmp("events.mcap");
    let dropped = format!("{} --drop-event 3", adapter_rk4().display());
    let out = rsts_command(
        "compare",
        &[
            "--exec",
            &dropped,
            "--rtol",
            "1e-8",
            "--atol",
            "1e-8",
            "--t-end",
            "20",
            "--samples",
            "201",
            "--event",
            "omega1",
            "--event",
            "gamma2",
            "--mcap",
            path.to_str().unwrap(),
            "--format",
            "json",
        ],
    );
    let report = json_doc(&out);
    let exact = report["events"]["exact"].as_u64().unwrap() as usize;
    let read =
        |channel: &str| command_json("inspect", &[path.to_str().unwrap(), "--channel", channel]);
    let markers = read("/events/markers");
    let rows = markers["messages"]
        .as_array()
        .or_else(|| markers.as_array())
        .expect("messages");
    assert_eq!(rows.len(), exact, "{markers}");
    let text = markers.to_string();
    assert_eq!(text.matches("\"detected\":0.0").count(), 1, "{text}");
    let logs = read("/events").to_string();
    assert_eq!(logs.matches("MISSED").count(), 1, "{logs}");
}
