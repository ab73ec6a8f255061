//! Reliability: the twelve defects of issue 13, each as the command that showed it, run the way a
//! careful (or hostile) user runs it. Every test here failed before the fix it guards.
//!
//! Runs are started with limits where a defect used to run away: a wall-clock guard (a hung run
//! is killed and the test fails, it never hangs CI), an address-space limit (RLIMIT_AS: memory
//! that grew with the steps instead of the samples now fails the run) and a file-size limit
//! (RLIMIT_FSIZE with SIGXFSZ ignored: writes past it fail with EFBIG, a stand-in for a full
//! disk that needs no privileges).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common;
use common::{dir, entries, rsts, s, stderr, stdout};

/// Limits of one run.
#[derive(Clone, Copy, Default)]
struct Limits {
    /// Kill the run after this long (a guard against hangs, not a timing assertion).
    guard_seconds: u64,
    /// RLIMIT_AS in MiB.
    memory_mib: Option<u64>,
    /// RLIMIT_FSIZE in bytes (SIGXFSZ ignored, so writes fail with EFBIG instead).
    file_bytes: Option<u64>,
}

fn command(args: &[&str], limits: Limits) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rsts"));
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    use std::os::unix::process::CommandExt;
    let Limits {
        memory_mib,
        file_bytes,
        ..
    } = limits;
    // SAFETY: only async-signal-safe calls (setrlimit, signal) between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            if let Some(m) = memory_mib {
                let lim = libc::rlimit {
                    rlim_cur: m << 20,
                    rlim_max: m << 20,
                };
                if libc::setrlimit(libc::RLIMIT_AS, &lim) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
            if let Some(b) = file_bytes {
                libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
                let lim = libc::rlimit {
                    rlim_cur: b,
                    rlim_max: b,
                };
                if libc::setrlimit(libc::RLIMIT_FSIZE, &lim) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
            Ok(())
        });
    }
    cmd
}

