//! External integrators: a program in any language that speaks `rsts-integrator/1` on its
//! standard input and output is an [`Integrator`] like the built-in methods.
//!
//! rsts starts the command (split like a shell would, run without a shell), writes one JSON
//! request on its stdin and closes it, and reads the answer from its stdout:
//!
//! ```text
//! request: {"protocol": "rsts-integrator/1", "a": "1", "b": "0.5",
//!           "initial": {"omega": ["…", "…", "…"], "alpha": [...], "beta": [...]},
//!           "times": [0, 0.1, …], "rtol": 1e-10, "atol": 1e-10, "digits": 36[, "step": 0.01]}
//! answer:  {"name": "my-rk4", "samples": [{"t": 0, "omega": [3], "alpha": [3], "beta": [3]}, …],
//!           "stats": {"steps": 123, "rhs_evals": 492, "integration_seconds": 0.01}}
//! ```
//!
//! `"step"` is present only when a fixed step is asked (`rsts convergence`): every step of the
//! integrator should then be h (each interval between two times is a whole number of steps).
//! Parameters and the initial state are decimal strings carrying `digits` digits (the exact
//! values the closed-form reference uses, rounded to that many digits); times are JSON numbers,
//! starting at 0. The answer has one sample per time; its numbers may be JSON numbers or decimal
//! strings; `name`, `stats`, `digits` (the integrator's working precision in decimal digits,
//! e.g. 15 for f64, reported instead of the request's) and `version` (its library's version,
//! recorded in the reports' environment) are optional. Instead of JSON the answer may be the CSV of
//! `rsts check` (header `t,omega1,…,beta3`). rsts measures the child's wall time; the
//! `integration_seconds` of the answer, when present, is the time reported.
//!
//! A child that cannot start, exits with a non-zero status, outlives its timeout, writes
//! something that is not an answer or the wrong number of samples is an error naming the command
//! and showing the end of its stderr. The child runs in its own process group; the group is
//! killed when the child is done or overdue, and the child is always waited for (no zombie).

use std::collections::BTreeSet;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rug::Float;
use serde_json::{json, Value};

use rsts_dynamics::integrators::{Problem, Stats, Tolerances};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_harness::{check_times, FixedStepIntegrator, HarnessError, Integrator, Trajectory};

use crate::files::{parse_csv, parse_json};
use crate::pipes::{Ended, Pipes};

/// The protocol name a request carries.
pub const PROTOCOL: &str = "rsts-integrator/1";
/// Default time a child may take (seconds).
pub const DEFAULT_TIMEOUT_SECONDS: f64 = 600.0;
/// Longest time a child may be given (seconds): every timeout (`--exec-timeout`, a suite's
/// `[adapters.NAME] timeout`) is checked by [`check_timeout`].
pub const MAX_TIMEOUT_SECONDS: f64 = 1e9;
/// Default decimal digits of the parameters and initial state of a request.
pub const DEFAULT_DIGITS: u32 = 36;
/// Lines of a child's stderr shown in an error.
const STDERR_TAIL_LINES: usize = 15;

/// Process groups of the children now running (killed by [`kill_running`]).
static RUNNING: Mutex<BTreeSet<i32>> = Mutex::new(BTreeSet::new());
/// Set by [`kill_running`]: the children were stopped on purpose.
static STOPPED: AtomicBool = AtomicBool::new(false);

/// Kill every external integrator this process is running (for a Ctrl-C handler); their runs
/// end with an error saying they were stopped.
pub fn kill_running() {
    STOPPED.store(true, Ordering::SeqCst);
    if let Ok(set) = RUNNING.try_lock() {
        for &pgid in set.iter() {
            kill_group(pgid);
        }
    }
}

fn kill_group(pgid: i32) {
    // SAFETY: kill(2) with a negative pid signals a process group; no memory is involved.
    unsafe {
        libc::kill(-pgid, libc::SIGKILL);
    }
}

/// The one rule for a timeout: a finite number of seconds, > 0 and at most
/// [`MAX_TIMEOUT_SECONDS`] (about 31 years; a deadline that far ahead never overflows).
pub fn check_timeout(seconds: f64) -> Result<Duration, String> {
    if seconds.is_finite() && seconds > 0.0 && seconds <= MAX_TIMEOUT_SECONDS {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(format!(
            "must be a positive number of seconds, at most {MAX_TIMEOUT_SECONDS:e}; got {seconds}"
        ))
    }
}

