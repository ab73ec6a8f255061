//! scripts/bench_vs_heyoka.sh and its driver scripts/bench_vs_heyoka.py: the shell script
//! parses, and the driver's selection logic (the cheapest tolerance reaching a target error,
//! the best error, the per-round ratios, criterion's bencher lines) passes its self-test. The
//! measurement itself needs heyoka and minutes of machine time: it is a script, not a test
//! (docs/benchmarks.md).

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn shell_script_parses() {
    let out = Command::new("bash")
        .arg("-n")
        .arg(root().join("scripts/bench_vs_heyoka.sh"))
        .output()
        .expect("run bash");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn driver_selftest() {
    let Ok(out) = Command::new("python3")
        .arg(root().join("scripts/bench_vs_heyoka.py"))
        .arg("selftest")
        .output()
    else {
        rsts_io::report_skip("driver_selftest", "python3 not found");
        return;
    };
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "selftest ok");
}
