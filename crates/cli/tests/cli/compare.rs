//! `rsts compare` and `rsts inspect` as a user runs them: the report, the MCAP file read back by
//! `inspect`, a damaged file, and Ctrl-C leaving a readable file.

use std::process::{Command, Stdio};
use std::time::Duration;

use serde_json::Value;

use crate::common;
use common::{exit_2, rsts, rsts_command, tmp};

fn report(extra: &[&str]) -> Value {
    let mut args = vec![
        "compare",
        "--t-end",
        "20",
        "--samples",
        "41",
        "--format",
        "json",
    ];
    args.extend_from_slice(extra);
    let out = rsts(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON report")
}

#[test]
fn json_report_has_the_documented_fields_and_separates_tight_from_loose() {
    let tight = report(&["--method", "dop853", "--rtol", "1e-12", "--atol", "1e-12"]);
    for key in [
        "method",
        "rtol",
        "atol",
        "max_state_error",
        "final_state_error",
        "max_orientation_error",
        "scd",
        "mescd",
        "scd_min",
        "mescd_min",
        "drift",
        "steps",
        "rhs_evals",
        "integration_seconds",
    ] {
        assert!(tight.get(key).is_some(), "missing {key}");
    }
    for key in ["H", "K", "G", "constraints", "off_N"] {
        assert!(tight["drift"].get(key).is_some(), "missing drift.{key}");
    }
    let loose = report(&["--method", "dopri5", "--rtol", "1e-4", "--atol", "1e-4"]);
    let (t, l) = (
        tight["max_state_error"].as_f64().unwrap(),
        loose["max_state_error"].as_f64().unwrap(),
    );
    assert!(t < 1e-8 && l > 100.0 * t, "tight {t:e}, loose {l:e}");
    // The geometry of the error (docs/stability.md).
    assert_eq!(tight["normal"]["type"], "elliptic");
    for key in ["max", "final"] {
        assert!(tight["normal"]["distance_from_N"][key].is_f64(), "{tight}");
        assert!(tight["phase_error"]["psi1"][key].is_f64(), "{tight}");
        assert!(tight["phase_error"]["psi2"][key].is_f64(), "{tight}");
    }
    assert!(tight["normal"]["growth"]["kind"].is_string(), "{tight}");
    assert!(tight["normal"]["growth"]["rate"].is_f64(), "{tight}");
}

/// The showcase comparison (camera V, error ~4): the table says the error is the departure from
/// N, growing like e^{λt} with λ ≈ 0.24 (docs/stability.md); in camera I+ it is the drift along
/// the torus.
#[test]
fn the_report_says_what_dominates_the_error() {
    let run = |extra: &[&str], format: &str| {
        let mut args = vec![
            "compare", "--method", "dopri5", "--rtol", "1e-8", "--atol", "1e-8",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--format", format]);
        let out = rsts(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let v = ["--m", "-0.7092", "--h", "1.5643", "--torus", "2"];
    let json: Value = serde_json::from_str(&run(&v, "json")).unwrap();
    let normal = &json["normal"];
    assert_eq!(normal["type"], "hyperbolic");
    assert_eq!(normal["growth"]["kind"], "exponential", "{normal}");
    let rate = normal["growth"]["rate"].as_f64().unwrap();
    assert!(rate > 0.18 && rate < 0.3, "{normal}");
    assert!(
        normal["distance_from_N"]["max"].as_f64().unwrap() > 1e-3,
        "{normal}"
    );
    assert_eq!(json["error_split"]["dominant"], "departure from N");
    let table = run(&v, "table");
    let line = table
        .lines()
        .find(|l| l.starts_with("the error is:"))
        .unwrap();
    assert!(
        line.contains("departure from N") && line.contains("normally hyperbolic"),
        "{table}"
    );
    assert!(table.contains("drift of on-N relations:"), "{table}");
    let table = run(&["--m", "0.3", "--h", "-0.375"], "table");
    let line = table
        .lines()
        .find(|l| l.starts_with("the error is:"))
        .unwrap();
    assert!(line.contains("drift along the torus"), "{table}");
    assert!(table.contains("N normally elliptic here"), "{table}");
}

#[test]
fn mcap_log_reads_back_with_inspect() {
    let path = tmp("ok.mcap");
    let p = path.to_str().unwrap();
    let out = rsts(&["compare", "--t-end", "5", "--samples", "51", "--mcap", p]);
    assert!(out.status.success());
    // A note, so on stderr (stdout holds only the report: docs/output.md).
    assert!(String::from_utf8_lossy(&out.stderr).contains("Open it in Foxglove"));
    let summary = rsts(&["inspect", p]);
    assert!(summary.status.success());
    let text = String::from_utf8(summary.stdout).unwrap();
    assert!(text.contains("status: complete"), "{text}");
    assert!(
        text.contains("/errors")
            && text.contains("foxglove.FrameTransform")
            && text.contains("foxglove.SceneUpdate")
    );
    assert!(text.contains("integrator.method = dop853"));
    let csv = rsts(&["inspect", p, "--channel", "/errors", "--format", "csv"]);
    assert!(csv.status.success());
    let csv = String::from_utf8(csv.stdout).unwrap();
    assert_eq!(csv.lines().count(), 52, "header + 51 samples");
    let header = csv.lines().next().unwrap();
    for field in [
        "distance_from_n",
        "phase_error_psi1",
        "phase_error_psi2",
        "x_phi",
    ] {
        assert!(header.contains(field), "{header}");
    }
    assert!(csv.lines().next().unwrap().contains("state_error"));
    let bad = rsts(&["inspect", p, "--channel", "/nope"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("/errors"),
        "lists the available channels"
    );
}

#[test]
fn a_file_cut_in_half_gives_what_can_be_recovered() {
    let path = tmp("full.mcap");
    let p = path.to_str().unwrap();
    assert!(
        rsts(&["compare", "--t-end", "20", "--samples", "401", "--mcap", p])
            .status
            .success()
    );
    let bytes = std::fs::read(&path).unwrap();
    let half = tmp("half.mcap");
    std::fs::write(&half, &bytes[..bytes.len() / 2]).unwrap();
    let out = rsts(&["inspect", half.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(3), "recovered, not healthy");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("truncated or damaged"), "{err}");
    assert!(!err.contains("panicked"));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("/errors"),
        "the recovered part is shown: {text}"
    );
    let garbage = tmp("garbage.mcap");
    std::fs::write(&garbage, b"this is not an mcap file at all").unwrap();
    let out = rsts(&["inspect", garbage.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "));
    let missing = rsts(&["inspect", "/nonexistent/x.mcap"]);
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn ctrl_c_leaves_a_readable_file() {
    let path = tmp("interrupted.mcap");
    let p = path.to_str().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args([
            "compare",
            "--t-end",
            "20000",
            "--samples",
            "400001",
            "--mcap",
            p,
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("interrupted"));
    assert!(String::from_utf8_lossy(&out.stdout).contains("(interrupted)"));
    let summary = rsts(&["inspect", p]);
    assert!(
        summary.status.success(),
        "{}",
        String::from_utf8_lossy(&summary.stderr)
    );
    assert!(String::from_utf8_lossy(&summary.stdout).contains("status: complete"));
}

#[test]
fn bad_input_is_named() {
    let err = |args: &[&str]| exit_2(&rsts_command("compare", args), args);
    assert!(err(&["--m", "0", "--h", "2"]).contains("Σ"));
    assert!(err(&["--rtol", "0"]).contains("rtol"));
    assert!(err(&["--t-end", "inf"]).contains("--t-end"));
    assert!(err(&["--torus", "5"]).contains("torus 5 does not exist"));
    assert!(err(&["--method", "taylor-mp", "--digits", "3"]).contains("--digits"));
    assert!(err(&["--mcap", "/proc/nope/x.mcap", "--samples", "3"]).contains("--mcap"));
}

#[test]
fn svg_draws_the_errors_against_time_and_bad_paths_are_refused_before_work() {
    let path = tmp("sub/errors.svg");
    let p = path.to_str().unwrap();
    let out = rsts(&[
        "compare",
        "--t-end",
        "10",
        "--samples",
        "101",
        "--format",
        "json",
        "--svg",
        p,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // stdout is the report alone; the SVG is named on stderr.
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON report");
    assert_eq!(v["samples_compared"], 101);
    assert!(String::from_utf8_lossy(&out.stderr).contains(p));
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"));
    for text in [
        "dop853 at rtol = atol = 1e-12 against the exact motion",
        "camera I+: a = 1, b = 0.5, m = 0.3, h = −0.375, torus 0",
        "time t",
        "state error",
        "drift of H",
        "drift of K",
        "drift of G",
    ] {
        assert!(svg.contains(text), "missing {text:?}");
    }

    let err = |args: &[&str]| exit_2(&rsts_command("compare", args), args);
    assert!(err(&["--samples", "1", "--svg", p]).contains("at least 2 samples"));
    assert!(err(&["--svg", "/proc/nope/x.svg", "--samples", "3"]).contains("--svg"));
    let same = tmp("same.out");
    let same = same.to_str().unwrap();
    let msg = err(&["--samples", "3", "--svg", same, "--mcap", same]);
    assert!(msg.contains("--svg") && msg.contains("--mcap"), "{msg}");
    assert!(!std::path::Path::new(same).exists());
    // A diagram that cannot be written after the run is named as --svg (was "--mcap /dev/full:
    // --svg /dev/full: …").
    let msg = err(&["--samples", "3", "--svg", "/dev/full"]);
    assert!(
        msg.contains("--svg /dev/full") && !msg.contains("--mcap"),
        "{msg}"
    );
}
