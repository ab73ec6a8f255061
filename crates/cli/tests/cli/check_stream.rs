//! `rsts check` streams its input in chunks of 8192 rows (rsts_external::stream): the report of
//! a trajectory of several chunks, from a CSV file, an npy file or a CSV on standard input, is
//! the report of the whole trajectory checked at once (the library's `rsts_harness::check`, as
//! the Python face calls it); a time that goes back across a chunk's boundary is refused naming
//! its line; a stream that turns high-precision after its first chunk is refused.

use crate::common;
use std::io::Write;
use std::process::{Command, Stdio};

use common::{camera_v_dopri5_csv, exit_2, json_doc, rsts, s, tmp, whole_check};
use rsts_external::stream::CHUNK_ROWS;

/// `rsts check` with `input` on standard input.
fn check_stdin(args: &[&str], input: &[u8]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    // A refused stream may close its end early.
    let _ = stdin.write_all(input);
    drop(stdin);
    child.wait_with_output().unwrap()
}

#[test]
fn a_streamed_check_reports_what_the_whole_trajectory_gives() {
    let n = 2 * CHUNK_ROWS + 1500;
    let csv = camera_v_dopri5_csv("400", n);
    let path = tmp("traj.csv");
    std::fs::write(&path, &csv).unwrap();

    // The whole trajectory at once, through the library.
    let raw =
        rsts_external::parse_trajectory(&csv, rsts_external::FileFormat::Csv, s(&path)).unwrap();
    let whole = whole_check(&raw, s(&path), "traj.csv", 15);
    assert_eq!(whole["samples_compared"], n);
    assert!(whole["max_state_error"].as_f64().unwrap() > 1e-9, "{whole}");
    assert!(whole["normal"]["growth"].is_object(), "{whole}");

    let file = json_doc(&rsts(&["check", s(&path), "--format", "json"]));
    assert_eq!(file, whole, "streamed file vs whole");

    let stdin = json_doc(&check_stdin(
        &["check", "-", "--input-format", "csv", "--format", "json"],
        &csv,
    ));
    let mut expected = whole.clone();
    expected["file"] = "<stdin>".into();
    expected["method"] = "<stdin>".into();
    assert_eq!(stdin, expected, "streamed standard input vs whole");

    // The npy of the same rows (C order): streamed row by row.
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let mut row = vec![raw.times[k].to_f64()];
            row.extend(raw.states[k].iter().map(|x| x.to_f64()));
            row
        })
        .collect();
    let npy = tmp("traj.npy");
    std::fs::write(&npy, rsts_external::npy_bytes(&rows, 10)).unwrap();
    let mut from_npy = json_doc(&rsts(&["check", s(&npy), "--format", "json"]));
    from_npy["file"] = whole["file"].clone();
    from_npy["method"] = whole["method"].clone();
    assert_eq!(from_npy, whole, "streamed npy vs whole");
}

#[test]
fn errors_across_chunk_boundaries_name_their_line() {
    let csv = String::from_utf8(camera_v_dopri5_csv("400", CHUNK_ROWS + 100)).unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    // The first row of the second chunk (line CHUNK_ROWS + 2) goes back in time.
    let first_of_second = CHUNK_ROWS + 1;
    let mut fields: Vec<String> = lines[first_of_second]
        .split(',')
        .map(str::to_string)
        .collect();
    fields[0] = "0.001".into();
    lines[first_of_second] = fields.join(",");
    let bad = tmp("back.csv");
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let out = rsts(&["check", s(&bad), "--format", "json"]);
    let e = exit_2(&out, "time back across chunks");
    assert!(
        e.contains(&format!(
            "line {}: t = 0.001 does not come after",
            CHUNK_ROWS + 2
        )),
        "{e}"
    );
    assert!(out.stdout.is_empty());

    // Standard input: a 30-digit value after a first chunk of f64 data is refused.
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    let k = CHUNK_ROWS + 50;
    let mut fields: Vec<String> = lines[k].split(',').map(str::to_string).collect();
    // The same value written with 29 significant digits.
    let x: f64 = fields[4].parse().unwrap();
    fields[4] = format!("{x:.28e}");
    lines[k] = fields.join(",");
    let text = lines.join("\n");
    let out = check_stdin(&["check", "-", "--input-format", "csv"], text.as_bytes());
    let e = exit_2(&out, "long value after the first chunk");
    assert!(
        e.contains(&format!("line {}: a value of more than 17 digits", k + 1)),
        "{e}"
    );
    assert!(out.stdout.is_empty());
    // The same rows as a file are read twice: high-precision data, checked.
    let long = tmp("long.csv");
    std::fs::write(&long, &text).unwrap();
    let v = json_doc(&rsts(&["check", s(&long), "--format", "json"]));
    assert!(v["digits"].as_u64().unwrap() > 17, "{v}");
}
