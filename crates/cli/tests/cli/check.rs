//! `rsts check` and `rsts reference` as a user with a trajectory from elsewhere runs them: the
//! same errors as `rsts compare` for the same run (CSV, JSON, npy, MCAP), a perturbation found,
//! the motion identified in every camera, high-precision data read exactly, `--max-error`, and
//! every bad file named with its row and column.

use std::path::Path;

use serde_json::Value;

use crate::common;
use common::{exit_2, fails, json_of, ok, rsts, stderr, stdout, tmp, write};

/// The start state of a motion (the first row of `rsts reference`), as --omega/--alpha/--beta.
fn start(motion: &[&str], t: &str) -> [String; 3] {
    let mut args = vec!["reference", "--times", t];
    args.extend_from_slice(motion);
    let text = stdout(&ok(&args));
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    [
        row[1..4].join(","),
        row[4..7].join(","),
        row[7..10].join(","),
    ]
}

/// `rsts integrate` from the motion's start: (CSV text, JSON text).
fn integrate(motion: &[&str], extra: &[&str]) -> (String, String) {
    let [w, a, b] = start(motion, "0");
    let mut args = vec!["integrate", "--omega", &w, "--alpha", &a, "--beta", &b];
    if !extra.contains(&"--t-end") {
        args.extend_from_slice(&["--t-end", "20", "--samples", "101"]);
    }
    args.extend_from_slice(extra);
    let mut csv = args.clone();
    csv.extend_from_slice(&["--format", "csv"]);
    let mut json = args;
    json.extend_from_slice(&["--format", "json"]);
    (stdout(&ok(&csv)), stdout(&ok(&json)))
}

/// integrate's JSON as an npy array (N, 10) written by rsts-external's npy writer.
fn npy_of(json: &str) -> Vec<u8> {
    let doc: Value = serde_json::from_str(json).unwrap();
    let rows: Vec<Vec<f64>> = doc["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let mut r = vec![s["t"].as_f64().unwrap()];
            for k in ["omega", "alpha", "beta"] {
                r.extend(s[k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()));
            }
            r
        })
        .collect();
    rsts_external::npy_bytes(&rows, 10)
}