/// Check, before any work, that `program` can be started: a path names an executable file, a
/// bare name one found on the `PATH` (a run would otherwise fail only when its turn comes, after
/// the rest of a benchmark or suite).
pub fn check_program(program: &str) -> Result<(), String> {
    let executable = |p: &std::path::Path| {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    };
    if program.contains('/') {
        let p = std::path::Path::new(program);
        if !p.exists() {
            return Err(format!("cannot start `{program}`: no such file"));
        }
        if !executable(p) {
            return Err(format!(
                "cannot start `{program}`: not an executable file (chmod +x, or name its interpreter first: python3 {program})"
            ));
        }
        return Ok(());
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    if std::env::split_paths(&path).any(|d| executable(&d.join(program))) {
        Ok(())
    } else {
        Err(format!(
            "cannot start `{program}`: no such program on the PATH"
        ))
    }
}

/// Split a command line like a POSIX shell would (quotes, backslashes), without running a shell.
pub fn split_command(command: &str) -> Result<Vec<String>, String> {
    let argv = shlex::split(command).ok_or_else(|| {
        format!("cannot split `{command}`: unbalanced quotes or a trailing backslash")
    })?;
    if argv.is_empty() {
        return Err("the command is empty".into());
    }
    Ok(argv)
}

/// An external integrator: a command and the settings sent with every request.
#[derive(Clone, Debug)]
pub struct Exec {
    argv: Vec<String>,
    /// Name given by the user (a suite's adapter name); else the answer's, else the program's.
    name: Option<String>,
    answered_name: Option<String>,
    /// The working precision the answer stated (`"digits"`), reported instead of the request's.
    answered_digits: Option<u32>,
    /// The library version the answer stated (`"version"`), recorded in reports' environment.
    answered_version: Option<String>,
    pub tolerances: Tolerances,
    /// Digits of the parameters and initial state in the request (also the precision the
    /// reference must exceed).
    pub digits: u32,
    pub timeout: Duration,
    /// Events asked for in the request, as (name, direction) (docs/events.md); none: the
    /// request has no `"events"`.
    pub events: Vec<(String, String)>,
    /// The `"events"` of the last answer as (name, t), when it had them.
    pub answered_events: Option<Vec<(String, f64)>>,
    /// A fixed step asked of the integrator (`"step"` in the request; convergence studies).
    pub step: Option<f64>,
    /// K samples inside each step asked (`"dense": K` in the request; [`crate::dense`]).
    pub dense: Option<usize>,
    /// The steps and dense samples of the last answer to a request with `dense`.
    pub answered_dense: Option<rsts_dynamics::integrators::dense::StepSamples>,
    /// The parts of its cost the last answer stated (`"stats"`; a CSV answer states none).
    answered_stats: rsts_harness::StatedStats,
}

impl Exec {
    /// A command line, split like a shell would.
    pub fn new(command: &str, tolerances: Tolerances) -> Result<Self, String> {
        Self::from_argv(split_command(command)?, tolerances)
    }

    /// A command as its words (program first).
    pub fn from_argv(argv: Vec<String>, tolerances: Tolerances) -> Result<Self, String> {
        if argv.is_empty() || argv[0].is_empty() {
            return Err("the command is empty".into());
        }
        Ok(Self {
            argv,
            name: None,
            answered_name: None,
            answered_digits: None,
            answered_version: None,
            tolerances,
            digits: DEFAULT_DIGITS,
            timeout: Duration::from_secs_f64(DEFAULT_TIMEOUT_SECONDS),
            events: Vec::new(),
            answered_events: None,
            step: None,
            dense: None,
            answered_dense: None,
            answered_stats: rsts_harness::StatedStats::default(),
        })
    }

    /// Report under this name whatever the answer says.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// Digits of the request (10 to 10000).
    pub fn with_digits(mut self, digits: u32) -> Result<Self, String> {
        if !(10..=10_000).contains(&digits) {
            return Err(format!("digits must be between 10 and 10000, got {digits}"));
        }
        self.digits = digits;
        Ok(self)
    }

    /// Time the child may take ([`check_timeout`]).
    pub fn with_timeout(mut self, seconds: f64) -> Result<Self, String> {
        self.timeout = check_timeout(seconds)?;
        Ok(self)
    }

    /// [`check_program`] of the command's program.
    pub fn check_program(&self) -> Result<(), String> {
        check_program(&self.argv[0])
    }

    /// The command as a shell-quoted line (for messages).
    pub fn command_line(&self) -> String {
        shlex::try_join(self.argv.iter().map(String::as_str))
            .unwrap_or_else(|_| self.argv.join(" "))
    }

    /// The name of the program and its arguments, directories dropped.
    fn program_name(&self) -> String {
        let mut words: Vec<String> = self
            .argv
            .iter()
            .map(|w| w.rsplit('/').next().unwrap_or(w).to_string())
            .collect();
        words.retain(|w| !w.is_empty());
        words.join(" ")
    }

    /// The request for `problem` through `times` (decimal strings of `digits` digits).
    pub fn request(&self, problem: &Problem<Float>, times: &[f64]) -> Value {
        let d = Some(self.digits as usize);
        let dec = |x: &Float| x.to_string_radix(10, d);
        let v3 = |v: &[Float; 3]| [dec(&v[0]), dec(&v[1]), dec(&v[2])];
        let mut request = json!({
            "protocol": PROTOCOL,
            "a": dec(&problem.fields.a),
            "b": dec(&problem.fields.b),
            "initial": {
                "omega": v3(&problem.initial.omega),
                "alpha": v3(&problem.initial.alpha),
                "beta": v3(&problem.initial.beta),
            },
            "times": times,
            "rtol": self.tolerances.rtol,
            "atol": self.tolerances.atol,
            "digits": self.digits,
        });
        if !self.events.is_empty() {
            let list: Vec<Value> = self
                .events
                .iter()
                .map(|(name, direction)| json!({"name": name, "direction": direction}))
                .collect();
            request["events"] = Value::Array(list);
        }
        if let Some(h) = self.step {
            request["step"] = json!(h);
        }
        if let Some(k) = self.dense {
            request["dense"] = json!(k);
        }
        request
    }

    fn fail(&self, what: impl std::fmt::Display, stderr: &[u8]) -> HarnessError {
        HarnessError::Integrator(format!(
            "external integrator `{}`: {what}{}",
            self.command_line(),
            stderr_tail(stderr)
        ))
    }

    /// Run the child on `request`: its stdout (at most `max_answer` bytes, else an error), the
    /// end of its stderr and its wall time.
    pub fn run_raw(
        &self,
        request: &[u8],
        max_answer: usize,
    ) -> Result<(Vec<u8>, Vec<u8>, f64), HarnessError> {
        let mut cmd = Command::new(&self.argv[0]);
        cmd.args(&self.argv[1..])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        #[cfg(unix)]
        std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
        let started = Instant::now();
        let mut child = cmd.spawn().map_err(|e| {
            HarnessError::Integrator(format!(
                "external integrator `{}`: cannot start `{}`: {e}",
                self.command_line(),
                self.argv[0]
            ))
        })?;
        let pgid = child.id() as i32;
        if let Ok(mut set) = RUNNING.lock() {
            set.insert(pgid);
        }
        let result = self.talk(&mut child, request, started, max_answer);
        // Whatever happened: no process of the group left behind, the child reaped.
        kill_group(pgid);
        let _ = child.wait();
        if let Ok(mut set) = RUNNING.lock() {
            set.remove(&pgid);
        }
        result
    }

    fn talk(
        &self,
        child: &mut Child,
        request: &[u8],
        started: Instant,
        max_answer: usize,
    ) -> Result<(Vec<u8>, Vec<u8>, f64), HarnessError> {
        // One thread serves the three pipes until the deadline, whatever still holds them.
        let mut pipes = Pipes::new(child, request, max_answer);
        let ended = pipes.serve(child, started + self.timeout);
        let wall = started.elapsed().as_secs_f64();
        kill_group(child.id() as i32);
        let _ = child.wait();
        let (stdout, stderr) = (
            std::mem::take(&mut pipes.out),
            std::mem::take(&mut pipes.err),
        );
        match ended {
            Ended::Overdue => Err(self.fail(
                format_args!(
                    "no answer within {} s (the timeout, --exec-timeout); the process was killed",
                    self.timeout.as_secs_f64()
                ),
                &stderr,
            )),
            Ended::TooLong => Err(self.fail(
                format_args!(
                    "its answer passed {max_answer} bytes, the most an answer to this request may take \
                     (samples x digits, see docs/output.md); the process was killed"
                ),
                &stderr,
            )),
            Ended::Exited(_) if STOPPED.load(Ordering::SeqCst) => {
                Err(self.fail("stopped (Ctrl-C)", &stderr))
            }
            Ended::Exited(s) if !s.success() => Err(self.fail(describe_status(s), &stderr)),
            Ended::Exited(_) => Ok((stdout, stderr, wall)),
        }
    }

    /// Parse an answer for `times` into states at `bits` bits.
    pub fn parse_answer(
        &mut self,
        stdout: &[u8],
        stderr: &[u8],
        times: &[f64],
        bits: u32,
    ) -> Result<(Vec<rsts_dynamics::State<Float>>, Stats), HarnessError> {
        let text = std::str::from_utf8(stdout)
            .map_err(|_| self.fail("its answer is not UTF-8 text", stderr))?;
        let garbage = |e: String| {
            let start: String = text.trim().chars().take(200).collect();
            self.fail(
                format_args!(
                    "its answer is not an rsts-integrator/1 answer ({e}); it begins with: {start:?}"
                ),
                stderr,
            )
        };
        if text.trim().is_empty() {
            return Err(self.fail("it wrote no answer on stdout", stderr));
        }
        let mut answered = None;
        let mut digits = None;
        let mut version = None;
        let mut answered_events = None;
        let mut answered_dense = None;
        let (raw, stats) = if text.trim_start().starts_with('{') {
            let doc: Value =
                serde_json::from_str(text).map_err(|e| garbage(format!("invalid JSON: {e}")))?;
            if let Some(name) = doc.get("name") {
                let name = name
                    .as_str()
                    .filter(|s| !s.trim().is_empty())
                    .ok_or_else(|| garbage("\"name\" must be a non-empty string".into()))?;
                answered = Some(name.to_string());
            }
            let stats = parse_stats(doc.get("stats")).map_err(garbage)?;
            if let Some(d) = doc.get("digits").filter(|d| !d.is_null()) {
                let d = d
                    .as_u64()
                    .filter(|d| (1..=10_000).contains(d))
                    .ok_or_else(|| {
                        garbage("\"digits\" must be a whole number from 1 to 10000".into())
                    })?;
                digits = Some(d as u32);
            }
            if let Some(k) = self.dense {
                answered_dense =
                    Some(crate::dense::parse_dense(&doc, k).map_err(|e| self.fail(e, stderr))?);
            }
            if let Some(v) = doc.get("version").filter(|v| !v.is_null()) {
                version = Some(check_version(v).map_err(garbage)?);
            }
            answered_events = match doc.get("events") {
                None => None,
                Some(v) => Some(parse_events(v).map_err(garbage)?),
            };
            (parse_json(&doc).map_err(garbage)?, stats)
        } else {
            (parse_csv(text).map_err(garbage)?, (None, None, None))
        };
        if answered.is_some() {
            self.answered_name = answered;
        }
        if digits.is_some() {
            self.answered_digits = digits;
        }
        if version.is_some() {
            self.answered_version = version;
        }
        self.answered_events = answered_events;
        self.answered_dense = answered_dense;
        if let (Some(k), None) = (self.dense, &self.answered_dense) {
            return Err(self.fail(
                format_args!("--dense {k} needs a JSON answer with \"stats.step_times\" and \"dense\" (docs/own-integrator.md); it answered CSV"),
                stderr,
            ));
        }
        if raw.len() != times.len() {
            return Err(self.fail(
                format_args!(
                    "it answered {} samples for {} requested times",
                    raw.len(),
                    times.len()
                ),
                stderr,
            ));
        }
        for (k, (t, want)) in raw.times.iter().zip(times).enumerate() {
            let got = t.to_f64();
            if (got - want).abs() > 1e-12 * want.abs().max(1.0) {
                return Err(self.fail(
                    format_args!("sample {k} is at t = {got}, requested t = {want}"),
                    stderr,
                ));
            }
        }
        let samples = raw.to_samples(bits);
        let (steps, rhs_evals, seconds) = stats;
        self.answered_stats = rsts_harness::StatedStats {
            steps,
            rejected_steps: None,
            rhs_evals,
            integration_seconds: seconds,
        };
        Ok((
            samples.states,
            Stats {
                accepted_steps: steps.unwrap_or(0),
                rejected_steps: 0,
                rhs_evals: rhs_evals.unwrap_or(0),
                integration_seconds: seconds.unwrap_or(f64::NAN),
            },
        ))
    }
}

type AnswerStats = (Option<u64>, Option<u64>, Option<f64>);

/// Longest `"version"` an answer may carry (characters).
pub const MAX_VERSION_CHARS: usize = 200;

/// `version` of an answer: a non-empty string of at most [`MAX_VERSION_CHARS`] characters,
/// without control characters (it is printed in tables).
fn check_version(v: &Value) -> Result<String, String> {
    let s = v
        .as_str()
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .ok_or("\"version\" must be a non-empty string")?;
    if s.chars().count() > MAX_VERSION_CHARS {
        return Err(format!(
            "\"version\" has {} characters, at most {MAX_VERSION_CHARS} are taken",
            s.chars().count()
        ));
    }
    if s.chars().any(char::is_control) {
        return Err("\"version\" must not hold control characters".into());
    }
    Ok(s.to_string())
}

/// `events` of an answer: `[{"name", "t"}]`, t a number or a decimal string.
fn parse_events(v: &Value) -> Result<Vec<(String, f64)>, String> {
    let list = v.as_array().ok_or("\"events\" must be an array")?;
    list.iter()
        .enumerate()
        .map(|(i, e)| {
            let name = e.get("name").and_then(Value::as_str);
            let t = match e.get("t") {
                Some(Value::Number(n)) => n.as_f64(),
                Some(Value::String(s)) => s.trim().parse().ok(),
                _ => None,
            };
            match (name, t) {
                (Some(n), Some(t)) if t.is_finite() => Ok((n.to_string(), t)),
                _ => Err(format!(
                    "events[{i}] needs a \"name\" string and a finite \"t\""
                )),
            }
        })
        .collect()
}

/// `stats` of an answer: every field optional, numbers or decimal strings (read as a JSON
/// trajectory file's, [`crate::files::parse_stats`]).
fn parse_stats(v: Option<&Value>) -> Result<AnswerStats, String> {
    let s = crate::files::parse_stats(v)?;
    Ok((s.steps, s.rhs_evals, s.integration_seconds))
}

/// The most bytes an answer of `samples` samples at `digits` digits may take: 1 MiB, plus per
/// sample ten values of up to `digits` + 40 characters and 400 of keys and layout (pretty JSON),
/// doubled. Far more than any honest answer; a bound on what an adapter can make us hold.
pub fn max_answer(samples: usize, digits: u32) -> usize {
    let per_sample = 10 * (digits as usize + 40) + 400;
    (1 << 20) + 2 * samples.saturating_mul(per_sample)
}

fn describe_status(s: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = s.signal() {
            return format!("killed by signal {sig}");
        }
    }
    match s.code() {
        Some(c) => format!("exited with status {c}"),
        None => "exited abnormally".into(),
    }
}

