//! Hostile inputs of issue 22, each as the command that showed the defect (or a variant): device
//! files as outputs, a report folder holding the user's files, absurd timeouts, huge state
//! values, adapters that escape their timeout or flood us, suites without bound, and the small
//! ones (duplicate columns, a BOM, empty method lists, full disks on stdout). Every test failed
//! before its fix. Runs that used to hang are started with a wall-clock guard (the run is killed
//! and the test fails; the guard is not a timing assertion).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::{dir, entries, rsts, s, stderr};

/// Run `rsts args…`, killing it after `guard` seconds (then the test fails, naming the run).
/// Its stdout and stderr are read while it runs (a full pipe would block it).
fn guarded(args: &[&str], guard: u64) -> Output {
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start rsts");
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            let _ = pipe.read_to_end(&mut buf);
            buf
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let until = Instant::now() + Duration::from_secs(guard);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > until {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} still ran after {guard} s: killed");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// `compare --exec ADAPTER --t-end 1 --samples 2 EXTRA…`, guarded (60 s).
fn compare_exec(adapter: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "compare",
        "--exec",
        adapter,
        "--t-end",
        "1",
        "--samples",
        "2",
    ];
    args.extend_from_slice(extra);
    guarded(&args, 60)
}

/// An executable shell script `name` in `d`.
fn script(d: &Path, name: &str, body: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    let p = d.join(name);
    fs::write(&p, format!("#!/bin/sh\n{body}\n")).unwrap();
    fs::set_permissions(&p, fs::Permissions::from_mode(0o755)).unwrap();
    s(&p).to_string()
}

fn code(out: &Output) -> Option<i32> {
    out.status.code()
}

const HEADER: &str = "t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3";

// ---- 1. device files and FIFOs are written in place, never replaced --------------------------

/// `mknod PATH c 1 MINOR` (3: null, 7: full); false where this user may not make devices.
fn mknod(path: &Path, minor: &str) -> bool {
    Command::new("mknod")
        .args([s(path), "c", "1", minor])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|st| st.success())
}

fn is_char_device(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

/// Every output option of every command, with `X` for the output path; and the option's name.
fn outputs(d: &Path) -> Vec<(Vec<String>, &'static str)> {
    let traj = d.join("traj.csv");
    let out = rsts(&["reference", "--times", "0,0.5,1", "-o", s(&traj)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let v = |a: &[&str]| a.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    vec![
        (v(&["reference", "--times", "0,1", "-o", "X"]), "-o"),
        (
            v(&["compare", "--t-end", "1", "--samples", "3", "--mcap", "X"]),
            "--mcap",
        ),
        (v(&["check", s(&traj), "--mcap", "X"]), "--mcap"),
        (v(&["diagram", "--svg", "X"]), "--svg"),
        (
            v(&[
                "bench",
                "--t-end",
                "2",
                "--samples",
                "5",
                "--repeats",
                "1",
                "--svg",
                "X",
            ]),
            "--svg",
        ),
    ]
}

fn with_target(args: &[String], target: &Path) -> Vec<String> {
    args.iter()
        .map(|a| {
            if a == "X" {
                s(target).to_string()
            } else {
                a.clone()
            }
        })
        .collect()
}

#[test]
fn i1_a_device_is_written_in_place_and_a_full_one_names_the_option() {
    let d = dir("devices");
    let (null, full) = (d.join("mynull"), d.join("myfull"));
    if !(mknod(&null, "3") && mknod(&full, "7")) {
        rsts_io::report_skip(
            "i1_a_device_is_written_in_place_and_a_full_one_names_the_option",
            "mknod is not permitted here (tests run as root in CI)",
        );
        return;
    }
    for (args, option) in outputs(&d) {
        let run = |target: &Path| {
            let a = with_target(&args, target);
            let a: Vec<&str> = a.iter().map(String::as_str).collect();
            (guarded(&a, 120), a.join(" "))
        };
        let (out, what) = run(&null);
        assert_eq!(code(&out), Some(0), "{what}: {}", stderr(&out));
        assert!(is_char_device(&null), "{what} replaced the device");
        let (out, what) = run(&full);
        assert_eq!(code(&out), Some(2), "{what}: {}", stderr(&out));
        let e = stderr(&out);
        assert!(
            e.contains(option) && e.contains("No space left on device"),
            "{what}: {e}"
        );
        assert!(is_char_device(&full), "{what} replaced the device");
    }
    assert_eq!(
        entries(&d),
        vec!["myfull", "mynull", "traj.csv"],
        "nothing left"
    );
}

#[test]
fn i1_a_fifo_receives_the_document_and_a_socket_is_refused() {
    let d = dir("fifo");
    let fifo = d.join("pipe");
    let made = Command::new("mkfifo").arg(s(&fifo)).status().unwrap();
    assert!(made.success());
    // Held open read-write (Linux opens a FIFO so without waiting) until the run is over: the
    // reader never waits for a writer that does not come, whatever the run did to the path.
    let keep = fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&fifo)
        .unwrap();
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || fs::read(&fifo).unwrap())
    };
    let out = guarded(&["reference", "--times", "0,1", "-o", s(&fifo)], 60);
    drop(keep);
    let got = reader.join().unwrap();
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let want = rsts(&["reference", "--times", "0,1"]).stdout;
    assert_eq!(got, want, "the FIFO's reader gets the whole document");
    use std::os::unix::fs::FileTypeExt;
    assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
    let sock = d.join("sock");
    let _listener = std::os::unix::net::UnixListener::bind(&sock).unwrap();
    let out = rsts(&["reference", "--times", "0,1", "-o", s(&sock)]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("-o") && e.contains("socket"), "{e}");
}

