//! `rsts bench --ensemble`: each motion's row is `rsts compare … --pieces 1` of that motion (to
//! the bit), the seed repeats the motions, the bands are drawn, bad input exits 2.

use crate::common;

use common::{fails, rsts, s, stdout, tmp};
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
