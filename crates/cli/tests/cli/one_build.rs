//! One build serves both README commands: `scripts/run.sh` builds the binary (`cargo build
//! --release -p rsts-cli`), then `scripts/test.sh` (`cargo test --release --workspace`) must not
//! compile any crate of that build a second time. It would, whenever a dev-dependency (criterion,
//! rand, proptest, …) turns on a feature of a crate the binary also uses: cargo then builds that
//! crate, and everything above it, once more with the union of the features. The feature pins in
//! crates/cli/Cargo.toml enable those features in the binary's own build.
//!
//! The same holds for the example adapter, which docs/compare.md builds alone (`cargo build
//! --release -p example-adapter-rk4`): with other features it would be compiled again and
//! re-linked in target/release while documented examples and tests run it; its feature pins are
//! in crates/example-adapter-rk4/Cargo.toml.
//!
//! Two checks: the features `cargo tree` resolves for the binary's build are among those of the
//! test build (fast, and names the crate and feature to pin), and — in a release test run, where
//! the test build has just happened — `cargo build --release -p rsts-cli` finds every unit fresh
//! (catches any other cause, e.g. a profile setting that differs between the two builds).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .unwrap()
        .to_path_buf()
}

fn cargo() -> Command {
    let mut c = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    c.current_dir(workspace());
    c
}

/// Package ("name version") → the feature sets it is built with, from `cargo tree` lines
/// `name vX.Y.Z [f1,f2]`, `name vX.Y.Z (/path) [f]`, with `(*)` or `(proc-macro)` marks.
fn parse_tree(text: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in text.lines() {
        let (Some(open), Some(close)) = (line.rfind('['), line.rfind(']')) else {
            continue;
        };
        let mut words = line[..open].split_whitespace();
        let (Some(name), Some(version)) = (words.next(), words.next()) else {
            continue;
        };
        out.entry(format!("{name} {version}"))
            .or_default()
            .insert(line[open + 1..close].to_string());
    }
    out
}

fn tree(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let out = cargo()
        .arg("tree")
        .args(args)
        .args(["-f", "{p} [{f}]", "--prefix", "none", "--offline"])
        .output()
        .expect("run cargo tree");
    assert!(
        out.status.success(),
        "cargo tree {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    parse_tree(&String::from_utf8_lossy(&out.stdout))
}

/// The (package, features) of the binary's build that the test build does not have.
fn missing(
    bin: &BTreeMap<String, BTreeSet<String>>,
    test: &BTreeMap<String, BTreeSet<String>>,
) -> Vec<String> {
    let mut problems = Vec::new();
    for (pkg, sets) in bin {
        let in_test = test.get(pkg).cloned().unwrap_or_default();
        for features in sets.difference(&in_test) {
            problems.push(format!(
                "{pkg}: the binary's build has features [{features}], the test build only {:?}",
                in_test
            ));
        }
    }
    problems
}

#[test]
fn the_comparison_flags_a_feature_that_only_the_test_build_turns_on() {
    let bin = parse_tree(
        "serde_core v1.0.229 [result,std]\nrsts-io v0.1.0 (/w/crates/io) []\nsyn v2.0.1 [full] (*)\n",
    );
    let test = parse_tree(
        "serde_core v1.0.229 [alloc,result,std]\nrsts-io v0.1.0 (/w/crates/io) []\nsyn v2.0.1 [full]\n",
    );
    assert_eq!(bin["syn v2.0.1"], BTreeSet::from(["full".to_string()]));
    let found = missing(&bin, &test);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("serde_core v1.0.229"), "{found:?}");
    assert!(missing(&test, &test).is_empty());
}

/// Both checks in one test, in order: the slow one (which, when it fails, rebuilds part of the
/// binary's build) runs only when the fast one has passed.
#[test]
fn the_binary_shares_every_unit_with_the_test_build() {
    for package in ["rsts-cli", "example-adapter-rk4"] {
        features_of_the_binary_are_those_of_the_test_build(package);
    }
    // Only the binary: a test run of this crate alone builds rsts but not the adapter.
    after_the_test_build_the_binary_build_is_fresh("rsts-cli", 50);
}

fn features_of_the_binary_are_those_of_the_test_build(package: &str) {
    let bin = tree(&["-p", package, "-e", "normal,build"]);
    // As scripts/test.sh builds it (the Python extension is built by maturin there).
    let test = tree(&[
        "--workspace",
        "--exclude",
        "rsts-python",
        "-e",
        "normal,build,dev",
    ]);
    assert!(
        bin.keys().any(|k| k.starts_with(&format!("{package} "))),
        "{bin:?}"
    );
    let problems = missing(&bin, &test);
    assert!(
        problems.is_empty(),
        "`cargo build --release -p {package}` and the test build would compile these crates (and \
         all above them) each with its own features; turn the features on in the feature pins \
         of {package}'s Cargo.toml:\n{}",
        problems.join("\n")
    );
}

fn after_the_test_build_the_binary_build_is_fresh(package: &str, least_units: usize) {
    if cfg!(debug_assertions) {
        rsts_io::report_skip(
            "one_build::after_the_test_build_the_binary_build_is_fresh",
            "a debug test run has not built the release binary (run scripts/test.sh)",
        );
        return;
    }
    let out = cargo()
        .args([
            "build",
            "--release",
            "-p",
            package,
            "--offline",
            "--message-format=json",
        ])
        .output()
        .expect("run cargo build");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut units = 0;
    let mut rebuilt = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        if !line.contains(r#""reason":"compiler-artifact""#) {
            continue;
        }
        units += 1;
        if line.contains(r#""fresh":false"#) {
            let id = line
                .split(r#""package_id":""#)
                .nth(1)
                .and_then(|s| s.split('"').next())
                .unwrap_or(line);
            rebuilt.push(id.to_string());
        }
    }
    assert!(
        units > least_units,
        "only {units} units in the build of {package}"
    );
    assert!(
        rebuilt.is_empty(),
        "cargo build --release -p {package} recompiled {} of {units} units the test build had \
         built: {rebuilt:#?}",
        rebuilt.len()
    );
}