fn close(a: &Value, b: &Value, what: &str) {
    let (x, y) = (a.as_f64().unwrap(), b.as_f64().unwrap());
    assert!(
        (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
        "{what}: {x:e} vs {y:e}"
    );
}

fn same_errors(check: &Value, compare: &Value) {
    for key in [
        "max_state_error",
        "final_state_error",
        "max_orientation_error",
    ] {
        close(&check[key], &compare[key], key);
    }
    for key in ["H", "K", "G", "constraints", "off_N"] {
        close(&check["drift"][key], &compare["drift"][key], key);
    }
    assert_eq!(check["samples_compared"], compare["samples_compared"]);
    assert_eq!(check["camera"], compare["camera"]);
    // The same geometry of the error (docs/stability.md).
    assert_eq!(check["normal"]["type"], compare["normal"]["type"]);
    assert_eq!(
        check["error_split"]["dominant"],
        compare["error_split"]["dominant"]
    );
    for (what, x, y) in [
        (
            "distance_from_N",
            &check["normal"]["distance_from_N"]["max"],
            &compare["normal"]["distance_from_N"]["max"],
        ),
        (
            "psi1",
            &check["phase_error"]["psi1"]["max"],
            &compare["phase_error"]["psi1"]["max"],
        ),
    ] {
        let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
        assert!(
            (x - y).abs() <= 1e-6 * x.abs().max(y.abs()) + 1e-15,
            "{what}: {x:e} vs {y:e}"
        );
    }
}

const V: [&str; 8] = [
    "--m", "-0.7092", "--h", "1.5643", "--torus", "2", "--phase1", "0.4",
];

/// The same run: `rsts integrate` from the closed-form start, written as CSV, JSON and npy, read
/// by check, and `rsts compare --pieces 1` (one uninterrupted run, as integrate does).
#[test]
fn check_reports_the_errors_compare_reports_for_the_same_run() {
    let motion = V;
    let (csv, json) = integrate(
        &motion,
        &["--method", "dopri5", "--rtol", "1e-9", "--atol", "1e-9"],
    );
    let mut args = vec![
        "compare",
        "--pieces",
        "1",
        "--t-end",
        "20",
        "--samples",
        "101",
        "--method",
        "dopri5",
        "--rtol",
        "1e-9",
        "--atol",
        "1e-9",
    ];
    args.extend_from_slice(&motion);
    let compare = json_of(&args);
    assert!(compare["max_state_error"].as_f64().unwrap() > 1e-9);
    let files = [
        write("run.csv", csv.as_bytes()),
        write("run.json", json.as_bytes()),
        write("run.npy", &npy_of(&json)),
    ];
    for file in &files {
        let mut args = vec!["check", file.as_str()];
        args.extend_from_slice(&motion);
        let check = json_of(&args);
        same_errors(&check, &compare);
        assert_eq!(check["case"]["identified"], false);
        assert!(check["start_state_error"].as_f64().unwrap() < 1e-15);
        assert!(check["rtol"].is_null());
        // The cost is what the file states: integrate's JSON carries the run's `stats` (the
        // steps and evaluations of compare's same run); a CSV or npy states none (null, not 0).
        for key in [
            "steps",
            "rejected_steps",
            "rhs_evals",
            "integration_seconds",
        ] {
            if file.ends_with(".json") {
                assert!(
                    check[key].as_f64().is_some(),
                    "{file} {key}: {}",
                    check[key]
                );
            } else {
                assert!(check[key].is_null(), "{file} {key}: {}", check[key]);
            }
        }
        if file.ends_with(".json") {
            assert_eq!(check["steps"], compare["steps"], "{file}");
            assert_eq!(check["rhs_evals"], compare["rhs_evals"], "{file}");
        }
    }
    // The table says n/a where the JSON says null.
    let table = stdout(&ok(&["check", files[0].as_str()]));
    for line in [
        "steps (rejected):         n/a (n/a)",
        "rhs evaluations:          n/a",
        "integration time:         n/a",
    ] {
        assert!(table.lines().any(|l| l == line), "{line:?} in\n{table}");
    }
    let table = stdout(&ok(&["check", files[1].as_str()]));
    let steps = compare["steps"].as_u64().unwrap();
    assert!(
        table.contains(&format!("steps (rejected):         {steps} (0)")),
        "{table}"
    );
    // A stats block that is not one is refused, naming the key.
    let bad = json.replacen("\"rhs_evals\": ", "\"rhs_evals\": -", 1);
    assert_ne!(bad, json);
    let err = fails(&["check", &write("bad_stats.json", bad.as_bytes())]);
    assert!(
        err.contains("stats.rhs_evals must be a non-negative number"),
        "{err}"
    );
    // The MCAP log of check holds the trajectory: checking the log gives the same errors again.
    let mcap = tmp("check.mcap");
    let mut args = vec!["check", files[0].as_str(), "--mcap", mcap.to_str().unwrap()];
    args.extend_from_slice(&motion);
    ok(&args);
    let mut args = vec!["check", mcap.to_str().unwrap()];
    args.extend_from_slice(&motion);
    same_errors(&json_of(&args), &compare);
}

/// One value changed by 1e-6 is found: the max state error is that perturbation, at its time.
#[test]
fn a_perturbed_trajectory_reports_its_perturbation() {
    let (csv, _) = integrate(&[], &["--rtol", "1e-13", "--atol", "1e-13"]);
    let mut lines: Vec<String> = csv.lines().map(String::from).collect();
    let mut fields: Vec<String> = lines[51].split(',').map(String::from).collect();
    let x: f64 = fields[5].parse().unwrap();
    fields[5] = format!("{:?}", x + 1e-6);
    lines[51] = fields.join(",");
    let clean = json_of(&["check", &write("clean.csv", csv.as_bytes())]);
    let perturbed = json_of(&[
        "check",
        &write("perturbed.csv", lines.join("\n").as_bytes()),
    ]);
    let e = perturbed["max_state_error"].as_f64().unwrap();
    assert!(clean["max_state_error"].as_f64().unwrap() < 1e-10);
    assert!(
        (e - 1e-6).abs() < 1e-9,
        "perturbation of 1e-6 reported as {e:e}"
    );
    close(
        &perturbed["final_state_error"],
        &clean["final_state_error"],
        "final",
    );
    assert!(perturbed["drift"]["constraints"].as_f64().unwrap() > 1e-7);
}

/// Without --m/--h the motion is identified from the first row in every camera: m and h to
/// 1e-10, and the same report as with the motion given. A trajectory starting at t = 5 is
/// placed on the torus at its own time.
#[test]
fn the_motion_is_identified_in_every_camera() {
    for (camera, m, h) in rsts_closed_form::EXAMPLE_POINTS_A1_B05 {
        let (m, h) = (format!("{m}"), format!("{h}"));
        let motion = ["--m", &m, "--h", &h, "--phase1", "0.4", "--phase2", "1.3"];
        let (csv, _) = integrate(&motion, &["--t-end", "5", "--samples", "51"]);
        let file = write(&format!("cam-{}.csv", camera.label()), csv.as_bytes());
        let found = json_of(&["check", &file]);
        let mut args = vec!["check", file.as_str()];
        args.extend_from_slice(&motion);
        let given = json_of(&args);
        let label = camera.label();
        assert_eq!(found["case"]["identified"], true, "{label}");
        assert_eq!(found["camera"], label);
        for (key, want) in [("m", &m), ("h", &h)] {
            let got = found["case"][key].as_f64().unwrap();
            let want: f64 = want.parse().unwrap();
            assert!((got - want).abs() < 1e-10, "{label}: {key} {got} vs {want}");
        }
        for key in ["max_state_error", "final_state_error"] {
            let (x, y) = (found[key].as_f64().unwrap(), given[key].as_f64().unwrap());
            assert!(
                (x - y).abs() <= 1e-6 * y + 1e-15,
                "{label} {key}: {x:e} vs {y:e}"
            );
        }
        assert!(found["start_distance_from_n"].as_f64().unwrap() < 1e-12);
    }
    // Shift the times of a trajectory by 5: the phases at t = 0 move back by ν·5.
    let (csv, _) = integrate(&V, &["--t-end", "5", "--samples", "51"]);
    let shifted: Vec<String> = csv
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                return l.to_string();
            }
            let (t, rest) = l.split_once(',').unwrap();
            format!("{:?},{rest}", t.parse::<f64>().unwrap() + 5.0)
        })
        .collect();
    let file = write("shifted.csv", shifted.join("\n").as_bytes());
    let found = json_of(&["check", &file]);
    assert!(found["max_state_error"].as_f64().unwrap() < 1e-9, "{found}");
    assert_eq!(found["case"]["torus"], 2);
}

