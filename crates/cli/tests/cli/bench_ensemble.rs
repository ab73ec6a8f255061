//! `rsts bench --ensemble`: each motion's row is `rsts compare … --pieces 1` of that motion (to
//! the bit), the seed repeats the motions, the bands are drawn, bad input exits 2; shards
//! (`--shard K/N --json FILE`) merge (`rsts bench merge`) into the unsharded report.

use crate::common;

use common::{dir, entries, fails, rsts, s, stdout, tmp};
use serde_json::Value;

const SMALL: [&str; 8] = [
    "--t-end",
    "3",
    "--samples",
    "7",
    "--repeats",
    "1",
    "--tolerances",
    "1e-9,1e-11",
];

fn bench_json(extra: &[&str]) -> Value {
    let mut args = vec!["bench", "--format", "json"];
    args.extend(SMALL);
    args.extend(extra);
    let out = rsts(&args);
    assert!(out.status.success(), "{}", common::stderr(&out));
    serde_json::from_str(&stdout(&out)).unwrap()
}

fn num(v: &Value) -> String {
    v.as_f64()
        .map(|x| x.to_string())
        .unwrap_or_else(|| v.to_string())
}

/// Every row, rerun alone with `rsts compare` at its motion's m, h, torus and phases in one
/// piece, gives the same max error to the bit, the same steps and evaluations.
#[test]
fn each_row_is_a_comparison_of_its_motion_in_one_piece() {
    let doc = bench_json(&[
        "--ensemble",
        "3",
        "--cameras",
        "V,I-,VI",
        "--methods",
        "dop853,taylor-f64",
    ]);
    let motions = doc["ensemble"]["motions"].as_array().unwrap();
    assert_eq!(motions.len(), 3);
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3 * 2 * 2);
    for row in rows {
        let k = row["motion"].as_u64().unwrap() as usize;
        let mo = &motions[k];
        let tol = num(&row["tolerance"]);
        let out = rsts(&[
            "compare",
            "--format",
            "json",
            "--pieces",
            "1",
            "--t-end",
            "3",
            "--samples",
            "7",
            "--method",
            row["method"].as_str().unwrap(),
            "--rtol",
            &tol,
            "--atol",
            &tol,
            "--m",
            &num(&mo["m"]),
            "--h",
            &num(&mo["h"]),
            "--torus",
            &num(&mo["torus"]),
            "--phase1",
            &num(&mo["phase1"]),
            "--phase2",
            &num(&mo["phase2"]),
        ]);
        assert!(out.status.success(), "{}", common::stderr(&out));
        let c: Value = serde_json::from_str(&stdout(&out)).unwrap();
        assert_eq!(
            row["max_error"].as_f64().unwrap().to_bits(),
            c["max_state_error"].as_f64().unwrap().to_bits(),
            "motion {k}: {row} against {}",
            c["max_state_error"]
        );
        assert_eq!(row["steps"], c["steps"]);
        assert_eq!(row["rhs_evals"], c["rhs_evals"]);
    }
    let bands = doc["bands"].as_array().unwrap();
    assert_eq!(bands.len(), 4);
    for b in bands {
        let (lo, mid, hi) = (
            b["error_p05"].as_f64().unwrap(),
            b["error_median"].as_f64().unwrap(),
            b["error_p95"].as_f64().unwrap(),
        );
        assert!(0.0 < lo && lo <= mid && mid <= hi, "{b}");
        assert!(b["time_median"].as_f64().unwrap() > 0.0);
    }
}

/// The seed draws the motions: stated in the output, the same seed the same motions, another
/// seed others; the default seed is 2013.
#[test]
fn the_seed_repeats_the_motions_and_is_stated() {
    let one = &["--ensemble", "2", "--methods", "taylor-f64", "--seed", "5"];
    let a = bench_json(one);
    let b = bench_json(one);
    assert_eq!(a["ensemble"], b["ensemble"]);
    assert_eq!(a["ensemble"]["seed"], 5);
    let c = bench_json(&["--ensemble", "2", "--methods", "taylor-f64", "--seed", "6"]);
    assert_ne!(a["ensemble"]["motions"], c["ensemble"]["motions"]);
    let d = bench_json(&["--ensemble", "2", "--methods", "taylor-f64"]);
    assert_eq!(d["ensemble"]["seed"], 2013);
    let mut args = vec!["bench", "--ensemble", "2", "--methods", "taylor-f64"];
    args.extend(SMALL);
    let table = stdout(&rsts(&args));
    assert!(
        table.starts_with("ensemble of 2 motions (seed 2013)"),
        "{table}"
    );
    assert!(table.contains("95 %"), "{table}");
}

