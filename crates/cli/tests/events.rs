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
