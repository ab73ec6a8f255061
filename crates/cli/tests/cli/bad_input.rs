//! Property: for every subcommand, any bad value of any option — drawn from the option's known
//! bad values (out of range, non-finite, malformed, unwritable places) or generated at random
//! (garbage where a number is expected) — ends with exit code 2, a one-line `error:` that names
//! the option, nothing on stdout, no panic, and no file left behind.
//!
//! Each subcommand is a proptest with a modest number of cases (the whole file runs in well under
//! a minute); a failure prints the minimal (option, value) that broke the property.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use proptest::prelude::*;
use proptest::test_runner::Config;

use crate::common;
use common::{rsts, stderr, stdout, tmp};

/// Cases per subcommand.
const CASES: u32 = 40;

/// An option, the names a message about it may use, and its known bad values.
struct Opt {
    name: &'static str,
    /// Accepted spellings in the message (e.g. `--rtol/--atol` names both).
    named_as: &'static [&'static str],
    bad: &'static [&'static str],
    /// Random garbage is also bad (the option takes a number or a list of numbers).
    numeric: bool,
}

const fn num(name: &'static str, bad: &'static [&'static str]) -> Opt {
    Opt {
        name,
        named_as: &[],
        bad,
        numeric: true,
    }
}

const fn word(name: &'static str, bad: &'static [&'static str]) -> Opt {
    Opt {
        name,
        named_as: &[],
        bad,
        numeric: false,
    }
}

const NUMBER: &[&str] = &[
    "nan", "NaN", "inf", "-inf", "1e999", "x", "", "1,2", "0x10", "--",
];
const COUNT: &[&str] = &["-1", "1.5", "x", "", "99999999999999999999999"];

const A: Opt = num(
    "--a",
    &[
        "0", "-1", "nan", "inf", "1e300", "1e-300", "0.1", "0.5", "x",
    ],
);
const B: Opt = num("--b", &["0", "-0.5", "2", "1", "1e-300", "nan", "x"]);
const M: Opt = num("--m", &["1e300", "-1e300", "5", "1e7", "nan", "x"]);
const H: Opt = num("--h", &["1e300", "-100", "-1e300", "2.225", "nan", "x"]);
const TORUS: Opt = word("--torus", &["99", "-1", "x", "1.5"]);
const PHASE1: Opt = num("--phase1", &["nan", "inf", "x"]);
const PHASE2: Opt = num("--phase2", &["-inf", "1e999", "x"]);
const T_END: Opt = num("--t-end", &["-1", "nan", "inf", "1e12", "x"]);
const SAMPLES: Opt = num("--samples", &["0", "-1", "1.5", "x", "100000000"]);
const METHOD: Opt = word("--method", &["euler", "", "rk5", "dop"]);
const RTOL: Opt = num("--rtol", &["0", "-1e-12", "2", "1e-30", "nan", "1e300"]);
const ATOL: Opt = num("--atol", &["0", "-1", "2", "nan", "1e300"]);
const STEP: Opt = num("--step", &["0", "-1", "nan", "x"]);
const FORMAT: Opt = word("--format", &["xml", "", "yaml", "CSV2"]);

fn compare_opts() -> Vec<Opt> {
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        PHASE1,
        PHASE2,
        T_END,
        SAMPLES,
        METHOD,
        RTOL,
        ATOL,
        STEP,
        num("--digits", &["5", "10001", "-1", "x"]),
        word(
            "--mcap",
            &["/proc/rsts/c.mcap", "/dev/null/c.mcap", "/proc"],
        ),
        FORMAT,
    ]
}

/// A place for the files of this test (each test runs on its own thread and has its own
/// directory, so one test's temporaries are never taken for another's leftovers).
fn scratch() -> PathBuf {
    thread_local! {
        static DIR: PathBuf = {
            let name = std::thread::current().name().unwrap_or("main").replace("::", "-");
            let d = tmp(&format!("scratch-{name}"));
            std::fs::create_dir_all(&d).unwrap();
            d
        };
    }
    DIR.with(|d| d.clone())
}

/// A complete MCAP log and a tiny valid suite, made once.
fn fixtures() -> &'static (String, String, String) {
    static F: OnceLock<(String, String, String)> = OnceLock::new();
    F.get_or_init(|| {
        let d = tmp("fixtures");
        std::fs::create_dir_all(&d).unwrap();
        let mcap = d.join("ok.mcap");
        let out = rsts(&[
            "compare",
            "--t-end",
            "1",
            "--samples",
            "3",
            "--mcap",
            mcap.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let suite = d.join("tiny.toml");
        std::fs::write(
            &suite,
            "name = \"tiny\"\n[defaults]\nt_end = 1\nsamples = 3\n[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\n",
        )
        .unwrap();
        let text = d.join("not-mcap.txt");
        std::fs::write(&text, "hello").unwrap();
        (
            mcap.to_str().unwrap().to_string(),
            suite.to_str().unwrap().to_string(),
            text.to_str().unwrap().to_string(),
        )
    })
}

fn garbage() -> impl Strategy<Value = String> {
    "[a-zA-Z_%#]{1,6}|[0-9]{1,3}[a-z]{1,3}|[.,+-]{1,3}"
}

/// (option index, bad value) for `opts`.
fn bad_choice(opts: &'static [Opt]) -> impl Strategy<Value = (usize, String)> {
    (0..opts.len()).prop_flat_map(move |i| {
        let listed = proptest::sample::select(opts[i].bad).prop_map(String::from);
        let value = if opts[i].numeric {
            prop_oneof![3 => listed, 1 => garbage()].boxed()
        } else {
            listed.boxed()
        };
        (Just(i), value)
    })
}

/// Run `base` with `opt value` (replacing the option if `base` has it) and check the property.
fn check(base: &[&str], opt: &Opt, value: &str) -> Result<(), TestCaseError> {
    let mut args: Vec<String> = base.iter().map(|s| s.to_string()).collect();
    if let Some(k) = args.iter().position(|a| a == opt.name) {
        args.remove(k);
        args.remove(k);
    } else if let Some(k) = args
        .iter()
        .position(|a| a.starts_with(&format!("{}=", opt.name)))
    {
        args.remove(k);
    }
    args.push(format!("{}={value}", opt.name));
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = rsts(&argv);
    let err = stderr(&out);
    prop_assert!(!err.contains("panicked"), "{argv:?} panicked: {err}");
    prop_assert_eq!(out.status.code(), Some(2), "{:?}: {}", argv, err);
    prop_assert!(
        stdout(&out).is_empty(),
        "{argv:?} printed a document: {}",
        stdout(&out)
    );
    let names: Vec<&str> = std::iter::once(opt.name)
        .chain(opt.named_as.iter().copied())
        .collect();
    prop_assert!(
        names.iter().any(|n| err.contains(n)),
        "{argv:?}: the message does not name {}: {err}",
        opt.name
    );
    // Nothing written: no temporaries, no partial files.
    for e in std::fs::read_dir(scratch()).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        prop_assert!(false, "{argv:?} left {name} behind");
    }
    Ok(())
}

macro_rules! bad_input_property {
    ($test:ident, $opts:expr, $base:expr) => {
        proptest! {
            #![proptest_config(Config { cases: CASES, failure_persistence: None, ..Config::default() })]
            #[test]
            fn $test((i, value) in bad_choice({
                static OPTS: OnceLock<Vec<Opt>> = OnceLock::new();
                OPTS.get_or_init(|| $opts).as_slice()
            })) {
                static OPTS: OnceLock<Vec<Opt>> = OnceLock::new();
                let opts = OPTS.get_or_init(|| $opts);
                let base: Vec<String> = $base;
                let base: Vec<&str> = base.iter().map(String::as_str).collect();
                check(&base, &opts[i], &value)?;
            }
        }
    };
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

bad_input_property!(
    integrate_rejects_bad_input,
    vec![
        num("--a", &["0", "-1", "nan", "inf", "0.1", "x", "1e999"]),
        num("--b", &["-0.5", "2", "nan", "x"]),
        num(
            "--omega",
            &["1,2", "1,2,3,4", "nan,0,0", "x,y,z", "", "1,,3"]
        ),
        num("--alpha", &["2,0,0", "0,0,0", "1,0", "nan,0,0"]),
        num("--beta", &["1,0,0", "0,2,0", "0,1"]),
        T_END,
        SAMPLES,
        METHOD,
        RTOL,
        ATOL,
        STEP,
        FORMAT,
    ],
    strings(&["integrate", "--t-end", "1", "--samples", "3"])
);

bad_input_property!(
    explicit_rejects_bad_input,
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        PHASE1,
        PHASE2,
        num("--t-end", &["-1", "nan", "x", "1e400"]),
        SAMPLES,
        num("--digits", &["5", "100001", "-1", "x"]),
        FORMAT,
    ],
    strings(&["explicit", "--samples", "3", "--t-end", "1"])
);

bad_input_property!(
    diagram_point_rejects_bad_input,
    vec![A, B, M, H, FORMAT],
    strings(&["diagram", "--m", "0.3", "--h", "-0.375"])
);

bad_input_property!(
    diagram_picture_rejects_bad_input,
    vec![
        A,
        B,
        word("--svg", &["/proc/rsts/d.svg", "/dev/null/d.svg", "/proc"]),
        num("--m-range", &["2,1", "1", "nan,1", "1,1"]),
        num("--h-range", &["0,0", "x,1", "1,2,3"]),
        word("--format", &["json", "csv"]),
    ],
    {
        let svg = scratch().join("d.svg");
        vec![
            "diagram".into(),
            "--svg".into(),
            svg.to_str().unwrap().into(),
        ]
    }
);

bad_input_property!(
    compare_rejects_bad_input,
    compare_opts(),
    strings(&["compare", "--samples", "3", "--t-end", "1"])
);

bad_input_property!(
    bench_rejects_bad_input,
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        num("--t-end", &["0", "-1", "nan", "1e12"]),
        num("--samples", &["1", "0", "x", "2000000"]),
        word("--methods", &["euler", "", "dopri5,euler"]),
        num("--tolerances", &["0", "-1", "2", "nan", ""]),
        num("--repeats", &["0", "1001", "x", "-3"]),
        num("--digits", &["5", "10001"]),
        word("--svg", &["/proc/rsts/b.svg", "/dev/null/b.svg"]),
        Opt {
            name: "--exec",
            named_as: &["external integrator"],
            bad: &[
                "/bin/false",
                "",
                "'x",
                "/nonexistent/prog",
                "cat",
                "/proc/self/status"
            ],
            numeric: false,
        },
        num("--exec-timeout", NUMBER),
        FORMAT,
    ],
    strings(&[
        "bench",
        "--samples",
        "3",
        "--t-end",
        "1",
        "--repeats",
        "1",
        "--methods",
        "dopri5",
        "--tolerances",
        "1e-6",
    ])
    .into_iter()
    .chain(["--svg".to_string(), s(&scratch().join("b.svg"))])
    .collect()
);

