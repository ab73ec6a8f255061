//! `--jobs N`: the samples are computed on N threads and the output is the same bytes for any
//! N (rows in input order across batches of 8192).

mod common;
use common::{fails, rsts, s, tmp};

fn run(args: &[&str], jobs: &str) -> Vec<u8> {
    let mut all = args.to_vec();
    all.extend(["--jobs", jobs]);
    let out = rsts(&all);
    assert!(out.status.success(), "{all:?}: {}", common::stderr(&out));
    out.stdout
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
    let out = rsts(&[
        "integrate",
        "--omega=-1.0788400339538464,-0.3702277283006931,0",
        "--alpha=-0.5266712206715436,-0.8500690709091504,0",
        "--beta=-0.8500690709091504,0.5266712206715436,0",
        "--t-end",
        "300",
        "--samples",
        "12000",
        "--method",
        "dopri5",
        "--rtol",
        "1e-9",
        "--atol",
        "1e-9",
        "--format",
        "csv",
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let path = tmp("traj.csv");
    std::fs::write(&path, &out.stdout).unwrap();
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