/// The last lines of a child's stderr, indented; "(its stderr is empty)" when there is none.
pub fn stderr_tail(stderr: &[u8]) -> String {
    let text = String::from_utf8_lossy(stderr);
    let lines: Vec<&str> = text.trim_end().lines().collect();
    if lines.is_empty() {
        return " (its stderr is empty)".into();
    }
    let from = lines.len().saturating_sub(STDERR_TAIL_LINES);
    let shown: Vec<String> = lines[from..]
        .iter()
        .map(|l| {
            let l: String = l.chars().take(300).collect();
            format!("  | {l}")
        })
        .collect();
    format!(
        "; {} of its stderr:\n{}",
        if from > 0 { "the end" } else { "all" },
        shown.join("\n")
    )
}

impl Integrator for Exec {
    fn version(&self) -> Option<String> {
        self.answered_version.clone()
    }

    fn name(&self) -> String {
        self.name
            .clone()
            .or_else(|| self.answered_name.clone())
            .unwrap_or_else(|| self.program_name())
    }

    fn tolerances(&self) -> Option<Tolerances> {
        Some(self.tolerances)
    }

    fn working_bits(&self) -> u32 {
        bits_for_digits(self.digits)
    }

    fn digits(&self) -> u32 {
        self.answered_digits.unwrap_or(self.digits)
    }

