//! The output contract of docs/output.md, for every subcommand `rsts --help` lists: each
//! `--format` value its `--help` lists gives that format on stdout (one JSON document, a
//! rectangular CSV with the common column naming, a table) and nothing else; other values are
//! rejected with exit code 2. A subcommand without an entry in `BASE` fails the test, so a new
//! command gets its contract checked when it lands.

use std::path::PathBuf;
use std::sync::OnceLock;

use serde_json::Value;

use crate::common;
use common::{rsts, stderr, stdout, tmp};

/// A complete MCAP log for `inspect`.
fn log() -> &'static PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| {
        let p = tmp("contract.mcap");
        let out = rsts(&[
            "compare",
            "--t-end",
            "2",
            "--samples",
            "5",
            "--mcap",
            p.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        p
    })
}

/// A trajectory of the default motion for `check` (written by `rsts reference`).
fn trajectory() -> &'static PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| {
        let p = tmp("contract-traj.csv");
        let out = rsts(&[
            "reference",
            "--t-end",
            "1",
            "--samples",
            "5",
            "-o",
            p.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        p
    })
}

/// Cheap valid arguments of each subcommand (`None`: it has no `--format`), and the formats
/// that are only valid in another mode of the command.
fn base(command: &str) -> Option<Vec<Vec<String>>> {
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let mcap = log().to_str().unwrap().to_string();
    Some(match command {
        "integrate" => vec![v(&["integrate", "--t-end", "1", "--samples", "3"])],
        "explicit" => vec![
            v(&["explicit", "--t-end", "1", "--samples", "3"]),
            v(&[
                "explicit",
                "--t-end",
                "1",
                "--samples",
                "3",
                "--digits",
                "30",
            ]),
        ],
        "diagram" => vec![v(&["diagram", "--m", "0.3", "--h", "-0.375"])],
        "compare" => vec![
            v(&["compare", "--t-end", "1", "--samples", "3"]),
            v(&[
                "compare",
                "--t-end",
                "5",
                "--samples",
                "51",
                "--event",
                "omega1",
            ]),
        ],
        "events" => vec![
            v(&[
                "events", "--event", "omega1", "--event", "s2", "--t-end", "5",
            ]),
            v(&[
                "events", "--event", "omega1", "--t-end", "5", "--digits", "30",
            ]),
        ],
        "inspect" => vec![
            vec!["inspect".into(), mcap.clone()],
            vec![
                "inspect".into(),
                mcap,
                "--channel".into(),
                "/exact/state".into(),
            ],
        ],
        "bench" => vec![v(&[
            "bench",
            "--t-end",
            "1",
            "--samples",
            "3",
            "--methods",
            "dopri5",
            "--tolerances",
            "1e-6",
            "--repeats",
            "1",
        ])],
        "convergence" => vec![v(&[
            "convergence",
            "--t-end",
            "1",
            "--samples",
            "2",
            "--steps",
            "0.5,0.25,0.125",
        ])],
        "table1" => vec![v(&["table1"])],
        "check" => {
            let traj = trajectory().to_str().unwrap().to_string();
            let log = tmp("contract-check.mcap").to_str().unwrap().to_string();
            vec![
                vec!["check".into(), traj.clone()],
                // A log written beside the report changes nothing on stdout.
                vec!["check".into(), traj, "--mcap".into(), log],
            ]
        }
        "reference" => vec![v(&["reference", "--times", "0,0.5,1"])],
        // A state of camera V to 10 digits (the first example of `rsts identify --help`).
        "identify" => vec![v(&[
            "identify",
            "--a",
            "1",
            "--b",
            "0.5",
            "--omega=-0.7647920880,0.0304544152,-0.0788113714",
            "--alpha=-0.8092123863,0.4893823915,0.3250848946",
            "--beta=0.1716166194,-0.3322951766,0.9274306721",
        ])],
        "table2" => vec![v(&["table2"])],
        "validate" | "surfaces" | "help" => return None,
        other => panic!(
            "subcommand `{other}` has no entry in tests/cli/contract.rs: add its cheap valid \
             arguments so its --format contract is checked"
        ),
    })
}