/// A first row off N is refused with its distance; --m/--h still check it.
#[test]
fn a_first_row_off_n_is_an_error_with_its_distance() {
    let (csv, _) = integrate(&[], &[]);
    let mut lines: Vec<String> = csv.lines().map(String::from).collect();
    lines[1] = "0,0.3,-0.2,0.5,1,0,0,0,1,0,0,0,0".into();
    let file = write("off-n.csv", lines.join("\n").as_bytes());
    let err = exit_2(&rsts(&["check", &file]), "off N");
    assert!(
        err.contains("first row") && err.contains("distance from N"),
        "{err}"
    );
    assert!(err.contains("--m"), "says how to check anyway: {err}");
    assert!(
        err.contains("a and b default to 1 and 0.5") && err.contains("--a A --b B"),
        "says a, b are the defaults and how to give them: {err}"
    );
}

/// Data of one motion checked against another (same m, h; phases 0.4, 1.1 against 0, 0): the
/// start offset is said first on stderr with the motion the first row identifies, the report is
/// written, and the run exits 1 unless --allow-start-offset. (Before issue 33: exit 0, nothing
/// on stderr, only "start state error" in the report.)
#[test]
fn a_start_offset_is_said_and_exits_1() {
    let out = ok(&[
        "reference",
        "--t-end",
        "3",
        "--samples",
        "7",
        "--phase1",
        "0.4",
        "--phase2",
        "1.1",
    ]);
    let file = write("offset.csv", &out.stdout);
    let out = rsts(&[
        "check", &file, "--m", "0.3", "--h", "-0.375", "--format", "json",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.starts_with("warning:")
            && err.contains("not a sample of that motion")
            && err.contains("camera I+")
            && err.contains("phases 0.4000")
            && err.contains("--allow-start-offset"),
        "{err}"
    );
    let r: Value = serde_json::from_slice(&out.stdout).expect("the report, whole");
    assert!(r["start_offset"]["error"].as_f64().unwrap() > 1e-3, "{r}");
    assert_eq!(r["start_offset"]["identified"]["torus"], 0, "{r}");
    let r = json_of(&[
        "check",
        &file,
        "--m",
        "0.3",
        "--h",
        "-0.375",
        "--allow-start-offset",
    ]);
    assert!(r["start_offset"].is_object(), "{r}");
    let r = json_of(&[
        "check", &file, "--m", "0.3", "--h", "-0.375", "--phase1", "0.4", "--phase2", "1.1",
    ]);
    assert!(r.get("start_offset").is_none(), "{r}");
}

/// High-precision data (40 digits) are read exactly: the closed form's own samples have no
/// error beyond 1e-35 (read as f64 they would be off by 1e-17).
#[test]
fn long_decimals_are_read_exactly() {
    let out = ok(&[
        "reference",
        "--t-end",
        "3",
        "--samples",
        "7",
        "--digits",
        "40",
    ]);
    let file = write("exact.csv", &out.stdout);
    let r = json_of(&["check", &file, "--m", "0.3", "--h", "-0.375"]);
    assert!(r["max_state_error"].as_f64().unwrap() < 1e-35, "{r}");
    assert_eq!(r["digits"], 40);
    let out = ok(&["reference", "--t-end", "3", "--samples", "7"]);
    let file = write("f64.csv", &out.stdout);
    let r = json_of(&["check", &file, "--m", "0.3", "--h", "-0.375"]);
    let e = r["max_state_error"].as_f64().unwrap();
    assert!(e > 1e-19 && e < 3e-16, "f64 rounding only: {e:e}");
}

#[test]
fn max_error_exits_1_naming_the_figure() {
    let (csv, _) = integrate(
        &[],
        &["--method", "dopri5", "--rtol", "1e-6", "--atol", "1e-6"],
    );
    let file = write("loose.csv", csv.as_bytes());
    ok(&["check", &file, "--max-error", "1e-2"]);
    let out = rsts(&["check", &file, "--max-error", "1e-9"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains("max state error") && err.contains("--max-error 1e-9"),
        "{err}"
    );
    assert!(
        stdout(&out).contains("max state error"),
        "the report is still printed"
    );
}

/// Every kind of bad file: exit 2, a message naming the file and where.
#[test]
fn bad_files_are_named_with_row_and_column() {
    let header = "t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3";
    let good = "0,-0.17131207221604822,0,1.2580177644422093,0.6956521739130435,0,-0.7183787670373176,0,1,0";
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "missing.csv",
            b"t,omega1,omega2\n0,1,2\n".to_vec(),
            "lacks column(s) omega3",
        ),
        (
            "nan.csv",
            format!("{header}\n{good}\n1,NaN,0,0,1,0,0,0,1,0\n").into_bytes(),
            "line 3, column 2 (omega1)",
        ),
        (
            "back.csv",
            format!("{header}\n{good}\n{good}\n").into_bytes(),
            "line 3: t = 0",
        ),
        (
            "short.csv",
            format!("{header}\n{good}\n1,0,0\n").into_bytes(),
            "line 3: 3 fields",
        ),
        ("empty.csv", Vec::new(), "empty"),
        (
            "header-only.csv",
            format!("{header}\n").into_bytes(),
            "no samples",
        ),
        (
            "bad.json",
            b"{\"samples\": [{\"t\": 0}]}".to_vec(),
            "samples[0]: \"omega\"",
        ),
        ("broken.json", b"{\"samples\": [".to_vec(), "not valid JSON"),
        (
            "shape.npy",
            rsts_external::npy_bytes(&[vec![0.0; 9]], 9),
            "shape [1, 9]",
        ),
        (
            "cut.npy",
            {
                let b = rsts_external::npy_bytes(&[vec![0.0; 10], vec![1.0; 10]], 10);
                b[..b.len() - 12].to_vec()
            },
            "truncated",
        ),
        (
            "noise.npy",
            b"not an npy file at all".to_vec(),
            "not a valid npy",
        ),
        ("data.txt", b"1,2,3".to_vec(), "unknown file type 'txt'"),
    ];
    for (name, bytes, expect) in cases {
        let file = write(name, &bytes);
        let err = exit_2(
            &rsts(&["check", &file, "--m", "0.3", "--h", "-0.375"]),
            name,
        );
        assert!(err.contains(&file), "{name}: names the file: {err}");
        assert!(err.contains(expect), "{name}: expected {expect:?} in {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let err = exit_2(&rsts(&["check", "/nonexistent/t.csv"]), "missing file");
    assert!(err.contains("cannot read"), "{err}");
    // A truncated MCAP log.
    let mcap = tmp("cut.mcap");
    ok(&[
        "compare",
        "--t-end",
        "2",
        "--samples",
        "21",
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    let bytes = std::fs::read(&mcap).unwrap();
    let cut = write("cut-log.mcap", &bytes[..bytes.len() / 2]);
    let err = exit_2(&rsts(&["check", &cut]), "cut mcap");
    assert!(
        err.contains("damaged") && err.contains("rsts inspect"),
        "{err}"
    );
}

#[test]
fn reference_writes_any_times_in_every_format() {
    let times = tmp("times.txt");
    std::fs::write(&times, "# times\n0\n0.5, 2.25\n7\n").unwrap();
    let json = json_of(&["reference", "--times-file", times.to_str().unwrap()]);
    let samples = json["samples"].as_array().unwrap();
    let ts: Vec<f64> = samples.iter().map(|s| s["t"].as_f64().unwrap()).collect();
    assert_eq!(ts, vec![0.0, 0.5, 2.25, 7.0]);
    for s in samples {
        close(&s["H"], &Value::from(-0.375), "H is h on the exact motion");
    }
    let npy = tmp("ref.npy");
    ok(&[
        "reference",
        "--times",
        "0,0.5,2.25,7",
        "--format",
        "npy",
        "-o",
        npy.to_str().unwrap(),
    ]);
    // The npy file is a trajectory check reads back (13 columns: H, K, G dropped is not allowed,
    // so compare with the CSV instead).
    let csv = stdout(&ok(&["reference", "--times", "0,0.5,2.25,7"]));
    let bytes = std::fs::read(&npy).unwrap();
    assert_eq!(&bytes[..6], b"\x93NUMPY");
    let last_csv: f64 = csv
        .lines()
        .nth(4)
        .unwrap()
        .split(',')
        .nth(12)
        .unwrap()
        .parse()
        .unwrap();
    let last_npy = f64::from_le_bytes(bytes[bytes.len() - 8..].try_into().unwrap());
    assert_eq!(last_csv, last_npy, "G of the last row");
    let digits = json_of(&["reference", "--times", "1", "--digits", "50"]);
    let w = digits["samples"][0]["omega"][0]
        .as_str()
        .expect("decimal string");
    assert!(rsts_external::samples::significant_digits(w) >= 49, "{w}");
    for (args, expect) in [
        (vec!["reference"], "give the times"),
        (vec!["reference", "--times", "0,2,1"], "strictly increasing"),
        (
            vec![
                "reference",
                "--times",
                "0",
                "--digits",
                "30",
                "--format",
                "npy",
                "-o",
                "x.npy",
            ],
            "float64",
        ),
        (
            vec!["reference", "--times", "0", "--m", "0", "--h", "2"],
            "Σ",
        ),
        (
            vec!["reference", "--times-file", "/nonexistent"],
            "cannot read",
        ),
    ] {
        let err = exit_2(&rsts(&args), &args);
        assert!(err.contains(expect), "{args:?}: {err}");
    }
    assert!(!Path::new("x.npy").exists());
}

/// An npy file written by numpy itself (`numpy.save`, from the CSV of `rsts integrate`) is read
/// like the CSV. Needs numpy (`common::python_with`); skipped otherwise.
#[test]
fn an_npy_written_by_numpy_is_read_like_the_csv() {
    let Some(python) = common::python_with("numpy", "an_npy_written_by_numpy_is_read_like_the_csv")
    else {
        return;
    };
    let (csv, _) = integrate(&V, &[]);
    let csv_file = write("numpy-src.csv", csv.as_bytes());
    let npy = tmp("numpy.npy");
    let status = std::process::Command::new(&python)
        .args([
            "-c",
            "import numpy, sys; x = numpy.loadtxt(sys.argv[1], delimiter=',', skiprows=1); numpy.save(sys.argv[2], x[:, :10])",
            &csv_file,
            npy.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let mut a = vec!["check", csv_file.as_str()];
    a.extend_from_slice(&V);
    let mut b = vec!["check", npy.to_str().unwrap()];
    b.extend_from_slice(&V);
    same_errors(&json_of(&b), &json_of(&a));
}
