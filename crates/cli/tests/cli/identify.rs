//! `rsts identify`: the states `rsts explicit` prints map back to their motion (camera, torus,
//! m, h, the phases ψ⁰ + νt) in f64 and at 40 digits; a state off N exits 1 with
//! {"on_N": false, "distance_from_N": …}; bad input exits 2 naming the option.

use crate::common;
use common::*;

use serde_json::Value;

const CAMERAS: [(&str, &str, &str); 9] = [
    ("I+", "0.3", "-0.375"),
    ("I-", "-1.9244", "0.4503"),
    ("II+", "0.05", "1.058"),
    ("II-", "-0.5573", "1.463"),
    ("III", "-2.9877", "1.2605"),
    ("IV+", "0.05", "2.0706"),
    ("IV-", "-0.3295", "1.7668"),
    ("V", "-0.7092", "1.5643"),
    ("VI", "-2.9877", "3.2858"),
];

fn json(out: &std::process::Output) -> Value {
    serde_json::from_str(&stdout(out)).unwrap_or_else(|e| panic!("{e}: {}", stdout(out)))
}

/// (ω, α, β) of each sample of `rsts explicit … --format json` as option values.
fn explicit_states(args: &[&str]) -> (Value, Vec<[String; 3]>) {
    let doc = command_json("explicit", args);
    let states = doc["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            ["omega", "alpha", "beta"].map(|k| {
                s[k].as_array()
                    .unwrap()
                    .iter()
                    // Decimal strings above f64's digits, numbers in f64.
                    .map(|x| x.as_str().map_or_else(|| x.to_string(), str::to_string))
                    .collect::<Vec<_>>()
                    .join(",")
            })
        })
        .collect();
    (doc, states)
}

fn identify(state: &[String; 3], extra: &[&str]) -> std::process::Output {
    let omega = format!("--omega={}", state[0]);
    let alpha = format!("--alpha={}", state[1]);
    let beta = format!("--beta={}", state[2]);
    let mut args = vec![omega.as_str(), alpha.as_str(), beta.as_str()];
    args.extend_from_slice(extra);
    rsts_command("identify", &args)
}