/// Wait for `child`, killing it after `guard` seconds; panics (naming `what`) if it had to.
/// Its stdout and stderr are read while it runs (a full pipe would block it).
fn wait_guarded(mut child: Child, guard: u64, what: &str) -> Output {
    use std::io::Read;
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut buf);
            }
            buf
        })
    };
    let out = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("poll the child") {
            break status;
        }
        if start.elapsed() > Duration::from_secs(guard) {
            let _ = child.kill();
            let _ = child.wait();
            let err = err.join().unwrap();
            panic!(
                "`rsts {what}` still running after {guard} s (killed); stderr: {}",
                String::from_utf8_lossy(&err)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// Run `rsts args…` under `limits`.
fn run(args: &[&str], limits: Limits) -> Output {
    let guard = if limits.guard_seconds == 0 {
        120
    } else {
        limits.guard_seconds
    };
    let child = command(args, limits).spawn().expect("start rsts");
    wait_guarded(child, guard, &args.join(" "))
}

fn code(out: &Output) -> Option<i32> {
    out.status.code()
}

/// `d/c.mcap`: the log of a short comparison (T = 2, 5 samples), which must succeed.
fn small_compare_log(d: &Path) -> PathBuf {
    let mcap = d.join("c.mcap");
    let out = rsts(&[
        "compare",
        "--t-end",
        "2",
        "--samples",
        "5",
        "--mcap",
        s(&mcap),
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    mcap
}

/// No leftover temporaries (`.NAME.tmp-PID-N`) anywhere under `d`.
fn assert_no_temporaries(d: &Path) {
    for e in fs::read_dir(d).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        assert!(!name.contains(".tmp-"), "temporary left behind: {name}");
        if e.file_type().unwrap().is_dir() {
            assert_no_temporaries(&e.path());
        }
    }
}

/// `inspect FILE` exits 0 and calls the file complete.
fn assert_complete_mcap(path: &Path) {
    let out = rsts(&["inspect", s(path)]);
    assert_eq!(
        code(&out),
        Some(0),
        "{}: {}{}",
        path.display(),
        stdout(&out),
        stderr(&out)
    );
    assert!(
        stdout(&out).contains("status: complete"),
        "{}",
        stdout(&out)
    );
}

/// No run of 10 or more digits (numbers in messages are printed short).
fn assert_short_numbers(text: &str) {
    let mut run = 0;
    for c in text.chars() {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        assert!(run < 10, "long number in message: {text}");
    }
}

/// Neither NaN nor inf anywhere in `text`.
fn assert_finite_text(text: &str) {
    let lower = text.to_ascii_lowercase();
    assert!(
        !lower.contains("nan") && !lower.contains("inf"),
        "non-finite value printed: {}",
        &text[..text.len().min(2000)]
    );
}

// ---- 1. a rejected run destroys an existing file --------------------------------------------

#[test]
fn d01_a_rejected_run_leaves_an_existing_file_untouched() {
    let d = dir("d01");
    let keep = d.join("keep.mcap");
    let out = rsts(&[
        "compare",
        "--t-end",
        "20",
        "--samples",
        "200",
        "--mcap",
        s(&keep),
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let before = fs::read(&keep).unwrap();
    // On Σ: rejected.
    let out = rsts(&["compare", "--m", "1.0", "--h", "-1.25", "--mcap", s(&keep)]);
    assert_eq!(code(&out), Some(2), "{}", stderr(&out));
    assert_eq!(fs::read(&keep).unwrap(), before, "keep.mcap was changed");
    // Rejected later, by the integrator's own checks, and by a bad format/method combination.
    for args in [
        vec!["compare", "--rtol", "1e-30", "--atol", "1e-30"],
        vec!["compare", "--method", "taylor-f64", "--rtol", "1e-20"],
        vec!["compare", "--t-end", "-1"],
    ] {
        let mut args = args;
        args.extend(["--mcap", s(&keep)]);
        let out = rsts(&args);
        assert_eq!(code(&out), Some(2), "{args:?}: {}", stderr(&out));
        assert_eq!(
            fs::read(&keep).unwrap(),
            before,
            "{args:?} changed keep.mcap"
        );
    }
    assert_eq!(entries(&d), vec!["keep.mcap"]);
}

/// A shell script standing in for an external integrator (`--exec`).
fn script(d: &Path, name: &str, body: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    let path = d.join(name);
    fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    fs::set_permissions(&path, fs::Permissions::from_mode(0o755)).unwrap();
    path.to_str().unwrap().to_string()
}

/// An external integrator that fails, answers garbage, hangs past its timeout or writes part
/// of an answer and dies: exit 2 naming it, and the files the run was to replace (MCAP log,
/// work-precision SVG, check's log) keep their bytes; nothing else appears.
#[test]
fn d01_a_failing_or_hanging_external_integrator_leaves_existing_files_untouched() {
    let d = dir("d01-exec");
    let progs = dir("d01-exec-programs");
    let keep = d.join("keep.mcap");
    let svg = d.join("keep.svg");
    let traj = d.join("traj.csv");
    for args in [
        vec![
            "compare",
            "--t-end",
            "1",
            "--samples",
            "5",
            "--mcap",
            s(&keep),
        ],
        vec!["diagram", "--svg", s(&svg)],
        vec![
            "reference",
            "--t-end",
            "1",
            "--samples",
            "5",
            "-o",
            s(&traj),
        ],
    ] {
        let out = rsts(&args);
        assert_eq!(code(&out), Some(0), "{args:?}: {}", stderr(&out));
    }
    let before = |p: &Path| fs::read(p).unwrap();
    let (mcap0, svg0, traj0) = (before(&keep), before(&svg), before(&traj));
    let children = [
        script(
            &progs,
            "fails.sh",
            "cat > /dev/null\necho 'Traceback: boom' >&2\nexit 1",
        ),
        script(
            &progs,
            "garbage.sh",
            "cat > /dev/null\necho '{\"samples\": [1, 2'",
        ),
        script(&progs, "hangs.sh", "cat > /dev/null\nsleep 30"),
        script(
            &progs,
            "dies.sh",
            "cat > /dev/null\nprintf '{\"samples\": [{\"t\": 0, \"omega\": [0'\nkill -9 $$",
        ),
    ];
    for child in &children {
        let runs: Vec<Vec<&str>> = vec![
            vec![
                "compare",
                "--exec",
                child,
                "--t-end",
                "1",
                "--samples",
                "5",
                "--mcap",
                s(&keep),
            ],
            vec![
                "bench",
                "--exec",
                child,
                "--t-end",
                "1",
                "--samples",
                "5",
                "--tolerances",
                "1e-6",
                "--repeats",
                "1",
                "--svg",
                s(&svg),
            ],
        ];
        for mut args in runs {
            args.extend(["--exec-timeout", "2"]);
            let out = run(&args, Limits::default());
            let err = stderr(&out);
            assert_eq!(code(&out), Some(2), "{args:?}: {err}");
            assert!(
                err.contains(&format!("`{child}`")),
                "{args:?}: not named: {err}"
            );
            assert!(!err.contains("panicked"), "{err}");
            assert!(stdout(&out).is_empty(), "{args:?}: {}", stdout(&out));
        }
        assert_eq!(before(&keep), mcap0, "{child}: keep.mcap changed");
        assert_eq!(before(&svg), svg0, "{child}: keep.svg changed");
    }
    assert_eq!(before(&traj), traj0);
    assert_eq!(entries(&d), vec!["keep.mcap", "keep.svg", "traj.csv"]);
}

// ---- 2. two runs writing the same file at once ----------------------------------------------

#[test]
fn d02_two_concurrent_runs_leave_one_complete_file() {
    let d = dir("d02");
    let same = d.join("same.mcap");
    let args = [
        "compare",
        "--t-end",
        "20",
        "--samples",
        "2000",
        "--mcap",
        s(&same),
    ];
    let a = command(&args, Limits::default()).spawn().unwrap();
    let b = command(&args, Limits::default()).spawn().unwrap();
    let (a, b) = (
        wait_guarded(a, 120, "compare"),
        wait_guarded(b, 120, "compare"),
    );
    assert_eq!(code(&a), Some(0), "{}", stderr(&a));
    assert_eq!(code(&b), Some(0), "{}", stderr(&b));
    assert_complete_mcap(&same);
    assert_eq!(entries(&d), vec!["same.mcap"]);
}

// ---- 3. memory grows with steps, not samples ------------------------------------------------

#[test]
fn d03_rk4_with_a_hopeless_step_count_is_refused_at_once_with_the_estimate() {
    let out = run(
        &[
            "compare",
            "--method",
            "rk4",
            "--rtol",
            "1e-38",
            "--atol",
            "1e-38",
            "--t-end",
            "3",
            "--samples",
            "4",
        ],
        Limits {
            guard_seconds: 30,
            memory_mib: Some(1024),
            ..Limits::default()
        },
    );
    assert_eq!(code(&out), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("steps"), "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("memory allocation"),
        "{err}"
    );
}

#[test]
fn d03_rk4_memory_is_bounded_by_the_samples_not_the_steps() {
    // 10⁷ steps for 3 samples: the old integrator kept every step (~1.4 GB here).
    let out = run(
        &[
            "integrate",
            "--method",
            "rk4",
            "--step",
            "1e-7",
            "--t-end",
            "1",
            "--samples",
            "3",
            "--format",
            "json",
        ],
        Limits {
            guard_seconds: 300,
            memory_mib: Some(400),
            ..Limits::default()
        },
    );
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["samples"].as_array().unwrap().len(), 3);
    assert_eq!(v["stats"]["accepted_steps"].as_u64(), Some(10_000_000));
}

// ---- 4. tiny t-end ---------------------------------------------------------------------------

#[test]
fn d04_a_tiny_t_end_neither_hangs_nor_grows_memory() {
    let limits = Limits {
        guard_seconds: 60,
        memory_mib: Some(400),
        ..Limits::default()
    };
    for method in ["dop853", "dopri5", "rk4", "taylor-f64"] {
        for t_end in ["1e-300", "1e-14", "5e-324"] {
            let out = run(
                &[
                    "integrate",
                    "--t-end",
                    t_end,
                    "--samples",
                    "11",
                    "--method",
                    method,
                    "--format",
                    "json",
                ],
                limits,
            );
            assert_eq!(code(&out), Some(0), "{method} {t_end}: {}", stderr(&out));
            let v: Value = serde_json::from_slice(&out.stdout).unwrap();
            let samples = v["samples"].as_array().unwrap();
            assert_eq!(samples.len(), 11);
            let last = &samples[10];
            assert_eq!(last["t"].as_f64().unwrap(), t_end.parse::<f64>().unwrap());
            // Nothing moves in 1e-14 s beyond a few ulps.
            let w = last["omega"][0].as_f64().unwrap();
            assert!((w - 0.3).abs() < 1e-13, "{method} {t_end}: omega1 = {w}");
        }
    }
    let out = run(&["compare", "--t-end", "1e-14", "--samples", "11"], limits);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
}

#[test]
fn d04_a_suite_with_a_tiny_t_end_finishes() {
    let d = dir("d04-suite");
    let suite = d.join("tiny.toml");
    fs::write(
        &suite,
        "name = \"tiny\"\n[defaults]\nt_end = 1e-14\nsamples = 11\n[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\n",
    )
    .unwrap();
    let out = run(
        &[
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&d.join("report")),
            "--jobs",
            "1",
        ],
        Limits {
            guard_seconds: 120,
            memory_mib: Some(2048),
            ..Limits::default()
        },
    );
    assert!(matches!(code(&out), Some(0) | Some(1)), "{}", stderr(&out));
    assert!(d.join("report/report.json").is_file());
}

// ---- 5. dense output at many samples ---------------------------------------------------------

#[test]
fn d05_dense_output_at_twenty_thousand_samples_hits_every_grid_time() {
    for method in ["dop853", "dopri5"] {
        let out = run(
            &[
                "integrate",
                "--samples",
                "20000",
                "--t-end",
                "10",
                "--method",
                method,
                "--format",
                "csv",
            ],
            Limits::default(),
        );
        assert_eq!(code(&out), Some(0), "{method}: {}", stderr(&out));
        let text = stdout(&out);
        let rows: Vec<&str> = text.lines().skip(1).collect();
        assert_eq!(rows.len(), 20000);
        for (k, row) in rows.iter().enumerate() {
            let t: f64 = row.split(',').next().unwrap().parse().unwrap();
            let want = 10.0 * k as f64 / 19999.0;
            assert!(
                (t - want).abs() <= 4.0 * f64::EPSILON * 10.0,
                "{method} row {k}: t = {t}"
            );
        }
    }
    for cmd in [
        vec![
            "compare",
            "--t-end",
            "10",
            "--samples",
            "20000",
            "--format",
            "json",
        ],
        vec![
            "bench",
            "--t-end",
            "10",
            "--samples",
            "20000",
            "--methods",
            "dopri5",
            "--tolerances",
            "1e-8",
            "--repeats",
            "1",
            "--format",
            "json",
        ],
    ] {
        let out = run(&cmd, Limits::default());
        assert_eq!(code(&out), Some(0), "{cmd:?}: {}", stderr(&out));
    }
}

// ---- 6. points on Σ --------------------------------------------------------------------------

/// Points exactly on Σ for a = 1, b = 0.5, typed as decimals (rounded to f64 on input), with
/// the line each lies on.
const ON_SIGMA: [(&str, &str, &str); 4] = [
    ("0.2", "-1.15", "h = −r²m − 2b"),
    ("0.3", "2.225", "h = r²m + 2a"),
    ("0.3", "0.775", "h = −r²m + 2b"),
    ("-0.6666666666666666", "1.5", "h = r²m + 2a"),
];

#[test]
fn d06_points_on_sigma_are_refused_by_every_command_naming_the_line() {
    let d = dir("d06");
    for (m, h, line) in ON_SIGMA {
        let runs: Vec<Vec<&str>> = vec![
            vec!["diagram", "--m", m, "--h", h],
            vec!["explicit", "--m", m, "--h", h, "--samples", "2"],
            vec![
                "compare",
                "--m",
                m,
                "--h",
                h,
                "--samples",
                "2",
                "--t-end",
                "1",
            ],
            vec![
                "bench",
                "--m",
                m,
                "--h",
                h,
                "--samples",
                "2",
                "--t-end",
                "1",
                "--repeats",
                "1",
            ],
            vec!["surfaces", "--m", m, "--h", h, "--out", s(&d)],
        ];
        for args in runs {
            let out = rsts(&args);
            assert_eq!(code(&out), Some(2), "{args:?}: {}", stdout(&out));
            let err = stderr(&out);
            assert!(err.contains("Σ") && err.contains(line), "{args:?}: {err}");
            assert_short_numbers(&err);
        }
    }
    assert!(entries(&d).is_empty(), "{:?}", entries(&d));
}

#[test]
fn d06_points_a_billionth_off_sigma_stay_valid_hard_cases() {
    for (m, h) in [
        ("0.2", "-1.149999999"),
        ("0.3", "2.225000001"),
        ("0.300000001", "0.775"),
    ] {
        for args in [
            vec!["diagram", "--m", m, "--h", h],
            vec![
                "explicit",
                "--m",
                m,
                "--h",
                h,
                "--samples",
                "3",
                "--t-end",
                "1",
            ],
        ] {
            let out = rsts(&args);
            assert_eq!(code(&out), Some(0), "{args:?}: {}", stderr(&out));
        }
    }
}

#[test]
fn d06_huge_m_and_h_are_refused_with_the_documented_range() {
    for (m, h, opt) in [
        ("1e308", "1e308", "--m"),
        ("0.3", "1e300", "--h"),
        ("-1e12", "5", "--m"),
    ] {
        let out = rsts(&["diagram", "--m", m, "--h", h]);
        assert_eq!(code(&out), Some(2), "{m} {h}");
        let err = stderr(&out);
        assert!(err.contains(opt) && !err.contains("residual"), "{err}");
        assert_short_numbers(&err);
    }
    for (a, b) in [("1e300", "0.5"), ("1", "1e-300")] {
        let out = rsts(&["explicit", "--a", a, "--b", b, "--samples", "2"]);
        assert_eq!(code(&out), Some(2), "{a} {b}");
        assert_short_numbers(&stderr(&out));
    }
}

// ---- 7. non-finite results -------------------------------------------------------------------

#[test]
fn d07_no_nan_or_inf_is_printed_with_exit_0() {
    for args in [
        vec!["integrate", "--rtol", "1e300", "--format", "csv"],
        vec![
            "integrate",
            "--rtol",
            "0.5",
            "--atol",
            "1e300",
            "--format",
            "json",
        ],
        vec![
            "integrate",
            "--omega",
            "1e200,1e200,1e200",
            "--format",
            "csv",
        ],
        vec!["explicit", "--t-end", "1e308", "--samples", "3"],
        vec![
            "explicit",
            "--t-end",
            "1e308",
            "--samples",
            "3",
            "--format",
            "json",
        ],
    ] {
        let out = run(
            &args,
            Limits {
                guard_seconds: 60,
                ..Limits::default()
            },
        );
        if code(&out) == Some(0) {
            assert_finite_text(&stdout(&out));
        } else {
            assert_eq!(code(&out), Some(2), "{args:?}");
            let err = stderr(&out);
            assert!(!err.contains("panicked"), "{err}");
        }
    }
}

#[test]
fn d07_explicit_at_a_huge_time_is_the_motion_at_that_time() {
    // t = 1e300 used to give the state at t = 0; the f64 and the 40-digit runs must agree.
    let f64_run = rsts(&[
        "explicit",
        "--t-end",
        "1e300",
        "--samples",
        "2",
        "--format",
        "json",
    ]);
    assert_eq!(code(&f64_run), Some(0), "{}", stderr(&f64_run));
    // The same motion at the same time: the exact decimal values of the f64 numbers 1e300 and
    // 0.3 (the decimal 10^300 is another time, ~1e284 away, and the decimal 0.3 another motion,
    // whose phase at t = 1e300 is unrelated).
    let t_exact = format!("{:.0}", 1e300_f64);
    let m_exact = format!("{:.60}", 0.3_f64);
    let mp_run = rsts(&[
        "explicit",
        "--t-end",
        &t_exact,
        "--m",
        &m_exact,
        "--samples",
        "2",
        "--digits",
        "40",
        "--format",
        "json",
    ]);
    assert_eq!(code(&mp_run), Some(0), "{}", stderr(&mp_run));
    let a: Value = serde_json::from_slice(&f64_run.stdout).unwrap();
    let b: Value = serde_json::from_slice(&mp_run.stdout).unwrap();
    let num = |v: &Value| -> f64 {
        v.as_f64()
            .or_else(|| v.as_str().and_then(|s| s.parse().ok()))
            .unwrap()
    };
    let (w0, w1) = (
        num(&a["samples"][0]["omega"][0]),
        num(&a["samples"][1]["omega"][0]),
    );
    let w1_mp = num(&b["samples"][1]["omega"][0]);
    assert!((w1 - w1_mp).abs() < 1e-12, "f64 {w1} vs 40 digits {w1_mp}");
    assert!(
        (w1 - w0).abs() > 1e-6,
        "the state at t = 1e300 is the state at t = 0"
    );
    assert_eq!(num(&a["samples"][1]["t"]), 1e300);
}

/// `reference` and `check` at t = 1e300 follow the motion too (they used to give the state at
/// t = 0: the phase clock lacked the bits of so large a time): reference agrees with explicit
/// there, and check finds a reference trajectory reaching 1e300 exact.
#[test]
fn d07_reference_and_check_at_a_huge_time_follow_the_motion() {
    let d = dir("d07-ref");
    let json = |args: &[&str]| -> Value {
        let out = rsts(args);
        assert_eq!(code(&out), Some(0), "{args:?}: {}", stderr(&out));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let e = json(&[
        "explicit",
        "--t-end",
        "1e300",
        "--samples",
        "2",
        "--format",
        "json",
    ]);
    let r = json(&["reference", "--times", "0,1e300", "--format", "json"]);
    let w = |v: &Value, k: usize| v["samples"][k]["omega"][0].as_f64().unwrap();
    assert!(
        (w(&r, 1) - w(&e, 1)).abs() < 1e-12,
        "{} vs {}",
        w(&r, 1),
        w(&e, 1)
    );
    assert!(
        (w(&r, 1) - w(&r, 0)).abs() > 1e-6,
        "the state at 1e300 is the one at 0"
    );
    let traj = d.join("huge.csv");
    let out = rsts(&["reference", "--times", "0,1,1e300", "-o", s(&traj)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    for motion in [vec![], vec!["--m", "0.3", "--h", "-0.375"]] {
        let mut args = vec!["check", s(&traj), "--format", "json"];
        args.extend(motion);
        let c = json(&args);
        let err = c["max_state_error"].as_f64().unwrap();
        assert!(err < 1e-12, "{args:?}: max state error {err:e}");
    }
}

// ---- 8. disk full, unwritable places ---------------------------------------------------------

#[test]
fn d08_a_full_disk_leaves_no_partial_file_and_keeps_the_os_error() {
    let d = dir("d08");
    let limits = Limits {
        guard_seconds: 120,
        file_bytes: Some(20_000),
        ..Limits::default()
    };
    let ref_json = d.join("ref.json");
    let runs: Vec<Vec<String>> = vec![
        vec!["compare", "--t-end", "20", "--samples", "400", "--mcap"]
            .into_iter()
            .map(String::from)
            .chain([s(&d.join("x.mcap")).to_string()])
            .collect(),
        vec![
            "diagram".into(),
            "--svg".into(),
            s(&d.join("d.svg")).to_string(),
        ],
        vec![
            "reference".into(),
            "--t-end".into(),
            "20".into(),
            "--samples".into(),
            "400".into(),
            "--format".into(),
            "json".into(),
            "-o".into(),
            s(&ref_json).to_string(),
        ],
        vec![
            "surfaces".into(),
            "--m".into(),
            "0.3".into(),
            "--h".into(),
            "-0.375".into(),
            "--out".into(),
            s(&d.join("surf")).to_string(),
        ],
    ];
    for args in runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = run(&args, limits);
        assert_eq!(code(&out), Some(2), "{args:?}");
        let err = stderr(&out);
        assert!(err.contains("File too large"), "{args:?}: {err}");
        assert!(!err.contains("attempted another write"), "{err}");
    }
    for name in ["x.mcap", "d.svg", "ref.json"] {
        assert!(!d.join(name).exists(), "{name} left behind");
    }
    if d.join("surf").exists() {
        for e in entries(&d.join("surf")) {
            let p = d.join("surf").join(&e);
            // Only whole files: every PLY ends with its last face line, every PNG with IEND.
            let bytes = fs::read(&p).unwrap();
            if e.ends_with(".png") {
                assert!(bytes.ends_with(&[0xAE, 0x42, 0x60, 0x82]), "{e} partial");
            }
        }
    }
    assert_no_temporaries(&d);
}

#[test]
fn d08_an_unwritable_report_directory_fails_before_the_suite_runs() {
    let d = dir("d08-report");
    // A suite whose only run fails: had it run, stderr would name it ("ERROR c-...").
    let suite = d.join("s.toml");
    fs::write(
        &suite,
        "name = \"s\"\n[defaults]\nt_end = 1\nsamples = 3\n[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\nmethods = [\"taylor-f64\"]\ntolerances = [1e-30]\n",
    )
    .unwrap();
    for report in ["/proc/x", "/dev/null/report"] {
        let out = rsts(&["validate", "--suite", s(&suite), "--report", report]);
        assert_eq!(code(&out), Some(2), "{}", stderr(&out));
        let err = stderr(&out);
        assert!(err.contains("--report") && !err.contains("ERROR"), "{err}");
    }
}

#[test]
fn d08_an_over_long_case_name_still_gives_a_report() {
    let d = dir("d08-long");
    let name = "c".repeat(300);
    let suite = d.join("s.toml");
    fs::write(
        &suite,
        format!(
            "name = \"s\"\n[defaults]\nt_end = 1\nsamples = 3\n[[case]]\nname = \"{name}\"\nm = 0.3\nh = -0.375\n"
        ),
    )
    .unwrap();
    let report = d.join("report");
    let out = rsts(&["validate", "--suite", s(&suite), "--report", s(&report)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let v: Value = serde_json::from_slice(&fs::read(report.join("report.json")).unwrap()).unwrap();
    assert_eq!(v["runs"][0]["case"], name.as_str());
    assert_no_temporaries(&d);
}

// ---- 9. hopeless jobs refused up front -------------------------------------------------------

#[test]
fn d09_hopeless_jobs_are_refused_at_once_with_the_reason() {
    let d = dir("d09");
    let limits = Limits {
        guard_seconds: 30,
        ..Limits::default()
    };
    let suite = concat!(env!("CARGO_MANIFEST_DIR"), "/../../validation/quick.toml");
    let report = d.join("r");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "compare",
                "--rtol",
                "1e-30",
                "--atol",
                "1e-30",
                "--samples",
                "3",
            ],
            "--rtol",
        ),
        (
            vec!["integrate", "--rtol", "1e-30", "--atol", "1e-30"],
            "--rtol",
        ),
        (
            vec!["compare", "--t-end", "1e12", "--samples", "3"],
            "steps",
        ),
        (
            vec!["integrate", "--t-end", "1e12", "--samples", "3"],
            "steps",
        ),
        (
            vec!["integrate", "--t-end", "1e9", "--method", "taylor-f64"],
            "steps",
        ),
        (
            vec![
                "validate",
                "--suite",
                suite,
                "--report",
                s(&report),
                "--jobs",
                "10000",
            ],
            "--jobs",
        ),
        (vec!["bench", "--repeats", "1000000000"], "--repeats"),
        (
            // Camera V has four tori: the largest settings would write over 1 GB.
            vec![
                "surfaces",
                "--m",
                "-0.7092",
                "--h",
                "1.5643",
                "--out",
                s(&report),
                "--grid",
                "512",
                "--scene-grid",
                "256",
                "--samples",
                "1000000",
                "--size",
                "1200",
            ],
            "bytes",
        ),
        (
            vec![
                "surfaces",
                "--m",
                "0.3",
                "--h",
                "-0.375",
                "--out",
                s(&report),
                "--grid",
                "1024",
            ],
            "--grid",
        ),
    ];
    for (args, needle) in cases {
        let out = run(&args, limits);
        assert_eq!(code(&out), Some(2), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert_short_numbers(&err);
    }
    assert!(!report.exists());
}

// ---- 11. output formats ----------------------------------------------------------------------

#[test]
fn d11_json_on_stdout_is_one_document_even_with_an_mcap_file() {
    let d = dir("d11");
    let out = rsts(&[
        "compare",
        "--t-end",
        "5",
        "--samples",
        "11",
        "--format",
        "json",
        "--mcap",
        s(&d.join("j.mcap")),
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let v: Value =
        serde_json::from_slice(&out.stdout).expect("stdout is exactly one JSON document");
    assert!(v["mcap"].as_str().unwrap().ends_with("j.mcap"));
}

/// The rows of a CSV document (RFC 4180 quoting; no line breaks inside fields here).
fn csv(out: &Output) -> Vec<Vec<String>> {
    stdout(out)
        .lines()
        .map(|line| {
            let mut fields = vec![String::new()];
            let mut quoted = false;
            let mut chars = line.chars().peekable();
            while let Some(c) = chars.next() {
                match c {
                    '"' if quoted && chars.peek() == Some(&'"') => {
                        chars.next();
                        fields.last_mut().unwrap().push('"');
                    }
                    '"' => quoted = !quoted,
                    ',' if !quoted => fields.push(String::new()),
                    c => fields.last_mut().unwrap().push(c),
                }
            }
            fields
        })
        .collect()
}

#[test]
fn d11_every_listed_csv_format_is_csv() {
    let d = dir("d11-csv");
    let mcap = small_compare_log(&d);
    for args in [
        vec![
            "compare",
            "--t-end",
            "2",
            "--samples",
            "5",
            "--format",
            "csv",
        ],
        vec!["diagram", "--m", "0.3", "--h", "-0.375", "--format", "csv"],
        vec![
            "inspect",
            s(&mcap),
            "--channel",
            "/errors",
            "--format",
            "csv",
        ],
        vec!["integrate", "--format", "csv"],
        vec!["explicit", "--format", "csv"],
    ] {
        let out = rsts(&args);
        assert_eq!(code(&out), Some(0), "{args:?}: {}", stderr(&out));
        let rows = csv(&out);
        assert!(rows.len() >= 2, "{args:?}: {}", stdout(&out));
        for r in &rows {
            assert_eq!(
                r.len(),
                rows[0].len(),
                "{args:?}: ragged CSV\n{}",
                stdout(&out)
            );
        }
        // Every data cell is a number or a plain word, never an aligned table cell.
        assert!(!stdout(&out).contains("  "), "{args:?}: a table, not CSV");
    }
}

#[test]
fn d11_inspect_json_without_channel_is_the_summary_as_json() {
    let d = dir("d11-inspect");
    let mcap = small_compare_log(&d);
    let out = rsts(&["inspect", s(&mcap), "--format", "json"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON summary");
    assert_eq!(v["recovered"], false);
    assert!(v["channels"].as_array().unwrap().len() >= 5);
}

#[test]
fn d11_one_column_naming_and_json_numbers_as_numbers() {
    let state = [
        "t", "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
    ];
    for args in [
        vec!["integrate", "--format", "csv"],
        vec!["explicit", "--format", "csv"],
    ] {
        let out = rsts(&args);
        let header = csv(&out)[0].clone();
        assert_eq!(&header[..10], &state, "{args:?}");
    }
    let d = dir("d11-names");
    let mcap = small_compare_log(&d);
    let out = rsts(&[
        "inspect",
        s(&mcap),
        "--channel",
        "/exact/state",
        "--format",
        "csv",
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let header = csv(&out)[0].clone();
    assert_eq!(&header[..10], &state, "inspect /exact/state");
    assert!(!header.iter().any(|h| h.contains('.')), "{header:?}");

    // explicit in f64: numbers; at 40 digits: decimal strings (digits beyond f64).
    let out = rsts(&["explicit", "--samples", "2", "--format", "json"]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    for x in [
        &v["a"],
        &v["m"],
        &v["samples"][1]["t"],
        &v["samples"][1]["omega"][0],
    ] {
        assert!(x.is_number(), "{x}");
    }
    let out = rsts(&[
        "explicit",
        "--samples",
        "2",
        "--digits",
        "40",
        "--format",
        "json",
    ]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let w = v["samples"][1]["omega"][0]
        .as_str()
        .expect("a decimal string");
    assert!(w.len() > 30, "{w}");
}

// ---- 12. Ctrl-C ------------------------------------------------------------------------------

fn interrupt(child: &Child) {
    // SAFETY: plain kill(2) on our own child.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
}

#[test]
fn d12_ctrl_c_at_any_moment_leaves_the_old_file_or_a_complete_new_one() {
    let d = dir("d12");
    let target = d.join("c.mcap");
    let args = [
        "compare",
        "--t-end",
        "200",
        "--samples",
        "4001",
        "--mcap",
        s(&target),
    ];
    for delay_ms in [0u64, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 400] {
        let _ = fs::remove_file(&target);
        let child = command(&args, Limits::default()).spawn().unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        interrupt(&child);
        let out = wait_guarded(child, 120, "compare (interrupted)");
        // 0 (done), 130 (stopped), or killed by SIGINT before the handler was installed
        // (the first thing `main` does, before any file exists).
        use std::os::unix::process::ExitStatusExt;
        assert!(
            matches!(code(&out), Some(0) | Some(130)) || out.status.signal() == Some(libc::SIGINT),
            "{delay_ms} ms: {:?} {}",
            out.status,
            stderr(&out)
        );
        if target.exists() {
            assert_complete_mcap(&target);
        }
        assert_no_temporaries(&d);
    }
}

#[test]
fn d12_a_second_ctrl_c_exits_130_and_removes_the_temporary() {
    let d = dir("d12-twice");
    let target = d.join("c.mcap");
    fs::write(&target, b"previous").unwrap();
    let child = command(
        &[
            "compare",
            "--t-end",
            "2000",
            "--samples",
            "20001",
            "--method",
            "taylor-mp",
            "--mcap",
            s(&target),
        ],
        Limits::default(),
    )
    .spawn()
    .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    interrupt(&child);
    std::thread::sleep(Duration::from_millis(20));
    interrupt(&child);
    let out = wait_guarded(child, 120, "compare (interrupted twice)");
    assert_eq!(code(&out), Some(130), "{}", stderr(&out));
    let now = fs::read(&target).unwrap();
    assert!(
        now == b"previous" || rsts(&["inspect", s(&target)]).status.success(),
        "neither the old file nor a complete new one"
    );
    assert_no_temporaries(&d);
}

// ---- 10. inspect: CRCs, exit codes, truncation -----------------------------------------------

/// A complete log of a short comparison.
fn small_log(d: &Path) -> (PathBuf, Vec<u8>) {
    let p = d.join("ok.mcap");
    let out = rsts(&[
        "compare",
        "--t-end",
        "5",
        "--samples",
        "50",
        "--mcap",
        s(&p),
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let bytes = fs::read(&p).unwrap();
    (p, bytes)
}

#[test]
fn d10_a_flipped_byte_anywhere_is_damage_with_or_without_channel() {
    let d = dir("d10-flip");
    let (_, bytes) = small_log(&d);
    let bad = d.join("bad.mcap");
    // Offsets spread over the file, the summary and the footer included.
    let n = bytes.len();
    let mut offsets: Vec<usize> = (0..40).map(|k| 8 + k * (n - 16) / 40).collect();
    offsets.extend([n - 9, n - 20, n - 30, n - 100, n - 300]);
    for off in offsets {
        let mut b = bytes.clone();
        b[off] ^= 0x10;
        fs::write(&bad, &b).unwrap();
        let plain = rsts(&["inspect", s(&bad)]);
        let chan = rsts(&["inspect", s(&bad), "--channel", "/errors"]);
        assert_eq!(code(&plain), Some(3), "offset {off}: {}", stdout(&plain));
        assert_eq!(code(&chan), code(&plain), "offset {off}: {}", stderr(&chan));
    }
}

#[test]
fn d10_a_file_cut_anywhere_says_truncated_at_byte_n() {
    let d = dir("d10-cut");
    let (_, bytes) = small_log(&d);
    let cut = d.join("cut.mcap");
    let n = bytes.len();
    let mut lengths: Vec<usize> = (0..30).map(|k| 8 + k * (n - 9) / 30).collect();
    lengths.extend([9, 100, 600, n - 1, n - 8, n - 30, n - 200]);
    for len in lengths {
        fs::write(&cut, &bytes[..len]).unwrap();
        for args in [
            vec!["inspect", s(&cut)],
            vec!["inspect", s(&cut), "--channel", "/errors"],
            vec![
                "inspect",
                s(&cut),
                "--channel",
                "/errors",
                "--format",
                "json",
            ],
        ] {
            let out = rsts(&args);
            assert_eq!(
                code(&out),
                Some(3),
                "cut at {len}: {args:?} {}",
                stderr(&out)
            );
            let err = stderr(&out);
            assert!(
                err.contains(&format!("truncated at byte {len}")),
                "cut at {len}: {args:?}: {err}"
            );
        }
    }
}

// ---- issue 35: bounded on every input, an input never overwritten ----------------------------
//
// Each test below failed on the code before its fix (commit f3e7973): the memory ones ran out
// of their address-space limit (exit 134) or ran past their guard, the others exited 0 having
// done the wrong thing.

/// `rsts reference --times 0,1 --format json`: the exact samples of the default case at 0 and
/// 1, the samples of a correct answer to `compare --t-end 1 --samples 2`.
fn exact_samples() -> Value {
    let out = rsts(&["reference", "--times", "0,1", "--format", "json"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    doc["samples"].clone()
}

/// An adapter that reads its request and answers `prefix`, then `n` bytes of `0,0,0,…`, then
/// `suffix`: an answer of any size made without holding it.
fn zeros_adapter(d: &Path, name: &str, prefix: &str, n: u64, suffix: &str) -> String {
    assert_eq!(n % 2, 0);
    script(
        d,
        name,
        &format!(
            "cat >/dev/null\nprintf '%s' '{prefix}'\nyes 0, | tr -d '\\n' | head -c {n}\nprintf '%s' '0{suffix}'"
        ),
    )
}

#[test]
fn r35_2_a_dense_answer_of_100_mb_is_read_in_memory_of_its_size() {
    // 100 MB of `"dense": [0, 0, …]`: 3.2 GB before (a serde_json::Value per number, then a
    // copy of the list); under 1 GiB of address space it aborted (exit 134).
    let d = dir("r35-2-dense");
    let adapter = zeros_adapter(&d, "dense.sh", "{\"dense\": [", 100_000_000, "]}");
    let out = run(
        &[
            "compare",
            "--exec",
            &adapter,
            "--dense",
            "1",
            "--t-end",
            "1",
            "--samples",
            "2",
        ],
        Limits {
            guard_seconds: 120,
            memory_mib: Some(1024),
            ..Limits::default()
        },
    );
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{err}");
    assert!(err.contains("no \"stats.step_times\""), "{err}");
}

#[test]
fn r35_2_a_junk_answer_is_skipped_not_held() {
    // 45 MB of junk in "name" (the request's 20000 samples allow 47 MB): 741 MB before.
    let d = dir("r35-2-junk");
    let adapter = zeros_adapter(&d, "junk.sh", "{\"name\": [", 45_000_000, "]}");
    let out = run(
        &[
            "compare",
            "--exec",
            &adapter,
            "--t-end",
            "1",
            "--samples",
            "20000",
        ],
        Limits {
            guard_seconds: 120,
            memory_mib: Some(400),
            ..Limits::default()
        },
    );
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{err}");
    assert!(err.contains("\"name\" must be a non-empty string"), "{err}");
    // The same junk under a key rsts does not read is skipped: the answer is good.
    let mut answer = serde_json::json!({ "samples": exact_samples() }).to_string();
    answer.pop();
    let prefix = format!("{answer}, \"junk\": [");
    let adapter = zeros_adapter(&d, "junk-key.sh", &prefix, 45_000_000, "]}");
    let out = run(
        &[
            "compare",
            "--exec",
            &adapter,
            "--t-end",
            "1",
            "--samples",
            "2",
        ],
        Limits {
            guard_seconds: 120,
            memory_mib: Some(400),
            ..Limits::default()
        },
    );
    // Two samples allow 1 MiB: the flood is cut off, as before, without being parsed.
    assert_eq!(code(&out), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("its answer passed"),
        "{}",
        stderr(&out)
    );
}

/// `d/traj.csv`: the default motion at 0, 0.5, 1.
fn traj_csv(d: &Path) -> PathBuf {
    let traj = d.join("traj.csv");
    let out = rsts(&["reference", "--times", "0,0.5,1", "-o", s(&traj)]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    traj
}

#[test]
fn r35_4_an_output_that_is_an_input_is_refused_and_nothing_is_touched() {
    let d = dir("r35-4");
    let traj = traj_csv(&d);
    let before = fs::read(&traj).unwrap();
    let hard = d.join("hard.csv");
    fs::hard_link(&traj, &hard).unwrap();
    let soft = d.join("soft.mcap");
    std::os::unix::fs::symlink(&traj, &soft).unwrap();
    let times = d.join("t.txt");
    fs::write(&times, "0 0.5 1\n").unwrap();
    let times_link = d.join("t-link.txt");
    std::os::unix::fs::symlink(&times, &times_link).unwrap();
    let events = d.join("ev.csv");
    fs::write(&events, "name,t\nomega1,0.5\n").unwrap();
    let adapter = script(&d, "adapter.sh", "cat >/dev/null; exit 1");
    let cases: Vec<(Vec<&str>, &str, &Path)> = vec![
        (vec!["check", s(&traj), "--mcap", s(&traj)], "--mcap", &traj),
        (
            vec!["check", s(&traj), "--mcap", s(&hard)],
            "hard link",
            &traj,
        ),
        (
            vec!["check", s(&traj), "--mcap", s(&soft)],
            "symbolic link",
            &traj,
        ),
        (
            vec![
                "check",
                s(&traj),
                "--events",
                s(&events),
                "--mcap",
                s(&events),
            ],
            "--events",
            &events,
        ),
        (
            vec!["reference", "--times-file", s(&times), "-o", s(&times)],
            "--times-file",
            &times,
        ),
        (
            vec!["reference", "--times-file", s(&times), "-o", s(&times_link)],
            "symbolic link",
            &times,
        ),
        (
            vec!["compare", "--exec", &adapter, "--mcap", &adapter],
            "--exec",
            Path::new(&adapter),
        ),
    ];
    for (args, needle, input) in cases {
        let kept = fs::read(input).unwrap();
        let out = run(&args, Limits::default());
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(needle) && err.contains("destroy the input"),
            "{args:?}: {err}"
        );
        assert_eq!(fs::read(input).unwrap(), kept, "{args:?} changed the input");
    }
    assert_eq!(fs::read(&traj).unwrap(), before);
    // Two outputs that are one file.
    let svg = d.join("x.svg");
    let out = run(
        &["bench", "--svg", s(&svg), "--svg-tolerance", s(&svg)],
        Limits::default(),
    );
    assert_eq!(code(&out), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("are one file"), "{}", stderr(&out));
    assert_no_temporaries(&d);
}

#[test]
fn r35_4_a_report_directory_holding_an_input_is_refused() {
    let d = dir("r35-4-validate");
    let suite = d.join("s.toml");
    fs::write(
        &suite,
        "name = \"s\"\n[defaults]\nt_end = 1.0\nsamples = 3\n[[case]]\nname = \"a\"\ncamera = \"I+\"\nm = 0.3\nh = -0.375\nmethods = [\"dop853\"]\ntolerances = [1e-8]\n",
    )
    .unwrap();
    let report = d.join("r");
    let out = run(
        &["validate", "--suite", s(&suite), "--report", s(&report)],
        Limits::default(),
    );
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let base = report.join("report.json");
    let before = fs::read(&base).unwrap();
    for args in [
        vec![
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&report),
            "--baseline",
            s(&base),
        ],
        vec!["validate", "merge", s(&report), "--report", s(&report)],
    ] {
        let out = run(&args, Limits::default());
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("--report") && err.contains("holds the input"),
            "{args:?}: {err}"
        );
        assert_eq!(
            fs::read(&base).unwrap(),
            before,
            "{args:?} replaced the report"
        );
    }
}

#[test]
fn r35_5_inputs_read_whole_are_bounded_before_reading() {
    let d = dir("r35-5");
    let traj = traj_csv(&d);
    // 3 GiB that take no room: refused from its size, before a byte is read.
    let sparse = d.join("sparse.json");
    fs::File::create(&sparse).unwrap().set_len(3 << 30).unwrap();
    let limits = Limits {
        guard_seconds: 60,
        memory_mib: Some(512),
        ..Limits::default()
    };
    for input in [s(&sparse), "/dev/zero"] {
        for args in [
            vec!["check", s(&traj), "--events", input],
            vec!["reference", "--times-file", input],
            vec!["inspect", input],
            vec!["validate", "merge", input, "--report", s(&d.join("m"))],
        ] {
            let out = run(&args, limits);
            let err = stderr(&out);
            assert_eq!(code(&out), Some(2), "{args:?}: {err}");
            // A device of zeros is not MCAP, nor JSON: refused at its first bytes.
            assert!(
                err.contains("larger than the")
                    || err.contains("longer than")
                    || err.contains("does not start with the MCAP magic")
                    || err.contains("is not a validation report"),
                "{args:?}: {err}"
            );
        }
    }
    let suite = d.join("s.toml");
    fs::write(
        &suite,
        "[[case]]\nname = \"a\"\ncamera = \"I+\"\nm = 0.3\nh = -0.375\nmethods = [\"dop853\"]\n",
    )
    .unwrap();
    let report = d.join("r");
    for input in [s(&sparse), "/dev/zero"] {
        let args = [
            "validate",
            "--suite",
            s(&suite),
            "--report",
            s(&report),
            "--baseline",
            input,
        ];
        let out = run(&args, limits);
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("larger than the") || err.contains("is not a validation report"),
            "{args:?}: {err}"
        );
    }
}

/// An npy file of version `major` whose header length field says `len` bytes (8 KB in all).
fn npy_with_header_length(major: u8, len: u32) -> Vec<u8> {
    let mut b = b"\x93NUMPY".to_vec();
    b.extend([major, 0]);
    b.extend(len.to_le_bytes());
    b.resize(8192, b' ');
    b
}

#[test]
fn r35_6_an_npy_header_length_is_bounded_before_the_npy_library_reads_it() {
    // 0xfffffff0: npyz allocated 4 GiB first (exit 134 under any address-space limit).
    let d = dir("r35-6");
    let limits = Limits {
        guard_seconds: 60,
        memory_mib: Some(1024),
        ..Limits::default()
    };
    for major in [2, 3] {
        let path = d.join(format!("v{major}.npy"));
        fs::write(&path, npy_with_header_length(major, 0xffff_fff0)).unwrap();
        let out = run(&["check", s(&path)], limits);
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{err}");
        assert!(err.contains("4294967280 bytes long"), "{err}");
        // The same bytes on standard input.
        let mut cmd = command(&["check", "-", "--input-format", "npy"], limits);
        cmd.stdin(fs::File::open(&path).unwrap());
        let out = wait_guarded(cmd.spawn().unwrap(), 60, "check - (npy)");
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{err}");
        assert!(err.contains("4294967280 bytes long"), "{err}");
    }
}

#[test]
fn r35_8_events_are_sized_before_they_are_computed() {
    // ~28000 turning points of s2 at 10000 digits: 2.8 GB of output. It used to start (hours of
    // work, every event held); it is refused at once with the estimate.
    let out = run(
        &[
            "events", "--event", "s2", "--t-end", "1e5", "--digits", "10000", "--format", "csv",
        ],
        Limits {
            guard_seconds: 60,
            memory_mib: Some(1024),
            ..Limits::default()
        },
    );
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{err}");
    assert!(err.contains("the events would take about"), "{err}");
    assert_short_numbers(&err);
}

#[test]
fn r35_8_events_are_written_as_they_are_found() {
    // 41000 turning points of s1 and s2 at 50 digits (23 MB of CSV): every event was held until
    // the end (79 MB peak); now a piece of the window at a time (7 MB, measured).
    let time = Path::new("/usr/bin/time");
    if !time.exists() {
        rsts_io::report_skip(
            "r35_8_events_are_written_as_they_are_found",
            "/usr/bin/time is not installed",
        );
        return;
    }
    let d = dir("r35-8");
    let peak = d.join("peak");
    let child = Command::new(time)
        .args(["-f", "%M", "-o", s(&peak), env!("CARGO_BIN_EXE_rsts")])
        .args([
            "events", "--event", "s1", "--event", "s2", "--t-end", "60000", "--digits", "50",
            "--format", "csv",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = wait_guarded(child, 300, "events --t-end 60000");
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let rows = out.stdout.iter().filter(|&&b| b == b'\n').count() - 1;
    assert!(rows > 40_000, "{rows} events");
    let kb: u64 = fs::read_to_string(&peak).unwrap().trim().parse().unwrap();
    assert!(
        kb < 25_000,
        "peak {kb} KB for {} bytes of events",
        out.stdout.len()
    );
}

#[test]
fn r35_9_jobs_are_capped_at_eight_per_core() {
    let d = dir("r35-9");
    let traj = traj_csv(&d);
    // Under 256 MiB of address space: the old code started threads until it ran out.
    let limits = Limits {
        guard_seconds: 30,
        memory_mib: Some(256),
        ..Limits::default()
    };
    for args in [
        vec!["check", s(&traj), "--jobs", "100000"],
        vec!["reference", "--times", "0,1", "--jobs", "100000"],
    ] {
        let out = run(&args, limits);
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {err}");
        assert!(err.contains("threads (8 per core"), "{args:?}: {err}");
    }
    let help = rsts(&["check", "--help"]);
    assert!(
        stdout(&help).contains("at most 8 per core"),
        "{}",
        stdout(&help)
    );
}

#[test]
fn r35_10_dense_step_times_cover_the_run_and_a_run_of_no_step_is_refused() {
    let d = dir("r35-10-dense");
    let samples = exact_samples();
    let states: Vec<Value> = samples.as_array().unwrap().clone();
    // Step times [0]: no step, no dense sample — reported as dense_max_error 0 before.
    // Step times [0, 0.5] for a run to t = 1: half the run — accepted before.
    let half = {
        let mut s0 = states[1].clone();
        s0["t"] = serde_json::json!(0.25);
        let mut s1 = states[1].clone();
        s1["t"] = serde_json::json!(0.5);
        vec![s0, s1]
    };
    for (step_times, dense) in [(vec![0.0], vec![]), (vec![0.0, 0.5], half)] {
        let answer = serde_json::json!({
            "samples": samples, "stats": {"step_times": step_times}, "dense": dense,
        });
        let file = d.join("answer.json");
        fs::write(&file, answer.to_string()).unwrap();
        let adapter = script(&d, "a.sh", &format!("cat >/dev/null; cat '{}'", s(&file)));
        let out = run(
            &[
                "compare",
                "--exec",
                &adapter,
                "--dense",
                "1",
                "--t-end",
                "1",
                "--samples",
                "2",
                "--format",
                "json",
            ],
            Limits::default(),
        );
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{step_times:?}: {}{err}", stdout(&out));
        assert!(err.contains("stats.step_times ends at"), "{err}");
    }
}

#[test]
fn r35_10_times_of_one_double_and_times_that_round_to_zero_are_refused() {
    let d = dir("r35-10-times");
    let traj = traj_csv(&d);
    let text = fs::read_to_string(&traj).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for (t1, t2, needle) in [
        ("0.1", "0.10000000000000001", "both are the double 0.1"),
        ("0", "1e-400", "rounds to 0 as f64"),
    ] {
        // Rows 2 and 3 (the states at 0.5 and 1) at times t1 and t2.
        for (k, t) in [(2, t1), (3, t2)] {
            let rest = lines[k].split_once(',').unwrap().1.to_string();
            lines[k] = format!("{t},{rest}");
        }
        if t1 == "0" {
            // Row 1 at -1: 0 then 1e-400 follow it.
            let rest = lines[1].split_once(',').unwrap().1.to_string();
            lines[1] = format!("-1,{rest}");
        }
        let bad = d.join("bad.csv");
        fs::write(&bad, lines.join("\n") + "\n").unwrap();
        let out = run(
            &["check", s(&bad), "--m", "0.3", "--h", "-0.375"],
            Limits::default(),
        );
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{t1} {t2}: {err}");
        assert!(err.contains("line 4") && err.contains(needle), "{err}");
        let mut cmd = command(
            &[
                "check",
                "-",
                "--input-format",
                "csv",
                "--m",
                "0.3",
                "--h",
                "-0.375",
            ],
            Limits::default(),
        );
        cmd.stdin(fs::File::open(&bad).unwrap());
        let out = wait_guarded(cmd.spawn().unwrap(), 60, "check -");
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "stdin {t1} {t2}: {err}");
        assert!(err.contains(needle), "{err}");
    }
}

#[test]
fn r35_10_messages_cut_long_values() {
    let d = dir("r35-10-cut");
    // 1e300 used to be printed as 301 digits.
    for args in [
        vec!["reference", "--times", "1e300,1"],
        vec![
            "events",
            "--event",
            "s1",
            "--t-start",
            "1e300",
            "--t-end",
            "1",
        ],
    ] {
        let out = rsts(&args);
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{args:?}: {err}");
        assert!(err.contains("1e300") && err.len() < 400, "{args:?}: {err}");
    }
    // A 200 kB line of a suite used to be printed twice.
    let suite = d.join("long.toml");
    let long = "x".repeat(200_000);
    fs::write(
        &suite,
        format!("name = \"t\"\n[defaults]\nt_end = \"{long}\"\n"),
    )
    .unwrap();
    let out = rsts(&["validate", "--suite", s(&suite), "--list"]);
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{}", &err[..err.len().min(300)]);
    assert!(err.len() < 600, "{} bytes: {}", err.len(), &err[..600]);
    // A 5000-digit time in an events file.
    let traj = traj_csv(&d);
    let events = d.join("ev.csv");
    fs::write(&events, format!("name,t\nomega1,{}x\n", "9".repeat(5000))).unwrap();
    let out = rsts(&["check", s(&traj), "--events", s(&events)]);
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{err}");
    assert!(
        err.len() < 400 && err.contains("(5001 characters)"),
        "{err}"
    );
}

#[test]
fn r35_10_a_version_with_bidi_controls_or_line_separators_is_refused() {
    let d = dir("r35-10-version");
    let samples = exact_samples();
    for version in ["1.0\u{202E}3.2", "1.0\u{2028}evil", "\u{2066}x\u{2069}"] {
        let answer = serde_json::json!({"samples": samples, "version": version});
        let file = d.join("answer.json");
        fs::write(&file, answer.to_string()).unwrap();
        let adapter = script(&d, "v.sh", &format!("cat >/dev/null; cat '{}'", s(&file)));
        let out = run(
            &[
                "compare",
                "--exec",
                &adapter,
                "--t-end",
                "1",
                "--samples",
                "2",
            ],
            Limits::default(),
        );
        let err = stderr(&out);
        assert_eq!(code(&out), Some(2), "{version:?}: {err}");
        assert!(err.contains("\"version\" must not hold"), "{err}");
    }
}

#[test]
fn r35_10_a_device_output_without_a_temporary_directory_names_tmpdir() {
    let out = command(
        &["reference", "--times", "0,1", "-o", "/dev/null"],
        Limits::default(),
    )
    .env("TMPDIR", "/nonexistent-rsts-tmp")
    .output()
    .unwrap();
    let err = stderr(&out);
    assert_eq!(code(&out), Some(2), "{err}");
    assert!(
        err.contains("TMPDIR") && err.contains("/nonexistent-rsts-tmp"),
        "{err}"
    );
}
