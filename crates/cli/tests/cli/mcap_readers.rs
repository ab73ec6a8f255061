//! Every kind of MCAP file `rsts` writes (compare, check, surfaces scene) is read by every reader a user may have:
//! * the `mcap` crate: `rsts_mcap::compat::reader_problems` (no chunk without messages, every
//!   chunk index with a message index, counts that agree with a linear read);
//! * the official Python reader (`scripts/check_mcap.py`, `mcap` from PyPI);
//! * @mcap/core 2.1.0 (the reader of Foxglove Studio 1.x) and today's @mcap/core under node,
//!   indexed and streamed, with every message validated by Ajv against the schema its channel
//!   carries and the official `@foxglove/schemas` JSON schemas (`scripts/mcap-readers`).
//!
//! The same checks are shown to fail on a file in the layout the writer produced before
//! (a first chunk without messages): @mcap/core 2.1.0 rejects it as Foxglove Studio did.
//! Tests that need python's `mcap` or node/npm skip with `rsts_io::report_skip` without them.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::{rsts_command, stderr, tmp};
use rsts_mcap::compat::{reader_problems, with_empty_first_chunk};
use serde_json::Value;

/// One kind of file, and the arguments of `scripts/check_mcap.py` that describe it.
struct Kind {
    name: &'static str,
    path: PathBuf,
    python_args: Vec<String>,
}

const COMPARE_SAMPLES: usize = 101;

/// The files, written once per test process.
fn kinds() -> &'static [Kind] {
    static KINDS: OnceLock<Vec<Kind>> = OnceLock::new();
    KINDS.get_or_init(|| {
        let compare = tmp("compare.mcap");
        let samples = COMPARE_SAMPLES.to_string();
        let run = |command: &str, args: String| {
            let args: Vec<&str> = args.split_whitespace().collect();
            let out = rsts_command(command, &args);
            assert!(out.status.success(), "{command}: {}", stderr(&out));
        };
        run(
            "compare",
            format!(
                "--t-end 5 --samples {samples} --format json --mcap {}",
                compare.display()
            ),
        );
        // `rsts check` logs like compare: here it checks the compare log's integrated channel.
        let check = tmp("check.mcap");
        run(
            "check",
            format!(
                "{} --format json --mcap {}",
                compare.display(),
                check.display()
            ),
        );
        let dir = tmp("surfaces");
        run(
            "surfaces",
            format!(
                "--m 0.3 --h -0.375 --torus 0 --scene-grid 16 --grid 16 --size 64 --samples 400 \
                 --no-ply --out {}",
                dir.display()
            ),
        );
        vec![
            Kind {
                name: "compare",
                path: compare,
                python_args: vec!["--rsts-layout".into(), "--samples".into(), samples.clone()],
            },
            Kind {
                name: "check",
                path: check,
                python_args: vec!["--rsts-layout".into(), "--samples".into(), samples.clone()],
            },
            Kind {
                name: "surfaces scene",
                path: dir.join("torus0_scene.mcap"),
                python_args: vec![
                    "--expect-channels".into(),
                    "/tf=foxglove.FrameTransform".into(),
                    "/surface/p=foxglove.SceneUpdate".into(),
                    "/surface/pi=foxglove.SceneUpdate".into(),
                    "/hodograph/moving=foxglove.SceneUpdate".into(),
                    "/hodograph/fixed=foxglove.SceneUpdate".into(),
                    "--expect-count".into(),
                    "/tf=400".into(),
                    "/surface/p=2".into(),
                    "/surface/pi=2".into(),
                ],
            },
        ]
    })
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Messages per topic, read with the mcap crate.
fn counts(bytes: &[u8]) -> std::collections::BTreeMap<String, u64> {
    let mut c = std::collections::BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        *c.entry(m.unwrap().channel.topic.clone()).or_default() += 1;
    }
    c
}

/// The file in the writer's former layout, beside the original.
fn old_layout(kind: &Kind) -> PathBuf {
    let old = kind.path.with_extension("old-layout.mcap");
    let bytes = std::fs::read(&kind.path).unwrap();
    std::fs::write(&old, with_empty_first_chunk(&bytes).unwrap()).unwrap();
    old
}

#[test]
fn the_mcap_crate_finds_no_chunk_without_messages() {
    for kind in kinds() {
        let bytes = std::fs::read(&kind.path).unwrap();
        assert_eq!(
            reader_problems(&bytes),
            Vec::<String>::new(),
            "{}",
            kind.name
        );
        assert!(counts(&bytes).values().all(|&n| n > 0));
        // Shown to fail on the former layout of the same file.
        let old = std::fs::read(old_layout(kind)).unwrap();
        let problems = reader_problems(&old);
        assert!(
            problems.iter().any(|p| p.contains("no message index")),
            "{}: {problems:?}",
            kind.name
        );
        assert_eq!(counts(&old), counts(&bytes));
    }
}

