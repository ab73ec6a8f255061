//! `compare`: an integrator started from the closed-form state at t = 0, compared with the
//! closed form along the motion at every sample time; its events and dense output matched
//! with the exact ones; everything logged to MCAP when asked (`rsts compare`, `rsts.compare`).

use std::path::PathBuf;

use rsts_closed_form::events::EventSpec;
use rsts_closed_form::{Motion, Times};
use rsts_dynamics::integrators::dense::StepSamples;
use rsts_dynamics::integrators::{MethodConfig, Problem, Tolerances};
use rsts_harness::bench::BenchIntegrator;
use rsts_harness::compare_diagram;
use rsts_harness::dense::{dense_of_method, dense_of_samples, DenseReport, MAX_DENSE};
use rsts_harness::environment::Environment;
use rsts_harness::events::{events_of_run, EventMatchReport, StateCollector};
use rsts_harness::{
    check_finite_report, compare_at, preflight_at, sampled, CompareOptions, HarnessError,
    Integrator, Observer, Report, StatedStats, Trajectory, MAX_SAMPLES,
};
use rsts_mcap::LogStats;
use serde::Serialize;

use crate::log::{check_log, Logged, Mcap, McapLog};
use crate::{FlowError, Limits, Verdict};

/// The integrator of a comparison.
pub enum Method<'a> {
    /// A built-in method with its settings.
    Builtin(MethodConfig),
    /// An integrator from outside the library: an `--exec` process, a Python callable, a
    /// user's Rust integrator. It is asked for the events and the dense output of the request
    /// ([`BenchIntegrator::ask_events`], [`BenchIntegrator::ask_dense`]); those it does not
    /// answer are located in its samples (events) or refused (dense output).
    Outside(&'a mut dyn BenchIntegrator),
}

/// What to compare.
pub struct CompareRequest<'a> {
    /// The motion, as written.
    pub motion: Motion,
    /// The sample times: N evenly spaced on [0, T] (the CLI's `--t-end`, `--samples`) or a list
    /// from 0 (Python's `times=`), each rounded once to f64 for the integrator.
    pub times: Times,
    pub method: Method<'a>,
    /// Events to locate and match with the exact ones (empty: none).
    pub events: Vec<EventSpec>,
    /// K samples of the dense output inside each step, checked apart from the step ends.
    pub dense: Option<usize>,
    /// At most this many calls of a restartable integrator (progress and Ctrl-C between them).
    pub pieces: usize,
    pub mcap: Option<Mcap>,
    /// A diagram of the state error and the drifts of H, K, G against time, written as SVG
    /// (`rsts compare --svg`): checked before the run, written after it.
    pub svg: Option<PathBuf>,
    pub limits: Limits,
}

/// What a comparison found: the document of `rsts compare --format json` (the report, the
/// events, the dense check, the environment, where the log went) and the verdict.
#[derive(Clone, Debug, Serialize)]
pub struct CompareOutcome {
    #[serde(flatten)]
    pub report: Report,
    /// The MCAP log written (its path as given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mcap: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub events: Option<EventMatchReport>,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub dense: Option<DenseReport>,
    /// Where it ran (the report carries a time): CPU, SIMD path, cores, OS, rsts version and
    /// commit, an outside integrator's library version.
    pub environment: Environment,
    /// Whether the run met the request's limits.
    #[serde(skip)]
    pub verdict: Verdict,
    /// What the MCAP log holds.
    #[serde(skip)]
    pub log: Option<LogStats>,
    /// Samples asked for (the report's `samples_compared` is smaller when the run was stopped).
    #[serde(skip)]
    pub samples: usize,
}

impl CompareOutcome {
    /// Why the run is not complete (it was stopped), if it is not.
    pub fn stopped(&self) -> Option<String> {
        (!self.report.complete).then(|| {
            format!(
                "compared {} of {} samples",
                self.report.samples_compared, self.samples
            )
        })
    }
}

/// Check `dense` (K from 1 to [`MAX_DENSE`] samples inside each step) before any work.
pub fn check_dense(k: usize) -> Result<(), FlowError> {
    if !(1..=MAX_DENSE).contains(&k) {
        return Err(FlowError::input(
            &["dense"],
            format!("K must be between 1 and {MAX_DENSE} samples inside each step, got {k}"),
        ));
    }
    Ok(())
}