/// --svg draws one shaded band per method under its median line.
#[test]
fn the_svg_shades_a_band_per_method() {
    let path = tmp("ensemble.svg");
    let mut args = vec![
        "bench",
        "--ensemble",
        "3",
        "--methods",
        "dop853,taylor-f64",
        "--svg",
        s(&path),
    ];
    args.extend(SMALL);
    let out = rsts(&args);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let svg = std::fs::read_to_string(&path).unwrap();
    let bands: Vec<&str> = svg
        .lines()
        .filter(|l| l.contains(r#"class="band""#))
        .collect();
    assert_eq!(bands.len(), 2, "{svg}");
    assert!(bands[0].contains(r#"data-label="dop853""#));
    // Two tolerances: a band of 4 corners.
    assert_eq!(
        bands[0]
            .split("points=\"")
            .nth(1)
            .unwrap()
            .split(' ')
            .count(),
        4
    );
}

#[test]
fn bad_ensembles_exit_2_naming_the_option() {
    let bad: [(&[&str], &str); 6] = [
        (
            &["--ensemble", "0"],
            "--ensemble: an ensemble has 1 to 1000 motions, got 0",
        ),
        (
            &["--ensemble", "1001"],
            "--ensemble: an ensemble has 1 to 1000",
        ),
        (
            &["--ensemble", "2", "--cameras", "I+,VII"],
            "unknown camera 'VII'",
        ),
        (
            &["--ensemble", "2", "--cameras", "V,V"],
            "--cameras: camera V is given twice",
        ),
        (
            &[
                "--ensemble",
                "2",
                "--a",
                "1",
                "--b",
                "0.01",
                "--cameras",
                "I+",
            ],
            "--cameras: no admissible point well inside camera I+ for a = 1, b = 0.01",
        ),
        (
            &["--ensemble", "2", "--event", "omega1"],
            "--event/--ensemble: events are not located",
        ),
    ];
    for (args, want) in bad {
        let mut all = vec!["bench"];
        all.extend(SMALL);
        all.extend(args);
        let err = fails(&all);
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(fails(&["bench", "--seed", "3"]).contains("--ensemble"));
}

/// The report without what the clock decides (the rows' times, the bands' time percentiles).
fn without_times(mut doc: Value) -> Value {
    for (list, keys) in [
        (
            "rows",
            &["integration_seconds", "time_min", "time_median", "time_max"][..],
        ),
        ("bands", &["time_p05", "time_median", "time_p95"][..]),
    ] {
        for item in doc[list].as_array_mut().unwrap() {
            for key in keys {
                item.as_object_mut().unwrap().remove(*key).unwrap();
            }
        }
    }
    doc
}

/// Three shards written with --json, merged in another order: the report of the unsharded run
/// up to the times (rows, fits, error bands to the bit), the same on stdout as in the --json
/// file; each shard's table names its slice, the merged table every motion.
#[test]
fn three_shards_merge_into_the_unsharded_report() {
    let d = dir("shards");
    let ensemble = ["--ensemble", "7", "--methods", "dop853,taylor-f64"];
    let mut files = Vec::new();
    for k in 1..=3 {
        let file = d.join(format!("shard-{k}.json"));
        let shard = format!("{k}/3");
        let mut args = vec!["bench", "--shard", &shard, "--json", s(&file)];
        args.extend(SMALL);
        args.extend(ensemble);
        let out = rsts(&args);
        assert!(out.status.success(), "{}", common::stderr(&out));
        let table = stdout(&out);
        let held = if k == 1 { 3 } else { 2 };
        assert!(
            table.contains(&format!(
                "shard {k}/3: the {held} motions whose index is {} mod 3",
                k - 1
            )),
            "{table}"
        );
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        assert_eq!(doc["shard"]["k"], k);
        assert_eq!(doc["rows"].as_array().unwrap().len(), held * 4);
        files.push(file);
    }
    let whole = bench_json(&ensemble);
    let merged_file = d.join("merged.json");
    let out = rsts(&[
        "bench",
        "merge",
        s(&files[2]),
        s(&files[0]),
        s(&files[1]),
        "--json",
        s(&merged_file),
        "--format",
        "json",
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let merged: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let written = std::fs::read_to_string(&merged_file).unwrap();
    assert_eq!(written, stdout(&out), "--json holds what stdout shows");
    assert!(merged.get("shard").is_none());
    let rows = merged["rows"].as_array().unwrap();
    let motions: Vec<u64> = rows.iter().map(|r| r["motion"].as_u64().unwrap()).collect();
    assert_eq!(motions, (0..7).flat_map(|m| [m; 4]).collect::<Vec<u64>>());
    for (m, w) in merged["bands"]
        .as_array()
        .unwrap()
        .iter()
        .zip(whole["bands"].as_array().unwrap())
    {
        for key in ["error_p05", "error_median", "error_p95"] {
            assert_eq!(
                m[key].as_f64().unwrap().to_bits(),
                w[key].as_f64().unwrap().to_bits(),
                "{key}: {m} against {w}"
            );
        }
    }
    assert_eq!(without_times(merged), without_times(whole));
    let table = stdout(&rsts(&[
        "bench",
        "merge",
        s(&files[0]),
        s(&files[1]),
        s(&files[2]),
    ]));
    assert!(
        table.starts_with("ensemble of 7 motions (seed 2013)"),
        "{table}"
    );
    assert!(!table.contains("shard"), "{table}");
    assert!(table.contains("\n     6 "), "every motion listed: {table}");
}

/// A merge that cannot be made exits 2 naming the shard, and writes nothing: not its --json or
/// --svg, and never over an input.
#[test]
fn bad_merges_exit_2_naming_the_shard_and_write_nothing() {
    let d = dir("bad-merges");
    let shard = |k: usize, extra: &[&str]| {
        let file = d.join(format!("shard-{k}{}.json", extra.join("")));
        let part = format!("{k}/2");
        let mut args = vec![
            "bench",
            "--ensemble",
            "3",
            "--methods",
            "taylor-f64",
            "--shard",
            &part,
        ];
        args.extend(SMALL);
        args.extend(extra);
        args.extend(["--json", s(&file)]);
        let out = rsts(&args);
        assert!(out.status.success(), "{}", common::stderr(&out));
        file
    };
    let (one, two) = (shard(1, &[]), shard(2, &[]));
    let other = shard(2, &["--seed", "9"]);
    let before = entries(&d);
    let (json, svg) = (d.join("out.json"), d.join("out.svg"));
    let merge = |inputs: &[&std::path::Path]| {
        let mut args = vec!["bench", "merge"];
        args.extend(inputs.iter().map(|p| s(p)));
        args.extend(["--json", s(&json), "--svg", s(&svg)]);
        fails(&args)
    };
    let err = merge(&[&one]);
    assert!(err.contains("missing shard(s) 2/2"), "{err}");
    let err = merge(&[&one, &one, &two]);
    assert!(err.contains("shard 1/2 given twice"), "{err}");
    let err = merge(&[&one, &other]);
    assert!(
        err.contains("different requests") && err.contains("--seed9"),
        "{err}"
    );
    let whole = tmp("whole.json");
    let mut args = vec![
        "bench",
        "--ensemble",
        "3",
        "--methods",
        "taylor-f64",
        "--json",
        s(&whole),
    ];
    args.extend(SMALL);
    assert!(rsts(&args).status.success());
    let err = merge(&[&whole]);
    assert!(err.contains("a whole report, not a shard"), "{err}");
    // A shard altered by hand: refused.
    let altered = d.join("altered.json");
    let text = std::fs::read_to_string(&two).unwrap();
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc["rows"][0]["max_error"] = Value::from(1e-3);
    std::fs::write(&altered, serde_json::to_string(&doc).unwrap()).unwrap();
    let err = merge(&[&one, &altered]);
    assert!(
        err.contains("shard 2/2") && err.contains("altered"),
        "{err}"
    );
    let err = fails(&["bench", "merge", s(&one), s(&two), "--json", s(&two)]);
    assert!(
        err.contains("--json") && err.contains("would destroy the input"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(&two).unwrap(),
        text,
        "the input is untouched"
    );
    let mut expected = [before, vec!["altered.json".to_string()]].concat();
    expected.sort();
    assert_eq!(entries(&d), expected, "nothing written");
    assert!(!json.exists() && !svg.exists());
    for bad in ["0/2", "3/2", "2", "x/2"] {
        let mut args = vec!["bench", "--ensemble", "3", "--shard", bad];
        args.extend(SMALL);
        let err = fails(&args);
        assert!(err.contains(&format!("--shard: '{bad}'")), "{err}");
    }
    assert!(fails(&["bench", "--shard", "1/2"]).contains("--ensemble"));
}