#[test]
fn the_python_mcap_reader_reads_every_kind() {
    let python = std::env::var("RSTS_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = repo().join("scripts/check_mcap.py");
    for kind in kinds() {
        let out = match Command::new(&python)
            .arg(&script)
            .arg(&kind.path)
            .args(&kind.python_args)
            .arg("--optional")
            .output()
        {
            Ok(out) => out,
            Err(e) => {
                return rsts_io::report_skip(
                    "the_python_mcap_reader_reads_every_kind",
                    &format!("cannot run {python}: {e}"),
                )
            }
        };
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        if text.contains("skipped: python mcap not installed") {
            return rsts_io::report_skip(
                "the_python_mcap_reader_reads_every_kind",
                &format!(
                    "the python `mcap` package is not installed for {python} (set RSTS_PYTHON; .ci/run makes a venv)"
                ),
            );
        }
        assert!(
            out.status.success() && text.contains("OK: read by the Python mcap library"),
            "{}: {text}{}",
            kind.name,
            stderr(&out)
        );
    }
}

/// NODE_PATH for `scripts/mcap-readers`, installed by `scripts/node_deps.sh`; `Err` is why not.
fn node_readers() -> Result<String, String> {
    let out = Command::new("bash")
        .arg(repo().join("scripts/node_deps.sh"))
        .arg("mcap-readers")
        .output()
        .map_err(|e| format!("cannot run bash: {e}"))?;
    if !out.status.success() {
        return Err(stderr(&out).trim().to_string());
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Runs `read_mcap.cjs` on `files`: (exit code, the JSON document).
fn read_with_node(node_path: &str, files: &[&Path]) -> (Option<i32>, Value) {
    let out = Command::new("node")
        .arg(repo().join("scripts/mcap-readers/read_mcap.cjs"))
        .args(files)
        .env("NODE_PATH", node_path)
        .output()
        .expect("run node");
    let doc = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("read_mcap.cjs printed no JSON ({e}): {}", stderr(&out)));
    (out.status.code(), doc)
}

#[test]
fn mcap_core_old_and_current_read_every_kind_with_official_schemas() {
    let node_path = match node_readers() {
        Ok(p) => p,
        Err(why) => {
            return rsts_io::report_skip(
                "mcap_core_old_and_current_read_every_kind_with_official_schemas",
                &why,
            )
        }
    };
    let files: Vec<&Path> = kinds().iter().map(|k| k.path.as_path()).collect();
    let (code, doc) = read_with_node(&node_path, &files);
    assert_eq!(code, Some(0), "{doc:#}");
    assert_eq!(doc["readers"]["@mcap/core 2.1.0"], "2.1.0");
    assert_eq!(doc["schemas_package"], "2.1.0");
    for (kind, entry) in kinds().iter().zip(doc["files"].as_array().unwrap()) {
        let expected = counts(&std::fs::read(&kind.path).unwrap());
        for (label, r) in entry["readers"].as_object().unwrap() {
            assert_eq!(r["ok"], true, "{} with {label}: {r:#}", kind.name);
            for how in ["indexed", "stream"] {
                let got: std::collections::BTreeMap<String, u64> =
                    serde_json::from_value(r[how]["by_topic"].clone()).unwrap();
                assert_eq!(got, expected, "{} with {label}, {how}", kind.name);
            }
        }
        let schemas = entry["schemas"].as_object().unwrap();
        for name in ["foxglove.FrameTransform", "foxglove.SceneUpdate"] {
            assert_eq!(
                schemas[name]["equals_official"], true,
                "{}: {name}",
                kind.name
            );
        }
        for (name, s) in schemas {
            assert_eq!(s["invalid_messages"], 0, "{}: {name}: {s:#}", kind.name);
            assert!(s["messages"].as_u64().unwrap() > 0);
        }
    }
    // The former layout: @mcap/core 2.1.0 rejects it as Foxglove Studio 1.48 did; today's
    // @mcap/core reads it.
    let old = old_layout(&kinds()[0]);
    let (code, doc) = read_with_node(&node_path, &[&old]);
    assert_eq!(code, Some(1));
    let readers = &doc["files"][0]["readers"];
    assert_eq!(readers["@mcap/core 2.1.0"]["ok"], false);
    assert!(readers["@mcap/core 2.1.0"]["error"]
        .as_str()
        .unwrap()
        .contains("Chunks without message indexes"));
    assert_eq!(readers["@mcap/core current"]["ok"], true);
}
