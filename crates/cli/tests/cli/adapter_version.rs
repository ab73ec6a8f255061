//! An adapter's self-reported library version (`"version"` in its answer) is recorded per method
//! in the reports' `environment.adapters`; a version that is not a short string is refused.

use serde_json::Value;

use crate::common;
use common::{adapter_command, adapter_rk4, exit_2, python_with, rsts, stderr, stdout, tmp};

/// A shell script standing in for an adapter.
fn script(name: &str, body: &str) -> String {
    let path = tmp(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_str().unwrap().to_string()
}

fn run_json(args: &[&str]) -> Value {
    let out = rsts(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_str(&stdout(&out)).unwrap()
}

const SHORT: [&str; 4] = ["--t-end", "1", "--samples", "11"];

#[test]
fn the_example_adapters_version_is_in_compare_and_bench() {
    let adapter = adapter_rk4();
    let adapter = adapter.to_str().unwrap();
    let mut args = vec!["compare", "--exec", adapter, "--format", "json"];
    args.extend(SHORT);
    let doc = run_json(&args);
    let want = serde_json::json!([{
        "method": "example-rk4",
        "version": concat!("example-adapter-rk4 ", env!("CARGO_PKG_VERSION")),
    }]);
    assert_eq!(doc["environment"]["adapters"], want);
    assert!(doc["environment"]["cpu"].is_string());
    // The table's environment line names it too.
    let mut args = vec!["compare", "--exec", adapter];
    args.extend(SHORT);
    let table = stdout(&rsts(&args));
    let line = table
        .lines()
        .find(|l| l.starts_with("environment:"))
        .unwrap_or_else(|| panic!("{table}"));
    assert!(line.contains("example-rk4 example-adapter-rk4 "), "{line}");
    // bench: once per method, whatever the number of tolerances.
    let mut args = vec![
        "bench",
        "--exec",
        adapter,
        "--tolerances",
        "1e-6,1e-8",
        "--repeats",
        "1",
        "--format",
        "json",
    ];
    args.extend(SHORT);
    assert_eq!(run_json(&args)["environment"]["adapters"], want);
    // A built-in method has no adapters entry.
    let mut args = vec!["compare", "--format", "json"];
    args.extend(SHORT);
    assert!(run_json(&args)["environment"].get("adapters").is_none());
}

#[test]
fn a_version_that_is_not_a_short_string_is_refused() {
    let adapter = adapter_rk4();
    let long = "x".repeat(201);
    for (name, replacement, want) in [
        (
            "number",
            "42".to_string(),
            "\"version\" must be a non-empty string",
        ),
        (
            "empty",
            "\"  \"".to_string(),
            "\"version\" must be a non-empty string",
        ),
        (
            "long",
            format!("\"{long}\""),
            "\"version\" has 201 characters, at most 200 are taken",
        ),
        (
            "control",
            "\"1.0\\u001b[31m\"".to_string(),
            "\"version\" must not hold control characters",
        ),
    ] {
        let s = script(
            &format!("version-{name}.sh"),
            &format!(
                "'{}' | sed 's/\"version\":\"[^\"]*\"/\"version\":{}/'",
                adapter.display(),
                replacement.replace('\\', "\\\\")
            ),
        );
        let mut args = vec!["compare", "--exec", &s];
        args.extend(SHORT);
        let err = exit_2(&rsts(&args), name);
        assert!(err.contains(want), "{name}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // 200 characters pass.
    let s = script(
        "version-200.sh",
        &format!(
            "'{}' | sed 's/\"version\":\"[^\"]*\"/\"version\":\"{}\"/'",
            adapter.display(),
            "y".repeat(200)
        ),
    );
    let mut args = vec!["compare", "--exec", &s, "--format", "json"];
    args.extend(SHORT);
    assert_eq!(
        run_json(&args)["environment"]["adapters"][0]["version"],
        "y".repeat(200)
    );
}

#[test]
fn the_scipy_and_heyoka_adapters_send_their_versions() {
    for (package, script, arg) in [
        ("scipy", "scipy_adapter.py", "DOP853"),
        ("heyoka", "heyoka_adapter.py", "f64"),
    ] {
        let Some(python) = python_with(package, "adapter_version") else {
            continue;
        };
        let command = adapter_command(&python, script, arg);
        let mut args = vec!["compare", "--exec", &command, "--format", "json"];
        args.extend(SHORT);
        let doc = run_json(&args);
        let version = doc["environment"]["adapters"][0]["version"]
            .as_str()
            .unwrap_or_else(|| panic!("{package}: {}", doc["environment"]));
        assert!(version.starts_with(&format!("{package} ")), "{version}");
        assert!(version[package.len() + 1..].starts_with(|c: char| c.is_ascii_digit()));
    }
}
