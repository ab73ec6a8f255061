//! `rsts explicit` as a user runs it: JSON shape, digits carried, agreement of f64 and
//! high-precision output, and clear errors on bad input.

use std::process::Output;

use serde_json::Value;

use crate::common;
use common::{command_json, exit_2, rsts_command};

fn explicit(args: &[&str]) -> Output {
    rsts_command("explicit", args)
}

fn json(args: &[&str]) -> Value {
    command_json("explicit", args)
}

fn error(args: &[&str]) -> String {
    let out = explicit(args);
    let err = exit_2(&out, args);
    assert!(out.stdout.is_empty());
    err
}

/// A number of the document: a JSON number in f64, a decimal string at --digits (docs/output.md).
fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| {
        v.as_str()
            .expect("a number or a decimal string")
            .parse()
            .unwrap()
    })
}

#[test]
fn json_has_the_documented_shape_and_digits() {
    let doc = json(&[
        "--m",
        "-0.7092",
        "--h",
        "1.5643",
        "--torus",
        "2",
        "--t-end",
        "3",
        "--samples",
        "4",
        "--digits",
        "60",
    ]);
    for key in ["a", "b", "m", "h", "camera", "tori", "digits", "samples"] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["camera"], "V");
    assert_eq!(doc["tori"], 4);
    assert_eq!(doc["digits"], 60);
    let samples = doc["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 4);
    assert_eq!(num(&samples[3]["t"]), 3.0);
    let w = samples[2]["omega"][0].as_str().unwrap();
    let mantissa: String = w
        .split('e')
        .next()
        .unwrap()
        .chars()
        .filter(char::is_ascii_digit)
        .collect();
    assert_eq!(mantissa.len(), 60, "{w}");
    for key in ["omega", "alpha", "beta", "gamma", "Omega"] {
        assert_eq!(samples[1][key].as_array().unwrap().len(), 3, "{key}");
    }
}

#[test]
fn one_sample_is_t_zero_and_f64_agrees_with_40_digits() {
    let doc = json(&["--samples", "1", "--t-end", "5"]);
    let s = doc["samples"].as_array().unwrap();
    assert_eq!(s.len(), 1);
    assert_eq!(num(&s[0]["t"]), 0.0);
    let motion = [
        "--m",
        "0.3",
        "--h",
        "-0.375",
        "--phase1",
        "1",
        "--t-end",
        "50",
        "--samples",
        "3",
    ];
    let lo = json(&motion);
    let hi = json(&[&motion[..], &["--digits", "40"]].concat());
    for k in 0..3 {
        for key in ["omega", "alpha", "beta", "gamma", "Omega"] {
            for i in 0..3 {
                let (x, y) = (
                    num(&lo["samples"][k][key][i]),
                    num(&hi["samples"][k][key][i]),
                );
                // f64 inputs 0.3, −0.375 differ from the exact decimals by ~1e-17 relative.
                assert!(
                    (x - y).abs() < 1e-13,
                    "{key}[{i}] at sample {k}: {x} vs {y}"
                );
            }
        }
    }
    // |α| = 1 in the 40-digit output, to 38 digits.
    let a: Vec<f64> = (0..3).map(|i| num(&hi["samples"][2]["alpha"][i])).collect();
    assert!((a.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-15);
}

#[test]
fn bad_input_is_named() {
    assert!(error(&["--digits", "5"]).contains("--digits"));
    assert!(error(&["--m", "nan"]).contains("--m"));
    assert!(error(&["--h", "abc"]).contains("--h: 'abc' is not a number"));
    assert!(error(&["--t-end", "-1"]).contains("--t-end"));
    assert!(error(&["--samples", "0"]).contains("--samples"));
    assert!(error(&["--m", "0", "--h", "-3"]).contains("outside the admissible region"));
    assert!(error(&["--m", "0", "--h", "2"]).contains("h = r²m + 2a"));
    assert!(error(&["--torus", "1"]).contains("torus 1 does not exist"));
    assert!(error(&["--b", "0"]).contains("a > b > 0"));
}