fn gap(x: f64, y: f64) -> f64 {
    let d = (x - y).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

#[test]
fn explicit_states_map_back_to_their_motion_in_every_camera_and_torus() {
    for (camera, m, h) in CAMERAS {
        let tori = {
            let (doc, _) = explicit_states(&["--m", m, "--h", h, "--samples", "1"]);
            doc["tori"].as_u64().unwrap() as usize
        };
        for torus in 0..tori {
            let t = torus.to_string();
            let (_, states) = explicit_states(&[
                "--m",
                m,
                "--h",
                h,
                "--torus",
                &t,
                "--phase1",
                "0.7",
                "--phase2",
                "2.1",
                "--t-end",
                "0",
                "--samples",
                "1",
            ]);
            let out = identify(&states[0], &["--format", "json"]);
            assert!(
                out.status.success(),
                "{camera} torus {torus}: {}",
                stderr(&out)
            );
            let id = json(&out);
            let what = format!("{camera} torus {torus}: {id}");
            assert_eq!(id["on_N"], true, "{what}");
            assert_eq!(id["camera"], camera, "{what}");
            assert_eq!(id["torus"].as_u64(), Some(torus as u64), "{what}");
            let f = |k: &str| id[k].as_f64().unwrap();
            assert!((f("m") - m.parse::<f64>().unwrap()).abs() < 1e-12, "{what}");
            assert!((f("h") - h.parse::<f64>().unwrap()).abs() < 1e-12, "{what}");
            assert!(
                gap(f("phase1"), 0.7) < 1e-10 && gap(f("phase2"), 2.1) < 1e-10,
                "{what}"
            );
            assert!(
                f("residual") < 1e-12 && f("distance_from_N") < 1e-12,
                "{what}"
            );
            let kind = if m.starts_with('-') {
                "hyperbolic"
            } else {
                "elliptic"
            };
            assert_eq!(id["normal"]["type"], kind, "{what}");
        }
    }
}

#[test]
fn forty_digits_round_trip_and_the_table_names_everything() {
    let (_, states) = explicit_states(&[
        "--m",
        "-0.7092",
        "--h",
        "1.5643",
        "--torus",
        "2",
        "--phase1",
        "0.5",
        "--phase2",
        "1",
        "--t-end",
        "0",
        "--samples",
        "1",
        "--digits",
        "40",
    ]);
    let out = identify(
        &states[0],
        &["--digits", "40", "--tolerance", "1e-35", "--format", "json"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let id = json(&out);
    // Decimal strings at 40 digits, equal to the given values to 1e-35.
    let off = |k: &str, v: &str| -> f64 {
        let p = |s: &str| rug::Float::with_val(200, rug::Float::parse(s).unwrap());
        (p(id[k].as_str().unwrap()) - p(v)).abs().to_f64()
    };
    for (k, v) in [
        ("m", "-0.7092"),
        ("h", "1.5643"),
        ("phase1", "0.5"),
        ("phase2", "1"),
    ] {
        assert!(off(k, v) < 1e-35, "{k}: {id}");
    }
    assert!(id["residual"].as_f64().unwrap() < 1e-38, "{id}");
    assert_eq!(id["torus"], 2);
    let out = identify(&states[0], &["--digits", "40"]);
    let text = stdout(&out);
    for key in [
        "camera:",
        "torus:",
        "m:",
        "h:",
        "phase1:",
        "phase2:",
        "distance from N:",
        "residual:",
        "normal type:",
    ] {
        assert!(text.contains(key), "{key} missing in\n{text}");
    }
    // The same 40-digit state read in f64 is on N to the rounding of f64 only.
    let out = identify(&states[0], &["--tolerance", "1e-20"]);
    assert_eq!(out.status.code(), Some(1), "{}", stdout(&out));
}

#[test]
fn a_state_off_n_exits_1_with_its_distance() {
    let state = ["0.3,-0.2,0.5", "1,0,0", "0,1,0"].map(String::from);
    let out = identify(&state, &["--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let doc = json(&out);
    assert_eq!(doc["on_N"], false);
    assert!(doc["distance_from_N"].as_f64().unwrap() > 1e-3);
    assert!(
        stderr(&out).contains("not on N (distance"),
        "{}",
        stderr(&out)
    );
    // A state of N moved by 1e-6 is off N at the default tolerance, on N at 1e-3.
    let (_, states) = explicit_states(&[
        "--m",
        "0.3",
        "--h",
        "-0.375",
        "--t-end",
        "0",
        "--samples",
        "1",
    ]);
    let mut moved = states[0].clone();
    let w: Vec<f64> = moved[0].split(',').map(|x| x.parse().unwrap()).collect();
    moved[0] = format!("{},{},{}", w[0], w[1], w[2] + 1e-6);
    assert_eq!(identify(&moved, &[]).status.code(), Some(1));
    let out = identify(&moved, &["--tolerance", "1e-3", "--format", "json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let d = json(&out)["distance_from_N"].as_f64().unwrap();
    assert!(
        d > 1e-9 && d <= 1.01e-6,
        "distance {d:e} for a move of 1e-6"
    );
}

#[test]
fn bad_input_exits_2_naming_the_option() {
    let good = [
        "--omega",
        "0.3,-0.2,0.5",
        "--alpha",
        "1,0,0",
        "--beta",
        "0,1,0",
    ];
    for (extra, needle) in [
        (vec!["--omega", "1,2"], "--omega"),
        (vec!["--alpha", "1,0,0.5"], "--omega/--alpha/--beta"),
        (vec!["--beta", "1,0,0"], "--omega/--alpha/--beta"),
        (vec!["--omega", "x,0,0"], "--omega"),
        (vec!["--digits", "5"], "--digits"),
        (vec!["--tolerance", "-1"], "--tolerance"),
        (vec!["--tolerance", "nan"], "--tolerance"),
        (vec!["--a", "0.5", "--b", "1"], "--a/--b"),
        (vec!["--b", "0"], "--a/--b"),
        (vec!["--format", "csv"], "--format"),
    ] {
        let mut args: Vec<&str> = vec!["identify"];
        for pair in good.chunks(2) {
            if !extra.contains(&pair[0]) {
                args.extend_from_slice(pair);
            }
        }
        args.extend_from_slice(&extra);
        let err = fails(&args);
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(!err.contains("panicked"), "{extra:?}: {err}");
    }
}