// `rsts convergence`: the case, the grid, the methods and order, the sweep, the diagram and
// the adapters; the SVG is not left behind.
bad_input_property!(
    convergence_rejects_bad_input,
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        PHASE1,
        PHASE2,
        T_END,
        num("--samples", &["0", "1", "x", "200000"]),
        word("--methods", &["euler", "", "rk4,euler", "taylor-f64"]),
        num("--order", &["0", "-1", "x"]),
        num("--digits", &["5", "10001", "x"]),
        num("--step", &["0", "-1", "nan", "x", "5"]),
        num("--halvings", &["1", "41", "x", "-1"]),
        num("--exec-tolerance", &["0", "-1", "2", "nan"]),
        word("--svg", &["/proc/rsts/c.svg", "/dev/null/c.svg"]),
        Opt {
            name: "--exec",
            named_as: &["external integrator"],
            bad: &["/bin/false", "", "'x", "/nonexistent/prog", "cat"],
            numeric: false,
        },
        FORMAT,
    ],
    strings(&[
        "convergence",
        "--samples",
        "2",
        "--t-end",
        "1",
        "--step",
        "0.5",
        "--halvings",
        "2",
    ])
    .into_iter()
    .chain(["--svg".to_string(), s(&scratch().join("c.svg"))])
    .collect()
);