/// The subcommands `rsts --help` lists.
fn subcommands() -> Vec<String> {
    let text = stdout(&rsts(&["--help"]));
    let mut in_list = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("Commands:") {
            in_list = true;
            continue;
        }
        if in_list {
            if line.trim().is_empty() {
                break;
            }
            out.push(line.split_whitespace().next().unwrap().to_string());
        }
    }
    assert!(out.len() >= 10, "{text}");
    out
}

/// The values `--format` lists in `rsts COMMAND --help` (empty: no `--format`).
fn listed_formats(command: &str) -> Vec<String> {
    let text = stdout(&rsts(&[command, "--help"]));
    let Some(at) = text.find("--format <") else {
        return Vec::new();
    };
    let rest = &text[at..];
    // Short form `[possible values: a, b]`, or the long form of values with docs:
    // `Possible values:` then one `- a: …` line each.
    if let Some(k) = rest.find("[possible values: ") {
        let start = k + "[possible values: ".len();
        let end = start + rest[start..].find(']').unwrap();
        return rest[start..end]
            .split(',')
            .map(|s| s.trim().to_string())
            .collect();
    }
    let k = rest
        .find("Possible values:")
        .expect("--format lists its values");
    rest[k..]
        .lines()
        .skip(1)
        .map(str::trim)
        .take_while(|l| l.starts_with("- "))
        .map(|l| l[2..].split(':').next().unwrap().trim().to_string())
        .collect()
}

/// A `.npy` float64 array of finite values with its shape in the header.
fn check_npy(args: &[String], bytes: &[u8]) {
    assert!(bytes.starts_with(b"\x93NUMPY"), "{args:?}: not npy");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let shape = header.split("'shape': (").nth(1).unwrap();
    let dims: Vec<usize> = shape
        .split(')')
        .next()
        .unwrap()
        .split(',')
        .filter(|d| !d.trim().is_empty())
        .map(|d| d.trim().parse().unwrap())
        .collect();
    let data = &bytes[10 + len..];
    assert_eq!(
        data.len(),
        8 * dims.iter().product::<usize>(),
        "{args:?}: {header}"
    );
    for x in data.chunks(8) {
        let x = f64::from_le_bytes(x.try_into().unwrap());
        assert!(x.is_finite(), "{args:?}: non-finite value {x}");
    }
}

fn check_document(args: &[String], format: &str, out: &std::process::Output) {
    if format == "npy" {
        return check_npy(args, &out.stdout);
    }
    let text = stdout(out);
    assert!(!text.trim().is_empty(), "{args:?}: empty stdout");
    // Whole words only: "dominant" holds "nan" and is no number.
    let lower = text.to_ascii_lowercase();
    let non_finite = lower
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '_'))
        .find(|w| ["nan", "inf", "infinity"].contains(w));
    assert!(
        non_finite.is_none(),
        "{args:?}: non-finite value printed ({non_finite:?})"
    );
    match format {
        "json" => {
            let v: Value = serde_json::from_str(&text)
                .unwrap_or_else(|e| panic!("{args:?}: stdout is not one JSON document: {e}"));
            assert!(v.is_object() || v.is_array(), "{args:?}");
        }
        "csv" => {
            let rows: Vec<&str> = text.lines().collect();
            assert!(rows.len() >= 2, "{args:?}: {text}");
            let width = |l: &str| {
                let mut quoted = false;
                1 + l
                    .chars()
                    .filter(|&c| {
                        if c == '"' {
                            quoted = !quoted;
                        }
                        c == ',' && !quoted
                    })
                    .count()
            };
            for r in &rows {
                assert_eq!(width(r), width(rows[0]), "{args:?}: ragged CSV\n{text}");
            }
            let header = rows[0];
            assert!(
                !header.contains('.') && !header.contains(' ') || header.contains('"'),
                "{args:?}: column names with dots or spaces: {header}"
            );
            for state in ["omega", "alpha", "beta"] {
                if header.split(',').any(|c| c.starts_with(state)) {
                    assert!(
                        header.contains(&format!("{state}1,{state}2,{state}3")),
                        "{args:?}: {header}"
                    );
                }
            }
            if header.contains("omega1") {
                assert!(
                    header.starts_with("t,omega1,omega2,omega3,alpha1"),
                    "{header}"
                );
            }
        }
        _ => {
            assert!(text.lines().count() >= 1);
        }
    }
}