/// An outside integrator as a harness [`Integrator`] (every call handed on).
struct Outside<'b, 'a>(&'b mut (dyn BenchIntegrator + 'a));

impl Integrator for Outside<'_, '_> {
    fn name(&self) -> String {
        self.0.name()
    }
    fn version(&self) -> Option<String> {
        self.0.version()
    }
    fn tolerances(&self) -> Option<Tolerances> {
        self.0.tolerances()
    }
    fn working_bits(&self) -> u32 {
        self.0.working_bits()
    }
    fn digits(&self) -> u32 {
        self.0.digits()
    }
    fn stated_stats(&self) -> Option<StatedStats> {
        self.0.stated_stats()
    }
    fn integrate(
        &mut self,
        problem: &Problem<rug::Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        self.0.integrate(problem, times)
    }
    fn restartable(&self) -> bool {
        self.0.restartable()
    }
    fn check_budget(
        &self,
        problem: &Problem<rug::Float>,
        grid: &rsts_dynamics::integrators::OutputGrid,
    ) -> Result<(), HarnessError> {
        self.0.check_budget(problem, grid)
    }
}

/// Compare: check the request whole before any work or output (the motion, the times, the
/// method's step budget, the events a built-in can locate, the log's size and path), run the
/// integrator through the times analysing each sample as it comes (handed to `observer`:
/// progress, Ctrl-C), match its events, check its dense output, and judge the limits.
///
/// A run stopped by `observer` gives its outcome with `complete: false` (the log finished);
/// a run that fails while `observer` asks to stop is [`FlowError::Interrupted`] (the log of
/// what was compared finished); a run that fails otherwise leaves no log.
pub fn compare(
    request: CompareRequest<'_>,
    observer: &mut dyn Observer,
) -> Result<CompareOutcome, FlowError> {
    let CompareRequest {
        motion,
        times,
        mut method,
        events,
        dense,
        pieces,
        mcap,
        svg,
        limits,
    } = request;
    if times.len() > MAX_SAMPLES {
        return Err(FlowError::input(
            &[samples_name(&times)],
            format!(
                "at most {MAX_SAMPLES} samples are supported, got {}",
                times.len()
            ),
        ));
    }
    if let Some(e) = limits.max_event_error {
        if e < 0.0 {
            return Err(FlowError::input(
                &["max-event-error"],
                format!("must be non-negative, got {e}"),
            ));
        }
    }
    if let Some(k) = dense {
        check_dense(k)?;
    }
    let case = sampled(&motion, &times)?;
    if pieces == 0 {
        return Err(FlowError::input(&["pieces"], "need at least 1"));
    }
    match &method {
        // The point of N and the step budget of the built-in method over the whole grid.
        Method::Builtin(config) => preflight_at(&motion, &times, config)?,
        Method::Outside(_) => {
            case.reference_motion(64)?;
        }
    }
    if let Some(log) = &mcap {
        // The files the outside integrator's command names are inputs the log must not replace.
        let files = log.command.as_deref().map(rsts_external::command_files);
        let inputs: Vec<_> = files
            .iter()
            .flatten()
            .map(|f| ("exec", f.as_path()))
            .collect();
        check_log(&log.path, Some(times.len()), samples_name(&times), &inputs)?;
    }
    if let Some(path) = &svg {
        let files = match &mcap {
            Some(Mcap {
                command: Some(c), ..
            }) => rsts_external::command_files(c),
            _ => Vec::new(),
        };
        compare_diagram::check_output(
            path,
            times.len(),
            mcap.as_ref().map(|m| m.path.as_path()),
            &files,
        )
        // The message names the options (`--svg`, `--mcap`, `--exec`) itself.
        .map_err(|e| FlowError::input(&[], rsts_io::error_text(&e)))?;
    }
    match &mut method {
        Method::Builtin(_) => {
            if let Some(s) = events.iter().find(|s| s.name.index() >= 12) {
                return Err(FlowError::input(
                    &["event"],
                    format!("{}: the built-in methods locate events of functions of the state (omega, alpha, beta, gamma); the turning points of s1, s2 need an --exec integrator that reports them", s.name),
                ));
            }
        }
        Method::Outside(outside) => {
            outside.ask_dense(dense);
            let asked: Vec<(String, String)> = events
                .iter()
                .map(|s| {
                    (
                        s.name.as_str().to_string(),
                        s.direction.as_str().to_string(),
                    )
                })
                .collect();
            outside.ask_events(&asked);
        }
    }
    let mut config;
    let mut outside;
    let integrator: &mut dyn Integrator = match &mut method {
        Method::Builtin(c) => {
            config = *c;
            &mut config
        }
        Method::Outside(o) => {
            outside = Outside(&mut **o);
            &mut outside
        }
    };
    let log = match &mcap {
        None => None,
        Some(m) => {
            let tolerances = integrator.tolerances();
            let mut meta = serde_json::json!({
                "method": integrator.name(),
                "rtol": tolerances.map(|t| t.rtol),
                "atol": tolerances.map(|t| t.atol),
                "digits": rsts_dynamics::scalar::digits_for_bits(integrator.working_bits()),
            });
            if let Some(command) = &m.command {
                meta["command"] = command.clone().into();
            }
            Some(McapLog::create(&m.path, &case, &meta)?)
        }
    };
    let mut logged = Logged::new(log, observer);
    let options = CompareOptions { pieces };
    let mut recorder = compare_diagram::Recorder::new(&mut logged, times.len());
    let mut collector = StateCollector::new(&mut recorder);
    let result = compare_at(&motion, &times, integrator, &options, &mut collector);
    let (sample_times, states) = (collector.times, collector.states);
    let series = recorder.series;
    let mut environment = Environment::detect();
    environment.record(integrator);
    let report = match result {
        Ok(r) => r,
        Err(e) if logged.should_stop() => {
            // Stopped (an external integrator is killed at once): the log of what was
            // compared is finished.
            logged.finish()?;
            return Err(FlowError::Interrupted(e.to_string()));
        }
        // A failed run discards its log: the temporary is removed, a previous file stays.
        Err(e) => return Err(e.into()),
    };
    let events = if events.is_empty() {
        None
    } else {
        let answered = match &method {
            Method::Outside(o) => o.answered_events(),
            Method::Builtin(_) => None,
        };
        Some(events_of_run(
            &case,
            &events,
            answered.as_deref(),
            &sample_times,
            &states,
        )?)
    };
    if let (Some(ev), Some(log)) = (&events, logged.log.as_mut()) {
        log.mark_events(ev)?;
    }
    let dense = match (dense, &mut method) {
        (None, _) => None,
        (Some(k), Method::Outside(o)) => {
            let samples: StepSamples = o.answered_dense().ok_or_else(|| {
                FlowError::input(&["dense"], "the external integrator gave no dense samples")
            })?;
            Some(dense_of_samples(&case, k, &samples)?)
        }
        (Some(k), Method::Builtin(config)) => Some(dense_of_method(&case, config, k)?),
    };
    let log = logged.finish()?;
    check_finite_report(&report)?;
    if let Some(path) = &svg {
        compare_diagram::write_svg(path, &motion, &report, &series).map_err(|e| {
            FlowError::Output {
                output: "svg",
                message: format!("{}: {}", path.display(), rsts_io::error_text(&e)),
            }
        })?;
    }
    let verdict = Verdict::from_reasons(
        events
            .as_ref()
            .zip(limits.max_event_error)
            .and_then(|(ev, limit)| ev.counts.failure(limit))
            .map(|why| format!("{}: {why}", report.method))
            .into_iter()
            .collect(),
    );
    Ok(CompareOutcome {
        report,
        mcap: mcap.map(|m| m.path.display().to_string()),
        events,
        dense,
        environment,
        verdict,
        log,
        samples: times.len(),
    })
}

/// The input that sets the number of samples: `samples` of a grid, `times` of a list.
fn samples_name(times: &Times) -> &'static str {
    match times {
        Times::Grid { .. } => "samples",
        _ => "times",
    }
}
