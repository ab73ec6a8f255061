//! The independent reader: `scripts/check_mcap.py` (official Python `mcap` package) on a
//! file written here. Runs with `$RSTS_PYTHON` or `python3`; when neither the interpreter
//! nor its `mcap` package is available the test reports itself skipped (`rsts_io::report_skip`).

use crate::common;

use std::path::PathBuf;
use std::process::Command;

use common::write_log;

#[test]
fn python_mcap_reads_the_log() {
    let n = 120;
    let (path, _) = write_log("python.mcap", n);
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scripts/check_mcap.py");
    let python = std::env::var("RSTS_PYTHON").unwrap_or_else(|_| "python3".into());
    let run = |samples: usize| {
        Command::new(&python)
            .arg(&script)
            .arg(&path)
            .args([
                "--rsts-layout",
                "--samples",
                &samples.to_string(),
                "--optional",
            ])
            .output()
    };
    let out = match run(n) {
        Ok(o) => o,
        Err(e) => {
            return rsts_io::report_skip(
                "python_mcap_reads_the_log",
                &format!("cannot run {python}: {e}"),
            )
        }
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "check_mcap.py failed");
    if stdout.contains("skipped: python mcap not installed") {
        return rsts_io::report_skip(
            "python_mcap_reads_the_log",
            &format!("the python `mcap` package is not installed for {python} (set RSTS_PYTHON)"),
        );
    }
    assert!(stdout.contains("OK: read by the Python mcap library"));
    // The script really checks: a wrong expectation fails.
    let wrong = run(n + 1).unwrap();
    assert_eq!(wrong.status.code(), Some(1));
}
