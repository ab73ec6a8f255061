//! `rsts events` as a user runs it: every format, digits as decimal strings, and exit 2 naming
//! the option on bad input.

use serde_json::Value;

mod common;
use common::{exit_2, rsts_command};

fn events_json(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.extend_from_slice(&["--format", "json"]);
    let out = rsts_command("events", &all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON document")
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
    assert!(lines.next().unwrap().starts_with("name,t,direction,omega1"));
    let csv_times: Vec<f64> = lines
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
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

/// The Python of scripts/install_adapters.sh when it has heyoka; `None` (skip reported) else.
fn heyoka_python(test: &str) -> Option<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let python = std::env::var("RSTS_ADAPTERS_PYTHON")
        .unwrap_or_else(|_| root.join(".venv-adapters/bin/python").display().to_string());
    let ok = std::process::Command::new(&python)
        .args(["-c", "import heyoka"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        rsts_io::report_skip(
            test,
            "heyoka is not installed (scripts/install_adapters.sh heyoka; needs pip and PyPI)",
        );
    }
    ok.then_some(python)
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
    let Some(python) = heyoka_python("heyoka_mpfr_event_times_agree_to_40_digits") else {
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