    fn stated_stats(&self) -> Option<rsts_harness::StatedStats> {
        Some(self.answered_stats)
    }

    fn integrate(
        &mut self,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        check_times(times)?;
        let bits = problem.initial.omega[0].prec();
        let dense_bytes = self.dense.map_or(0, |_| crate::dense::max_dense_bytes());
        let request = serde_json::to_vec(&self.request(problem, times))
            .map_err(|e| HarnessError::Integrator(format!("cannot write the request: {e}")))?;
        let (stdout, stderr, wall) =
            self.run_raw(&request, max_answer(times.len(), self.digits) + dense_bytes)?;
        let (states, mut stats) = self.parse_answer(&stdout, &stderr, times, bits)?;
        if stats.integration_seconds.is_nan() {
            stats.integration_seconds = wall;
        }
        Ok(Trajectory {
            times: times.to_vec(),
            states,
            stats,
            wall_seconds: Some(wall),
        })
    }

    fn restartable(&self) -> bool {
        false
    }
}

/// At a fixed step: the request carries `"step": h` (an adapter that ignores it answers the
/// same for every step and is refused by [`rsts_harness::convergence()`]).
impl FixedStepIntegrator for Exec {
    fn name(&self) -> String {
        Integrator::name(self)
    }

    fn label(&self) -> String {
        format!(
            "{} (external integrator `{}`)",
            Integrator::name(self),
            self.command_line()
        )
    }