// `rsts compare --exec`: a program that cannot start, fails, answers garbage or takes a bad
// timeout; the MCAP log it was to write is not left behind.
bad_input_property!(
    compare_exec_rejects_bad_input,
    vec![
        Opt {
            name: "--exec",
            named_as: &["external integrator"],
            bad: &[
                "/bin/false",
                "",
                "'x",
                "/nonexistent/prog",
                "cat",
                "no-such-program-rsts"
            ],
            numeric: false,
        },
        num("--exec-timeout", &["0", "-1", "nan", "inf", "1e300", "x"]),
        num("--digits", &["5", "10001", "x"]),
    ],
    strings(&[
        "compare",
        "--samples",
        "3",
        "--t-end",
        "1",
        "--exec",
        "cat",
        "--mcap"
    ])
    .into_iter()
    .chain([s(&scratch().join("e.mcap"))])
    .collect()
);

// `rsts identify`: malformed fields, vectors, digits, tolerance and format.
bad_input_property!(
    identify_rejects_bad_input,
    vec![
        A,
        B,
        num(
            "--omega",
            &["1,2", "1,2,3,4", "nan,0,0", "x,y,z", "", "1,,3"]
        ),
        num("--alpha", &["1,0", "inf,0,0", "a,b,c"]),
        num("--beta", &["0,1", "0,1,0,0", "0,nan,0"]),
        num("--digits", &["-1", "x", "1.5"]),
        num("--tolerance", &["nan", "-1", "x"]),
        FORMAT,
    ],
    strings(&[
        "identify",
        "--a",
        "1",
        "--b",
        "0.5",
        "--omega=-0.7647920880,0.0304544152,-0.0788113714",
        "--alpha=-0.8092123863,0.4893823915,0.3250848946",
        "--beta=0.1716166194,-0.3322951766,0.9274306721",
    ])
);

