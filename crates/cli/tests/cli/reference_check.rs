//! `rsts check` reads what `rsts reference` writes: the (N, 13) npy and the CSV give the same
//! report, and the f64 reference, correctly rounded, is off the motion by at most half an ulp.

use crate::common;
use common::{rsts, s, tmp};
use serde_json::Value;

fn ok(args: &[&str]) -> Vec<u8> {
    let out = rsts(args);
    assert!(out.status.success(), "{args:?}: {}", common::stderr(&out));
    out.stdout
}

#[test]
fn check_reads_the_npy_and_csv_of_reference() {
    let motion = ["--m", "-0.7092", "--h", "1.5643", "--torus", "2"];
    let (npy, csv) = (tmp("ref.npy"), tmp("ref.csv"));
    for (path, format) in [(&npy, "npy"), (&csv, "csv")] {
        let mut args = vec!["reference", "--t-end", "50", "--samples", "2001"];
        args.extend(motion);
        args.extend(["--format", format, "-o", s(path)]);
        ok(&args);
    }
    let report = |path: &std::path::Path| -> Value {
        let mut args = vec!["check", s(path), "--format", "json"];
        args.extend(motion);
        serde_json::from_slice(&ok(&args)).unwrap()
    };
    let (a, b) = (report(&npy), report(&csv));
    for key in ["max_state_error", "drift", "samples_compared", "camera"] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert_eq!(a["samples_compared"], 2001);
    // Every value is the exact one rounded: |error| ≤ ulp/2 ≤ 2⁻⁵³ for values below 1 in size
    // (and |ω| < 2 here: ≤ 2⁻⁵²).
    let e = a["max_state_error"].as_f64().unwrap();
    assert!(e > 0.0 && e <= f64::EPSILON, "{e:e}");

    // The same files on standard input (`rsts check -`) give the same report.
    for (path, format) in [(&npy, "npy"), (&csv, "csv")] {
        let mut args = vec!["check", "-", "--input-format", format, "--format", "json"];
        args.extend(motion);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rsts"))
            .args(&args)
            .stdin(std::fs::File::open(path).unwrap())
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", common::stderr(&out));
        let c: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(c["file"], "<stdin>");
        assert_eq!(c["method"], "<stdin>");
        for key in [
            "max_state_error",
            "drift",
            "samples_compared",
            "phase_error",
        ] {
            assert_eq!(a[key], c[key], "{format} on stdin: {key}");
        }
    }
    let e = common::fails(&["check", "-"]);
    assert!(e.contains("--input-format"), "{e}");
    let e = common::fails(&["check", s(&npy), "--input-format", "npy"]);
    assert!(e.contains("--input-format: only for standard input"), "{e}");
}
