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

/// The path `name` in this test process's temporary directory (created if needed):
/// `rsts-<test file>-tests-<pid>`.
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "rsts-{}-tests-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
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