const REFERENCE_TIMES: Opt = num(
    "--times",
    &["1,0", "0,0", "nan", "x", "", "0,1e999", "0,,1"],
);

fn reference_opts() -> Vec<Opt> {
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        PHASE1,
        PHASE2,
        REFERENCE_TIMES,
        num("--digits", &["5", "17", "10001", "x", "-1"]),
        word("--format", &["xml", "", "table", "CSV2"]),
        Opt {
            name: "--output",
            named_as: &["-o"],
            bad: &["/proc/rsts/r.csv", "/dev/null/r.csv", "/proc"],
            numeric: false,
        },
    ]
}

bad_input_property!(
    reference_rejects_bad_input,
    reference_opts(),
    strings(&["reference", "--times", "0,0.5,1", "--output"])
        .into_iter()
        .chain([s(&scratch().join("r.csv"))])
        .collect()
);

bad_input_property!(
    reference_grid_rejects_bad_input,
    vec![
        num("--t-end", &["-1", "nan", "inf", "x"]),
        num("--samples", COUNT),
        num("--samples", &["0", "100000000"]),
        // 10 million times at 10000 digits: more than an output file may hold.
        num("--digits", &["10000"]),
        word("--times-file", &["/nonexistent/times.txt"]),
    ],
    strings(&[
        "reference",
        "--t-end",
        "1",
        "--samples",
        "10000000",
        "--output"
    ])
    .into_iter()
    .chain([s(&scratch().join("g.json"))])
    .collect()
);