#[test]
fn i8_a_full_stdout_names_stdout() {
    let Ok(full) = fs::OpenOptions::new().write(true).open("/dev/full") else {
        rsts_io::report_skip("i8_a_full_stdout_names_stdout", "no /dev/full");
        return;
    };
    let out = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(["reference", "--times", "0,1"])
        .stdout(full)
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(
        e.contains("stdout") && e.contains("No space left on device"),
        "{e}"
    );
}

// ---- 2. a report folder holding the user's files is not replaced ----------------------------

const TINY_SUITE: &str = "[[case]]\nname = \"tiny\"\nm = 0.3\nh = -0.375\nt_end = 1\nsamples = 3\n";

#[test]
fn i2_validate_never_deletes_files_a_report_did_not_write() {
    let d = dir("report-folder");
    let rep = d.join("rep");
    // An earlier report, where the user also keeps the suite and notes.
    fs::create_dir_all(rep.join("plots")).unwrap();
    fs::write(rep.join("report.json"), "{}").unwrap();
    fs::write(rep.join("plots/error.svg"), "<svg/>").unwrap();
    let suite = rep.join("s.toml");
    fs::write(&suite, TINY_SUITE).unwrap();
    fs::write(rep.join("NOTES.txt"), "mine").unwrap();
    let out = rsts(&["validate", "--suite", s(&suite), "--report", s(&rep)]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(
        e.contains("--report") && (e.contains("s.toml") || e.contains("NOTES.txt")),
        "{e}"
    );
    assert_eq!(fs::read_to_string(&suite).unwrap(), TINY_SUITE);
    assert_eq!(fs::read_to_string(rep.join("NOTES.txt")).unwrap(), "mine");
    // Without the user's files the earlier report is replaced as before.
    let outside = d.join("s.toml");
    fs::rename(&suite, &outside).unwrap();
    fs::remove_file(rep.join("NOTES.txt")).unwrap();
    let out = rsts(&["validate", "--suite", s(&outside), "--report", s(&rep)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    assert!(rep.join("report.md").is_file());
    assert!(!rep.join("plots/error.svg").exists(), "replaced whole");
}

// ---- 3. one rule for every timeout ------------------------------------------------------------

#[test]
fn i3_absurd_timeouts_are_refused_naming_the_key() {
    let d = dir("timeouts");
    for t in ["1.8e19", "1e20", "1e300", "1e10", "0", "-1"] {
        let suite = d.join("s.toml");
        fs::write(
            &suite,
            format!(
                "{TINY_SUITE}methods = [\"x\"]\n[adapters.x]\ncommand = [\"true\"]\ntimeout = {t}\n"
            ),
        )
        .unwrap();
        let out = guarded(&["validate", "--suite", s(&suite), "--list"], 60);
        let e = stderr(&out);
        assert_eq!(code(&out), Some(2), "timeout = {t}: {e}");
        assert!(e.contains("[adapters.x] timeout"), "timeout = {t}: {e}");
        let timeout = format!("--exec-timeout={t}");
        let out = rsts(&["compare", "--exec", "true", &timeout]);
        let e = stderr(&out);
        assert_eq!(code(&out), Some(2), "--exec-timeout {t}: {e}");
        assert!(e.contains("--exec-timeout"), "{e}");
    }
}

// ---- 4. huge state values are refused at once, naming where ---------------------------------

#[test]
fn i4_state_values_beyond_the_range_are_refused_at_once() {
    let d = dir("huge");
    let csv = d.join("big.csv");
    fs::write(&csv, format!("{HEADER}\n0,1e100,0,0,1,0,0,0,1,0\n")).unwrap();
    let json = d.join("big.json");
    fs::write(
        &json,
        r#"{"samples": [{"t": 0, "omega": [0.1, 0.2, 0.3], "alpha": [1, 0, 0], "beta": [0, 1e308, 0]}]}"#,
    )
    .unwrap();
    let npy = d.join("big.npy");
    let mut row = vec![0.0, 0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    row[3] = -1e200;
    fs::write(&npy, rsts_external::npy_bytes(&[row], 10)).unwrap();
    let answers = script(
        &d,
        "answers-1e100.sh",
        &format!("cat >/dev/null\necho {HEADER}\necho 0,1e100,0,0,1,0,0,0,1,0\necho 1,1e100,0,0,1,0,0,0,1,0"),
    );
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["check", s(&csv)], "line 2, column 2 (omega1)"),
        (vec!["check", s(&json)], "samples[0].beta[1]"),
        (vec!["check", s(&npy)], "row 1, column 4 (omega3)"),
        (
            vec![
                "identify",
                "--omega=1e100,0,0",
                "--alpha",
                "1,0,0",
                "--beta",
                "0,1,0",
            ],
            "omega1",
        ),
        (
            vec![
                "integrate",
                "--omega=0,-1e9,0",
                "--alpha",
                "1,0,0",
                "--beta",
                "0,1,0",
            ],
            "omega2",
        ),
        (
            vec![
                "compare",
                "--exec",
                &answers,
                "--t-end",
                "1",
                "--samples",
                "2",
            ],
            "line 2, column 2 (omega1)",
        ),
    ];
    for (args, place) in cases {
        let out = guarded(&args, 60);
        let e = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {e}");
        assert!(e.contains(place) && e.contains("1e8"), "{args:?}: {e}");
    }
    // At the bound it still works, and fast (the run is guarded).
    let out = guarded(
        &[
            "identify",
            "--omega=1e8,3e7,-2e7",
            "--alpha",
            "0.6,0.8,0",
            "--beta",
            "0,0,1",
        ],
        60,
    );
    assert_eq!(code(&out), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("has no torus"), "{}", stderr(&out));
}

// ---- 5. the timeout holds whatever keeps the pipes open ---------------------------------------

/// Kill the process whose id the adapter wrote to `pidfile` (a grandchild in its own session).
fn kill_pid_in(pidfile: &Path) {
    if let Ok(text) = fs::read_to_string(pidfile) {
        if let Ok(pid) = text.trim().parse::<i32>() {
            // SAFETY: kill(2) of the one process this test's adapter started.
            unsafe {
                libc::kill(pid, libc::SIGKILL);
            }
        }
    }
}

#[test]
fn i5_a_grandchild_holding_stdout_cannot_stretch_the_timeout() {
    let d = dir("escape");
    let rsts_bin = env!("CARGO_BIN_EXE_rsts");
    let pid = d.join("pid");
    // Answers correctly, then leaves a child in its own session that keeps stdout open 120 s.
    let answers = script(
        &d,
        "answers-and-lingers.sh",
        &format!(
            "cat >/dev/null\n{rsts_bin} reference --times 0,1\nsetsid sleep 120 2>/dev/null &\necho $! > {}",
            s(&pid)
        ),
    );
    let out = compare_exec(&answers, &["--exec-timeout", "5", "--format", "json"]);
    kill_pid_in(&pid);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["samples_compared"], 2);
    // Never answers, and leaves such a child: "no answer within 2 s", not after the child.
    let pid2 = d.join("pid2");
    let silent = script(
        &d,
        "silent.sh",
        &format!(
            "setsid sleep 120 2>/dev/null &\necho $! > {}\nsleep 120",
            s(&pid2)
        ),
    );
    let out = compare_exec(&silent, &["--exec-timeout", "2"]);
    kill_pid_in(&pid2);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("no answer within 2 s"), "{e}");
}

