//! `--jobs N`: the samples are computed on N threads and the output is the same bytes for any
//! N (rows in input order across batches of 8192).

use crate::common;
use common::{camera_v_dopri5_csv, fails, ok, s, tmp};

fn run(args: &[&str], jobs: &str) -> Vec<u8> {
    let mut all = args.to_vec();
    all.extend(["--jobs", jobs]);
    ok(&all).stdout
}

#[test]
fn reference_output_is_the_same_on_any_number_of_threads() {
    // 20 000 rows: three batches, the last one partial.
    for format in ["csv", "json", "npy"] {
        let args = [
            "reference",
            "--m",
            "-0.7092",
            "--h",
            "1.5643",
            "--torus",
            "2",
            "--t-end",
            "500",
            "--samples",
            "20000",
            "--format",
            format,
        ];
        let one = run(&args, "1");
        assert!(one.len() > 20_000 * 13 * 8, "{format}: {} bytes", one.len());
        for jobs in ["2", "3"] {
            assert!(
                run(&args, jobs) == one,
                "{format}: --jobs {jobs} differs from --jobs 1"
            );
        }
    }
    let e = fails(&["reference", "--times", "0,1", "--jobs", "0"]);
    assert!(e.contains("--jobs") && e.contains("need N >= 1"), "{e}");
}

#[test]
fn check_report_is_the_same_on_any_number_of_threads() {
    // A dopri5 run of camera V, 12 000 samples (three batches of the analysis), to CSV.
    let csv = camera_v_dopri5_csv("300", 12000);
    let path = tmp("traj.csv");
    std::fs::write(&path, &csv).unwrap();
    let args = ["check", s(&path), "--format", "json"];
    let one = run(&args, "1");
    let report: serde_json::Value = serde_json::from_slice(&one).unwrap();
    assert_eq!(report["samples_compared"], 12000);
    assert!(report["max_state_error"].as_f64().unwrap() > 1e-10);
    assert!(
        run(&args, "2") == one,
        "check --jobs 2 differs from --jobs 1"
    );
    assert!(
        run(&args, "3") == one,
        "check --jobs 3 differs from --jobs 1"
    );
}