#[test]
fn every_listed_format_of_every_command_works_and_others_are_rejected() {
    for command in subcommands() {
        let formats = listed_formats(&command);
        let Some(bases) = base(&command) else {
            assert!(
                formats.is_empty() || command == "help",
                "{command} lists --format {formats:?}: give it an entry in BASE"
            );
            continue;
        };
        assert!(!formats.is_empty(), "{command}: no --format listed");
        for format in &formats {
            // At least one mode of the command takes each listed format; the others refuse
            // it with exit code 2 and a message naming --format.
            let mut worked = false;
            for b in &bases {
                let mut args = b.clone();
                args.extend(["--format".to_string(), format.clone()]);
                let argv: Vec<&str> = args.iter().map(String::as_str).collect();
                let out = rsts(&argv);
                match out.status.code() {
                    Some(0) => {
                        check_document(&args, format, &out);
                        worked = true;
                    }
                    Some(2) => {
                        let err = stderr(&out);
                        assert!(err.contains("--format"), "{args:?}: {err}");
                        assert!(stdout(&out).is_empty(), "{args:?}");
                    }
                    other => panic!("{args:?}: exit {other:?}: {}", stderr(&out)),
                }
            }
            assert!(
                worked,
                "{command} lists --format {format} but no mode takes it"
            );
        }
        for bad in ["xml", "yaml", "text"] {
            let mut args = bases[0].clone();
            args.extend(["--format".to_string(), bad.to_string()]);
            let argv: Vec<&str> = args.iter().map(String::as_str).collect();
            let out = rsts(&argv);
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            assert!(stderr(&out).contains("--format"), "{args:?}");
        }
    }
}

/// `rsts reference -o FILE` writes exactly what it prints, in every format it lists.
#[test]
fn reference_files_hold_what_stdout_holds() {
    let formats = listed_formats("reference");
    assert!(formats.len() >= 3, "{formats:?}");
    for format in formats {
        let args = [
            "reference",
            "--times",
            "0,0.25,3",
            "--format",
            format.as_str(),
        ];
        let printed = rsts(&args);
        assert!(printed.status.success(), "{}", stderr(&printed));
        let file = tmp(&format!("ref.{format}"));
        let mut with_file = args.to_vec();
        with_file.extend(["-o", file.to_str().unwrap()]);
        let wrote = rsts(&with_file);
        assert!(wrote.status.success(), "{}", stderr(&wrote));
        assert!(wrote.stdout.is_empty(), "{format}: stdout with -o");
        assert_eq!(std::fs::read(&file).unwrap(), printed.stdout, "{format}");
    }
}

#[test]
fn notes_go_to_stderr_and_files_appear_whole() {
    let d = tmp("contract-files");
    let _ = std::fs::remove_dir_all(&d);
    let svg = d.join("d.svg");
    let out = rsts(&["diagram", "--svg", svg.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).is_empty(),
        "a note on stdout: {}",
        stdout(&out)
    );
    assert!(stderr(&out).contains("wrote"));
    assert!(std::fs::read_to_string(&svg)
        .unwrap()
        .trim_end()
        .ends_with("</svg>"));
    let mcap = d.join("c.mcap");
    let out = rsts(&[
        "compare",
        "--t-end",
        "1",
        "--samples",
        "3",
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(!stdout(&out).contains("MCAP log"), "{}", stdout(&out));
    assert!(stderr(&out).contains("MCAP log"));
}