    fn working_bits(&self) -> u32 {
        Integrator::working_bits(self)
    }

    fn integrate_at(
        &mut self,
        step: f64,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        self.step = Some(step);
        let result = self.integrate(problem, times);
        self.step = None;
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `"step"` is in the request only when a fixed step is asked.
    #[test]
    fn the_step_is_sent_only_when_asked() {
        use rsts_dynamics::{Fields, State};
        let f = |x: f64| Float::with_val(64, x);
        let problem = Problem {
            fields: Fields {
                a: f(1.0),
                b: f(0.5),
            },
            initial: State {
                omega: [f(0.1), f(0.2), f(0.3)],
                alpha: [f(1.0), f(0.0), f(0.0)],
                beta: [f(0.0), f(1.0), f(0.0)],
            },
        };
        let mut exec = Exec::new("x", Tolerances::new(1e-8, 1e-8).unwrap()).unwrap();
        assert!(exec.request(&problem, &[0.0, 1.0]).get("step").is_none());
        exec.step = Some(0.125);
        assert_eq!(exec.request(&problem, &[0.0, 1.0])["step"], json!(0.125));
    }

    #[test]
    fn commands_are_split_like_a_shell_would() {
        assert_eq!(
            split_command(r#"python3 "my adapter.py" --m 'a b' x\ y"#).unwrap(),
            vec!["python3", "my adapter.py", "--m", "a b", "x y"]
        );
        assert!(split_command("").is_err());
        assert!(split_command("   ").is_err());
        assert!(split_command("python3 'open")
            .unwrap_err()
            .contains("unbalanced"));
    }

    #[test]
    fn stats_are_optional_numbers_or_strings() {
        let s = parse_stats(Some(
            &json!({"steps": 10, "rhs_evals": "40", "integration_seconds": 0.5}),
        ))
        .unwrap();
        assert_eq!(s, (Some(10), Some(40), Some(0.5)));
        assert_eq!(parse_stats(None).unwrap(), (None, None, None));
        assert!(parse_stats(Some(&json!({"steps": -1}))).is_err());
        assert!(parse_stats(Some(&json!({"steps": 1.5}))).is_err());
        assert!(parse_stats(Some(&json!([1]))).is_err());
    }

    #[test]
    fn the_stderr_tail_keeps_the_last_lines() {
        let text: String = (0..40).map(|k| format!("line {k}\n")).collect();
        let tail = stderr_tail(text.as_bytes());
        assert!(
            tail.contains("line 39") && !tail.contains("line 24\n"),
            "{tail}"
        );
        assert!(tail.starts_with("; the end of its stderr"));
        assert_eq!(stderr_tail(b""), " (its stderr is empty)");
    }
}
