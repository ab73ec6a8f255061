//! Helpers shared by the CLI integration tests. Each `tests/*.rs` file is its own crate and
//! includes this module with `mod common;`; each uses a subset of it.
#![allow(dead_code)]

use std::fmt::Debug;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the built `rsts` binary with `args`.
pub fn rsts(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(args)
        .output()
        .expect("run the rsts binary")
}

/// Runs `rsts <command> args…`.
pub fn rsts_command(command: &str, args: &[&str]) -> Output {
    let mut all = vec![command];
    all.extend_from_slice(args);
    rsts(&all)
}

/// The standard output of a run, as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("stdout is UTF-8")
}

/// The standard error of a run, as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).expect("stderr is UTF-8")
}

/// Runs `rsts args…` and asserts that it succeeded (the arguments and stderr shown if not).
pub fn ok(args: &[&str]) -> Output {
    let out = rsts(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    out
}

/// The one JSON document on the stdout of a run that must have succeeded.
pub fn json_doc(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout).expect("one JSON document")
}

/// Runs `rsts args… --format json`, expects success and returns the document.
pub fn json_of(args: &[&str]) -> serde_json::Value {
    let mut all = args.to_vec();
    all.extend_from_slice(&["--format", "json"]);
    serde_json::from_slice(&ok(&all).stdout).expect("one JSON document")
}

/// Runs `rsts <command> args… --format json`, expects success and returns the document.
pub fn command_json(command: &str, args: &[&str]) -> serde_json::Value {
    let mut all = vec![command];
    all.extend_from_slice(args);
    json_of(&all)
}

/// A dopri5 run (rtol = atol = 1e-9) of a camera V motion, whose error grows: `rsts integrate`
/// to `t_end` with `samples` samples, as CSV.
pub fn camera_v_dopri5_csv(t_end: &str, samples: usize) -> Vec<u8> {
    ok(&[
        "integrate",
        "--omega=-1.0788400339538464,-0.3702277283006931,0",
        "--alpha=-0.5266712206715436,-0.8500690709091504,0",
        "--beta=-0.8500690709091504,0.5266712206715436,0",
        "--t-end",
        t_end,
        "--samples",
        &samples.to_string(),
        "--method",
        "dopri5",
        "--rtol",
        "1e-9",
        "--atol",
        "1e-9",
        "--format",
        "csv",
    ])
    .stdout
}

/// Writes `bytes` to [`tmp`]`(name)` and returns the path as a string, for an argument list.
pub fn write(name: &str, bytes: &[u8]) -> String {
    let p = tmp(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

/// The path `name` in this test file's temporary directory (created if needed):
/// `rsts-<test file>-tests-<pid>`. All the files are modules of one test process, so the file is
/// the first part of the running test's name (the name of its thread: `check::some_test`); two
/// files may use the same `name` at the same time.
pub fn tmp(name: &str) -> PathBuf {
    let thread = std::thread::current();
    let file = thread
        .name()
        .and_then(|n| n.split_once("::"))
        .map_or("cli", |(file, _)| file);
    let dir = std::env::temp_dir().join(format!("rsts-{file}-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Asserts that the run `out` exited with code 2 (bad input) and returns its stderr;
/// `what` (the arguments, a case name) is shown if it did not.
pub fn exit_2(out: &Output, what: impl Debug) -> String {
    assert_eq!(out.status.code(), Some(2), "{what:?}");
    stderr(out)
}

/// Runs `rsts args…`, expects exit code 2 and returns stderr.
pub fn fails(args: &[&str]) -> String {
    exit_2(&rsts(args), args)
}

/// A path as `&str`, for an argument list.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A fresh empty directory `name` under [`tmp`], for one test.
pub fn dir(name: &str) -> PathBuf {
    let d = tmp(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The names in a directory, sorted.
pub fn entries(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The compiled example adapter: beside the rsts binary (built by `cargo test --workspace`), or
/// built now into its own target directory.
pub fn adapter_rk4() -> PathBuf {
    let rsts = PathBuf::from(env!("CARGO_BIN_EXE_rsts"));
    let beside = rsts.with_file_name("example-adapter-rk4");
    if beside.exists() {
        return beside;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = root.join("target/adapter-build");
    let status = Command::new(env!("CARGO"))
        .args(["build", "--release", "--quiet", "-p", "example-adapter-rk4"])
        .env("CARGO_TARGET_DIR", &dir)
        .current_dir(&root)
        .status()
        .expect("run cargo");
    assert!(status.success(), "cargo build -p example-adapter-rk4");
    dir.join("release/example-adapter-rk4")
}

/// The Python of scripts/install_adapters.sh when it has `package` (`$RSTS_ADAPTERS_PYTHON` or
/// `.venv-adapters/bin/python`); `None` (the test reports a skip) otherwise.
pub fn python_with(package: &str, test: &str) -> Option<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let python = std::env::var("RSTS_ADAPTERS_PYTHON").unwrap_or_else(|_| {
        root.join(".venv-adapters/bin/python")
            .to_string_lossy()
            .into_owned()
    });
    let ok = Command::new(&python)
        .args(["-c", &format!("import {package}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(python)
    } else {
        rsts_io::report_skip(
            test,
            &format!("{package} is not installed (scripts/install_adapters.sh {package}; needs pip and PyPI)"),
        );
        None
    }
}

pub fn adapter_command(python: &str, script: &str, arg: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/adapters");
    format!("{python} {} {arg}", root.join(script).display())
}

/// The report of `rsts check FILE --format json` (motion identified, default fields) computed
/// by the library on the whole trajectory `raw` at once: `file` as given, `name` the method.
pub fn whole_check(
    raw: &rsts_external::RawTrajectory,
    file: &str,
    name: &str,
    digits: u32,
) -> serde_json::Value {
    let request = rsts_harness::CheckRequest {
        file: file.to_string(),
        name: name.to_string(),
        motion: rsts_harness::CheckMotion::Identify {
            a: rsts_closed_form::Decimal::from_integer(1),
            b: rsts_closed_form::Decimal::parse("0.5").unwrap(),
        },
        digits,
    };
    let samples = raw.to_samples(request.reference_bits());
    let whole = rsts_harness::check(
        &request,
        &samples.times,
        &samples.states,
        &mut rsts_harness::NoObserver,
    )
    .unwrap();
    serde_json::to_value(&whole).unwrap()
}

#[path = "../../../../harness/tests/harness/support/geometry_digits.rs"]
mod geometry_digits;
#[allow(unused_imports)] // each test file uses a subset of this module
pub use geometry_digits::assert_same_but_the_geometrys_last_digits;
