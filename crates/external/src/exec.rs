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

use std::time::Duration;

use rug::Float;
use serde_json::{json, Value};

use rsts_dynamics::integrators::{Problem, Tolerances};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_harness::{check_times, FixedStepIntegrator, HarnessError, Integrator, Trajectory};

/// The protocol name a request carries.
pub const PROTOCOL: &str = "rsts-integrator/1";
/// Default time a child may take (seconds).
pub const DEFAULT_TIMEOUT_SECONDS: f64 = 600.0;
/// Longest time a child may be given (seconds): every timeout (`--exec-timeout`, a suite's
/// `[adapters.NAME] timeout`) is checked by [`check_timeout`].
pub const MAX_TIMEOUT_SECONDS: f64 = 1e9;
/// Default decimal digits of the parameters and initial state of a request.
pub const DEFAULT_DIGITS: u32 = 36;

mod answer;
pub(crate) mod answer_doc;
mod process;

pub use answer::{max_answer, MAX_VERSION_CHARS};
pub use answer_doc::MAX_ANSWER_EVENTS;
pub use process::{
    check_program, check_timeout, command_files, kill_running, split_command, stderr_tail,
};

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

    /// The precision of the round-off it may accumulate: the `"digits"` its answer states, else
    /// f64 (53 bits), what an adapter that does not say works in (docs/convergence.md).
    fn round_off_bits(&self) -> u32 {
        self.answered_digits.map_or(53, bits_for_digits)
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
}