bad_input_property!(
    reference_times_file_rejects_bad_input,
    vec![word(
        "--times-file",
        &[
            "/nonexistent/times.txt",
            "/proc",
            "/proc/self/status",
            "/dev/null"
        ]
    )],
    {
        let (_, times) = trajectories();
        vec![
            "reference".into(),
            "--times-file".into(),
            times.clone(),
            "--output".into(),
            s(&scratch().join("f.csv")),
        ]
    }
);

// `rsts check FILE` with the motion given: every option, and the MCAP log it was to write.
bad_input_property!(
    check_rejects_bad_input,
    vec![
        A,
        B,
        M,
        H,
        TORUS,
        PHASE1,
        PHASE2,
        num("--digits", &["0", "10001", "x", "-1"]),
        num("--max-error", &["-1", "nan", "inf", "x"]),
        word(
            "--mcap",
            &["/proc/rsts/c.mcap", "/dev/null/c.mcap", "/proc"]
        ),
        FORMAT,
    ],
    {
        let (traj, _) = trajectories();
        vec![
            "check".into(),
            traj.clone(),
            "--m".into(),
            "0.3".into(),
            "--h".into(),
            "-0.375".into(),
            "--mcap".into(),
            s(&scratch().join("c.mcap")),
        ]
    }
);

/// A path as a String.
fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

/// A trajectory of the default motion (`rsts reference`, t in [0, 1]) as CSV, and a times file.
fn trajectories() -> &'static (String, String) {
    static F: OnceLock<(String, String)> = OnceLock::new();
    F.get_or_init(|| {
        let d = tmp("trajectories");
        std::fs::create_dir_all(&d).unwrap();
        let traj = d.join("traj.csv");
        let out = rsts(&[
            "reference",
            "--t-end",
            "1",
            "--samples",
            "3",
            "-o",
            traj.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let times = d.join("times.txt");
        std::fs::write(&times, "0\n0.5 # half\n1\n").unwrap();
        (s(&traj), s(&times))
    })
}

/// The FILE of `rsts check`: each bad file exits 2 with a message naming it, and the row and
/// column when the fault is in one; no MCAP log is left.
#[test]
fn check_names_a_bad_file_its_row_and_column() {
    let d = tmp("check-files");
    std::fs::create_dir_all(&d).unwrap();
    let (traj, _) = trajectories();
    let good = std::fs::read_to_string(traj).unwrap();
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    let header = lines[0].clone();
    // Row 2 (line 3), column omega2 made NaN.
    let mut cells: Vec<String> = lines[2].split(',').map(String::from).collect();
    cells[2] = "NaN".into();
    lines[2] = cells.join(",");
    let nan_row = d.join("nan.csv");
    std::fs::write(&nan_row, lines.join("\n")).unwrap();
    let short = d.join("short.csv");
    std::fs::write(&short, format!("{header}\n0,1,2\n")).unwrap();
    let header_only = d.join("empty.csv");
    std::fs::write(&header_only, format!("{header}\n")).unwrap();
    let backwards = d.join("backwards.csv");
    let rows: Vec<&str> = good.lines().collect();
    std::fs::write(
        &backwards,
        format!("{}\n{}\n{}\n", rows[0], rows[2], rows[1]),
    )
    .unwrap();
    let text = d.join("notes.txt");
    std::fs::write(&text, "hello").unwrap();
    let cases: Vec<(PathBuf, &[&str])> = vec![
        (d.join("missing.csv"), &[]),
        (nan_row, &["line 3", "omega2"]),
        (short, &["line 2"]),
        (header_only, &["no samples"]),
        (backwards, &["increasing"]),
        (text, &[".txt"]),
        (PathBuf::from("/proc"), &[]),
    ];
    let mcap = d.join("log.mcap");
    for (file, words) in cases {
        let f = s(&file);
        for extra in [vec![], vec!["--m", "0.3", "--h", "-0.375"]] {
            let mut args = vec!["check", f.as_str(), "--mcap", mcap.to_str().unwrap()];
            args.extend(extra);
            let out = rsts(&args);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
            assert!(!err.contains("panicked"), "{err}");
            assert!(err.contains(&f), "{args:?}: the file is not named: {err}");
            for w in words {
                assert!(err.contains(w), "{args:?}: no `{w}` in {err}");
            }
            assert!(stdout(&out).is_empty(), "{args:?}");
            assert!(!mcap.exists(), "{args:?} left the MCAP log");
        }
    }
    let left: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "temporaries left: {left:?}");
}