// ---- 6. what an adapter or a suite can make us hold is bounded --------------------------------

#[test]
fn i6_a_flood_on_stdout_is_cut_off_and_stderr_keeps_its_tail() {
    let d = dir("flood");
    let rsts_bin = env!("CARGO_BIN_EXE_rsts");
    // 64 MiB of whitespace before a valid answer: far more than 2 samples can need.
    let flood = script(
        &d,
        "flood.sh",
        &format!(
            "cat >/dev/null\nhead -c 67108864 /dev/zero | tr '\\0' ' '\n{rsts_bin} reference --times 0,1 --format json"
        ),
    );
    let out = compare_exec(&flood, &[]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(
        e.contains("its answer passed") && e.contains("bytes"),
        "{e}"
    );
    // 16 MiB of stderr, then the line that explains: shown, the flood cut.
    let noisy = script(
        &d,
        "noisy.sh",
        "cat >/dev/null\nhead -c 16777216 /dev/zero | tr '\\0' 'x' >&2\necho >&2\necho 'THE REASON' >&2\nexit 3",
    );
    let out = compare_exec(&noisy, &[]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(
        e.contains("THE REASON") && e.len() < 10_000,
        "{}",
        &e[..e.len().min(500)]
    );
}

#[test]
fn i6_a_suite_beyond_the_run_limit_is_refused_at_once() {
    let d = dir("big-suite");
    let suite = d.join("s.toml");
    // One case, 20001 runs (tolerances × methods): refused before anything is expanded.
    let tolerances: Vec<String> = (0..20_001).map(|k| format!("{}e-9", k + 1)).collect();
    fs::write(
        &suite,
        format!("{TINY_SUITE}tolerances = [{}]\n", tolerances.join(",")),
    )
    .unwrap();
    let out = guarded(&["validate", "--suite", s(&suite), "--list"], 60);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("20000"), "{e}");
    // Many cases: refused as soon as their runs pass the limit.
    let many: String = (0..20_001)
        .map(|k| format!("[[case]]\nname = \"c{k}\"\nm = 0.3\nh = -0.375\n"))
        .collect();
    fs::write(&suite, many).unwrap();
    let out = guarded(&["validate", "--suite", s(&suite), "--list"], 60);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("20000"), "{e}");
    // A file over 4 MiB is not even parsed.
    let mut big = String::from(TINY_SUITE);
    big.push_str(&"# padding\n".repeat(500_000));
    fs::write(&suite, big).unwrap();
    let out = rsts(&["validate", "--suite", s(&suite), "--list"]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("4 MiB"), "{e}");
}

