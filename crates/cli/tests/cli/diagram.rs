//! `rsts diagram` as a user runs it: the SVG file, a point description, and clear errors.

use std::process::Output;

use crate::common;
use common::{exit_2, rsts_command, tmp};

fn rsts(args: &[&str]) -> Output {
    rsts_command("diagram", args)
}

#[test]
fn svg_is_written_with_every_camera() {
    let path = tmp("sub/diagram.svg");
    let out = rsts(&["--a", "1", "--b", "0.5", "--svg", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"));
    for label in ["I+", "I-", "II+", "II-", "III", "IV+", "IV-", ">V<", "VI"] {
        assert!(svg.contains(label), "missing {label}");
    }
}

#[test]
fn a_point_is_described_in_json_and_table() {
    let out = rsts(&["--m", "-0.7092", "--h", "1.5643", "--format", "json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["camera"], "V");
    assert_eq!(v["tori"], 4);
    assert_eq!(v["normal"]["type"], "hyperbolic");
    assert!(v["normal"]["lambda2"].as_f64().unwrap() > 0.0);
    let table = String::from_utf8(rsts(&["--m", "0.3", "--h", "-0.375"]).stdout).unwrap();
    assert!(
        table.contains("camera I+") && table.contains("[a, θ2]"),
        "{table}"
    );
    assert!(table.contains("N is normally elliptic"), "{table}");
}

#[test]
fn bad_requests_are_explained() {
    let err = |args: &[&str]| exit_2(&rsts(args), args);
    assert!(err(&[]).contains("--svg FILE"));
    assert!(err(&["--m", "0", "--h", "2"]).contains("h = r²m + 2a"));
    assert!(err(&["--m", "0", "--h", "-5"]).contains("admissible"));
    assert!(err(&["--b", "2", "--m", "0", "--h", "0"]).contains("a > b > 0"));
    assert!(err(&["--svg", "/tmp/x.svg", "--m-range", "1,0"]).contains("LO < HI"));
    assert!(err(&["--svg", "/proc/nope/x.svg"]).contains("--svg"));
}