bad_input_property!(
    inspect_rejects_bad_input,
    {
        // The FILE argument is positional: its bad values are given as `--channel`-less runs
        // below; here the options.
        vec![
            Opt {
                name: "--channel",
                named_as: &[],
                bad: &["/nope", "", "errors"],
                numeric: false,
            },
            word("--format", &["xml", "table", "yaml"]),
        ]
    },
    {
        let (mcap, _, _) = fixtures();
        vec![
            "inspect".into(),
            mcap.clone(),
            "--channel".into(),
            "/errors".into(),
        ]
    }
);

bad_input_property!(
    validate_rejects_bad_input,
    vec![
        word(
            "--suite",
            &["/nonexistent/s.toml", "/proc/self/status", "/proc"]
        ),
        word("--report", &["/proc/rsts/r", "/dev/null/r"]),
        word(
            "--baseline",
            &["/nonexistent/report.json", "/proc/self/status"]
        ),
        word("--shard", &["0/3", "4/3", "x", "1/0", "1-3"]),
        num("--jobs", &["0", "100000", "x", "-1"]),
    ],
    {
        let (_, suite, _) = fixtures();
        let r = scratch().join("report");
        vec![
            "validate".into(),
            "--suite".into(),
            suite.clone(),
            "--report".into(),
            r.to_str().unwrap().into(),
        ]
    }
);

bad_input_property!(
    surfaces_rejects_bad_input,
    vec![
        A,
        B,
        M,
        H,
        num("--torus", &["5", "-1", "x"]),
        num("--grid", &["3", "513", "x", "0"]),
        num("--scene-grid", &["3", "257", "x"]),
        num("--size", &["10", "2000", "x", "-5"]),
        num("--periods", &["0", "-1", "1e9", "nan"]),
        num("--samples", &["1", "2000000", "x"]),
        num("--phases", &["1", "x,y", "nan,0", "1,2,3"]),
        num("--azimuth", &["nan", "inf", "x"]),
        num("--elevation", &["-inf", "x"]),
        word("--out", &["/proc/rsts/s", "/dev/null/s"]),
    ],
    {
        let out = scratch().join("surfaces");
        strings(&[
            "surfaces",
            "--m",
            "0.3",
            "--h",
            "-0.375",
            "--grid",
            "8",
            "--scene-grid",
            "8",
            "--samples",
            "10",
            "--size",
            "64",
            "--no-mcap",
            "--no-ply",
            "--out",
        ])
        .into_iter()
        .chain([out.to_str().unwrap().to_string()])
        .collect()
    }
);

bad_input_property!(
    table1_rejects_bad_input,
    vec![A, B, FORMAT],
    strings(&["table1"])
);

bad_input_property!(
    table2_rejects_bad_input,
    vec![A, B, FORMAT],
    strings(&["table2"])
);

/// The positional FILE of `inspect`: missing, a directory, not MCAP, empty — each named.
#[test]
fn inspect_names_a_bad_file() {
    let (_, _, text) = fixtures();
    let empty = scratch().join("../empty.mcap");
    std::fs::write(&empty, b"").unwrap();
    for file in [
        "/nonexistent/x.mcap",
        "/proc",
        text.as_str(),
        empty.to_str().unwrap(),
    ] {
        for extra in [vec![], vec!["--channel", "/errors"]] {
            let mut args = vec!["inspect", file];
            args.extend(extra);
            let out = rsts(&args);
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            let err = stderr(&out);
            assert!(err.contains(file) && !err.contains("panicked"), "{err}");
            assert!(stdout(&out).is_empty());
        }
    }
}