// ---- 8. smaller ones ------------------------------------------------------------------------

fn reference_csv(d: &Path) -> PathBuf {
    let p = d.join("ref.csv");
    let out = rsts(&["reference", "--times", "0,0.5,1", "-o", s(&p)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    p
}

#[test]
fn i8_duplicate_columns_are_refused_and_a_bom_is_accepted() {
    let d = dir("csv-small");
    let text = fs::read_to_string(reference_csv(&d)).unwrap();
    let bom = d.join("bom.csv");
    fs::write(&bom, format!("\u{feff}{text}")).unwrap();
    let out = rsts(&["check", s(&bom)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let dup = d.join("dup.csv");
    let mut lines: Vec<String> = text.lines().map(|l| format!("{l},0")).collect();
    lines[0] = format!("{},omega2", text.lines().next().unwrap());
    fs::write(&dup, lines.join("\n")).unwrap();
    let out = rsts(&["check", s(&dup)]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("omega2 more than once"), "{e}");
    // A 1 MB value is not repeated whole in the message.
    let long = d.join("long.csv");
    fs::write(
        &long,
        format!("{HEADER}\n0,{},0,0,1,0,0,0,1,0\n", "7x".repeat(500_000)),
    )
    .unwrap();
    let out = rsts(&["check", s(&long)]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{}", &e[..e.len().min(300)]);
    assert!(
        e.len() < 1000 && e.contains("1000000 characters"),
        "{}",
        &e[..e.len().min(300)]
    );
}

/// A logged state: t, ω (of any length), α, β.
type Logged = (f64, Vec<f64>, [f64; 3], [f64; 3]);

/// An MCAP log whose `/integrated/state` holds one message per state (t, ω, α, β as JSON).
fn mcap_of_states(path: &Path, states: &[Logged]) {
    let file = std::io::BufWriter::new(fs::File::create(path).unwrap());
    let mut w = mcap::Writer::new(file).unwrap();
    let schema = w.add_schema("rsts.BodyState", "jsonschema", b"{}").unwrap();
    let none = std::collections::BTreeMap::new();
    let channel = w
        .add_channel(schema, "/integrated/state", "json", &none)
        .unwrap();
    for (k, (t, omega, alpha, beta)) in states.iter().enumerate() {
        let data = serde_json::json!({"t": t, "omega": omega, "alpha": alpha, "beta": beta});
        let ns = (t * 1e9) as u64;
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: k as u32,
            log_time: ns,
            publish_time: ns,
        };
        w.write_to_known_channel(&header, data.to_string().as_bytes())
            .unwrap();
    }
    w.finish().unwrap();
}

/// An MCAP `omega` of four elements is refused, as CSV and JSON refuse it; the same log with
/// three is checked.
#[test]
fn i8_an_mcap_omega_of_four_elements_is_refused() {
    let d = dir("mcap-omega4");
    let text = fs::read_to_string(reference_csv(&d)).unwrap();
    let row: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let state = |omega: Vec<f64>| {
        vec![(
            row[0],
            omega,
            [row[4], row[5], row[6]],
            [row[7], row[8], row[9]],
        )]
    };
    let three = d.join("three.mcap");
    mcap_of_states(&three, &state(row[1..4].to_vec()));
    let out = rsts(&["check", s(&three)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let four = d.join("four.mcap");
    mcap_of_states(&four, &state(vec![row[1], row[2], row[3], 0.0]));
    let out = rsts(&["check", s(&four)]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(
        e.contains("message 1 of /integrated/state: \"omega\" must be an array of 3 numbers"),
        "{e}"
    );
}

/// A suite's errors say "suite" once: the option, the file, the case, the reason (they read
/// "--suite: suite: s.toml: suite: case 'tiny': suite: invalid integrator settings: …").
#[test]
fn suite_errors_do_not_repeat_their_prefixes() {
    let d = dir("prefixes");
    for (extra, reason) in [
        ("methods = [\"nope\"]\n", "unknown method 'nope'"),
        ("tori = 5\n", "torus 5 does not exist"),
        ("t_end = -1\n", "t_end must be non-negative"),
    ] {
        let suite = d.join("s.toml");
        fs::write(&suite, TINY_SUITE.replace("t_end = 1\n", "") + extra).unwrap();
        let out = rsts(&["validate", "--suite", s(&suite), "--list"]);
        let e = stderr(&out);
        assert_eq!(code(&out), Some(2), "{e}");
        let head = format!("error: --suite: {}: case 'tiny': ", suite.display());
        assert!(e.starts_with(&head) && e.contains(reason), "{e}");
        assert!(!e[head.len()..].contains("suite"), "{e}");
    }
}

#[test]
fn i8_a_suite_with_no_methods_is_refused() {
    let d = dir("no-methods");
    let suite = d.join("s.toml");
    fs::write(&suite, format!("{TINY_SUITE}methods = []\n")).unwrap();
    let out = rsts(&["validate", "--suite", s(&suite), "--list"]);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{e}");
    assert!(e.contains("methods is an empty list"), "{e}");
}

// ---- 7. long digit strings --------------------------------------------------------------------

#[test]
fn i7_digits_beyond_what_the_reference_uses_are_refused_and_identify_is_fast() {
    let d = dir("digits");
    let long = d.join("long.csv");
    let digits = format!("0.{}", "3".repeat(200_000));
    fs::write(&long, format!("{HEADER}\n0,{digits},0,0,1,0,0,0,1,0\n")).unwrap();
    let out = guarded(&["check", s(&long)], 60);
    let e = stderr(&out);
    assert_eq!(code(&out), Some(2), "{}", &e[..e.len().min(300)]);
    assert!(
        e.contains("line 2, column 2 (omega1)") && e.contains("more than 10000 significant digits"),
        "{}",
        &e[..e.len().min(300)]
    );
    // A 10-digit state identified at 10000 digits: the searches stop at the state's own
    // distance from N (epsilon at 33000 bits used to be 0: every loop ran to its limit, 70 s).
    let out = guarded(
        &[
            "identify",
            "--omega=-0.7647920880,0.0304544152,-0.0788113714",
            "--alpha=-0.8092123863,0.4893823915,0.3250848946",
            "--beta=0.1716166194,-0.3322951766,0.9274306721",
            "--digits",
            "10000",
            "--format",
            "json",
        ],
        45,
    );
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["camera"], "V");
    assert_eq!(doc["torus"], 3);
    let phase1: f64 = doc["phase1"].as_str().unwrap().parse().unwrap();
    assert!((phase1 - 0.5).abs() < 1e-8, "{phase1}");
}

/// A table cell wider than 65535 characters (a format width's limit) used to panic.
#[test]
fn i7_a_table_of_sixty_six_thousand_digits_prints() {
    let out = guarded(
        &[
            "explicit",
            "--t-end",
            "0",
            "--samples",
            "1",
            "--digits",
            "66000",
        ],
        120,
    );
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let widths: Vec<usize> = lines[lines.len() - 3..]
        .iter()
        .map(|l| l.chars().count())
        .collect();
    assert!(
        widths[0] > 66_000 && widths.iter().all(|&w| w == widths[0]),
        "{widths:?}"
    );
}

// ---- what a new user saw wrong ----------------------------------------------------------------

/// An answer stating its own precision (`"digits"`) is reported with it, not with the
/// request's 36 digits.
#[test]
fn user_an_adapter_states_its_digits() {
    let d = dir("answer-digits");
    let rsts_bin = env!("CARGO_BIN_EXE_rsts");
    // `reference --digits 20 --format json` carries "digits": 20 at its head.
    let answers = script(
        &d,
        "answers-20-digits.sh",
        &format!("cat >/dev/null\n{rsts_bin} reference --times 0,1 --digits 20 --format json"),
    );
    let out = compare_exec(&answers, &["--format", "json"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["digits"], 20, "{doc}");
}

/// The hint after `check --mcap` names a command that runs from anywhere (as compare's does),
/// not `target/release/rsts`, which only works at the top of a checkout.
#[test]
fn user_check_mcap_hint_runs_from_anywhere() {
    let d = dir("hint");
    let traj = reference_csv(&d);
    let out = Command::new(env!("CARGO_BIN_EXE_rsts"))
        .args(["check", s(&traj), "--mcap", "c.mcap"])
        .current_dir(&d)
        .output()
        .unwrap();
    let e = stderr(&out);
    assert_eq!(code(&out), Some(0), "{e}");
    assert!(
        e.contains(" inspect c.mcap`") && !e.contains("`target/release/rsts inspect"),
        "{e}"
    );
}

/// The error plot's dashed line is what its label says, the distance from N: in camera V it
/// follows the departure (above 1e-5 here), where off_N (the on-N relations' drift) stayed near
/// round-off and was drawn instead.
#[test]
fn user_the_error_plot_draws_the_distance_from_n() {
    let d = dir("plot-distance");
    let suite = d.join("v.toml");
    fs::write(
        &suite,
        "[[case]]\nname = \"camera-v\"\nm = -0.7092\nh = 1.5643\ntori = [2]\nt_end = 50\n\
         samples = 501\nmethods = [\"dopri5\"]\ntolerances = [1e-8]\n",
    )
    .unwrap();
    let rep = d.join("rep");
    let out = guarded(
        &["validate", "--suite", s(&suite), "--report", s(&rep)],
        120,
    );
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let report: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(rep.join("report.json")).unwrap()).unwrap();
    let run = report["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["method"] == "dopri5")
        .unwrap();
    let dist: Vec<f64> = run["series"]["distance_from_N"]
        .as_array()
        .expect("the series keeps the distance from N")
        .iter()
        .filter_map(serde_json::Value::as_f64)
        .collect();
    let max = dist.iter().copied().fold(0.0, f64::max);
    assert!(max > 1e-5, "max distance from N {max:e}");
    let svg = fs::read_to_string(rep.join("plots/error-camera-v-t2.svg")).unwrap();
    assert!(svg.contains("dopri5@1e-8 distance from N"), "legend");
    assert!(!svg.contains("off N"), "off_N is not drawn as the distance");
}

/// SIGTERM and SIGHUP are handled as Ctrl-C: a run killed while writing removes its temporary,
/// exits 128 + the signal (143, 129: the shell's convention; was 130 for both) and leaves the
/// previous file as it was (before, the temporary stayed behind).
#[test]
fn sigterm_and_sighup_remove_the_temporary() {
    for (name, signal, exit) in [("term", libc::SIGTERM, 143), ("hup", libc::SIGHUP, 129)] {
        let d = dir(&format!("signal-{name}"));
        let target = d.join("big.csv");
        fs::write(&target, "previous").unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_rsts"))
            .args([
                "reference",
                "--t-end",
                "1e4",
                "--samples",
                "2000000",
                "-o",
                s(&target),
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let temporary = |d: &Path| entries(d).into_iter().any(|e| e.contains(".tmp-"));
        let until = Instant::now() + Duration::from_secs(60);
        while !temporary(&d) {
            assert!(
                child.try_wait().unwrap().is_none(),
                "{name}: done before its temporary was seen"
            );
            assert!(Instant::now() < until, "{name}: no temporary after 60 s");
            std::thread::sleep(Duration::from_millis(10));
        }
        // SAFETY: plain kill(2) on our own child.
        unsafe {
            libc::kill(child.id() as i32, signal);
        }
        let out = guarded_wait(child, 60);
        assert_eq!(
            code(&out),
            Some(exit),
            "{name}: {:?} {}",
            out.status,
            stderr(&out)
        );
        assert_eq!(entries(&d), ["big.csv"], "{name}");
        assert_eq!(fs::read_to_string(&target).unwrap(), "previous", "{name}");
    }
}

/// Wait for `child`, killing it after `guard` seconds (then the test fails).
fn guarded_wait(mut child: std::process::Child, guard: u64) -> Output {
    let until = Instant::now() + Duration::from_secs(guard);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > until {
            let _ = child.kill();
            panic!("still running after {guard} s: killed");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}
