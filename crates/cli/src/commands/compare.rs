//! `rsts compare`: integrate from the closed-form state at t = 0 and compare with the closed form
//! along the motion; report errors, drifts and cost; optionally log everything to MCAP.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context};
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

use rsts_harness::compare_diagram;
use rsts_harness::dense::{dense_of_method, dense_of_samples, DenseReport, MAX_DENSE};
use rsts_harness::environment::Environment;
use rsts_harness::events::{events_of_run, EventMatchReport, StateCollector};
use rsts_harness::{
    compare_integrator, preflight, Case, CompareOptions, Integrator, Observer, Report, SampleRecord,
};
use rsts_mcap::{BodyState, ErrorSample, Metadata, Sample, TrajectoryLog};

use crate::args::{case_error, count, decimal, finite_f64, CaseArgs, MethodArgs, MAX_SAMPLES};
use crate::external::{exec_integrator, TimeoutArgs};
use crate::interrupt;
use crate::output::{self, Format};

/// Shown at the end of `rsts compare --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the built-in default case: camera I+ (a=1, b=0.5, m=0.3, h=-0.375), T=100, 1001 samples, dop853 at 1e-12
  rsts compare --mcap out/compare.mcap

  # the state error and the drifts of H, K, G against time, as a picture (what scripts/run.sh draws)
  rsts compare --svg out/compare.svg

  # a loose Dopri5 run in camera V on its third torus, JSON report
  rsts compare --m -0.7092 --h 1.5643 --torus 2 --method dopri5 --rtol 1e-6 --atol 1e-6 --format json

  # the Taylor integrator at 60 digits (the closed form is evaluated 64 bits beyond it)
  rsts compare --method taylor-mp --digits 60 --rtol 1e-55 --atol 1e-55 --t-end 20 --samples 21

  # an external integrator (any program speaking rsts-integrator/1, docs/own-integrator.md)
  cargo build --release -p example-adapter-rk4
  rsts compare --exec target/release/example-adapter-rk4 --rtol 1e-10 --atol 1e-10 --t-end 20 --samples 201

Open the MCAP file in Foxglove or Lichtblick (Open local file) with the layout
docs/foxglove/compare.json (Layouts > Import layout); see docs/mcap.md for the channels.
The MCAP file appears only when complete (an existing file is replaced then, never damaged).
Ctrl-C stops the run after the current piece and still writes a complete, readable MCAP file of
what was compared (exit code 130); a second Ctrl-C exits at once and leaves any previous file.";

/// Options of `rsts compare`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T >= 0
    #[arg(long, value_name = "T", default_value = "100", value_parser = decimal, allow_hyphen_values = true)]
    pub t_end: rsts_closed_form::Decimal,
    /// Number N >= 1 of samples evenly spaced on [0, T]
    #[arg(long, value_name = "N", default_value = "1001", value_parser = count)]
    pub samples: usize,
    #[command(flatten)]
    pub method: MethodArgs,
    /// Run this external integrator instead of --method: a command (split like a shell would,
    /// run without a shell) speaking rsts-integrator/1 on stdin/stdout (docs/own-integrator.md)
    #[arg(long, value_name = "COMMAND", conflicts_with = "method")]
    pub exec: Option<String>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// Decimal digits of taylor-mp (10 to 10000; default 50); with --exec, of the request's
    /// parameters and initial state (default 36)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Integrate in at most N pieces, each restarted from the last state of the previous one
    /// (progress, Ctrl-C between pieces); 1: one uninterrupted run, as `rsts integrate` does
    #[arg(long, value_name = "N", default_value_t = rsts_harness::DEFAULT_PIECES)]
    pub pieces: usize,
    /// Event NAME[:up|down|both] to locate (repeatable; docs/events.md): an --exec integrator is
    /// asked for it in the request; a built-in method's events are located in its samples by
    /// cubic Hermite interpolation. Matched with the exact events in the report
    #[arg(long = "event", value_name = "NAME[:DIR]")]
    pub event: Vec<String>,
    /// With --event: exit with status 1 when an event is missed or a time error exceeds E
    #[arg(long, value_name = "E", value_parser = finite_f64, requires = "event")]
    pub max_event_error: Option<f64>,
    /// Check the dense output: K samples (1 to 64) inside each of the integrator's own steps,
    /// evaluated by its interpolant, reported apart from the step ends (dense_max_error,
    /// step_max_error; docs/compare.md). A built-in method makes one more run in one piece; an
    /// --exec integrator is asked for "dense": K (docs/own-integrator.md)
    #[arg(long, value_name = "K")]
    pub dense: Option<usize>,
    /// Write the comparison to this MCAP file (Foxglove schemas)
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Draw the state error and the drifts of H, K, G against time (log scale) as SVG
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Output format of the report (csv: one header line and one row, the JSON fields flattened)
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

impl Args {
    fn case(&self) -> Case {
        self.case.case(&self.t_end, self.samples)
    }
}

/// The run was stopped by Ctrl-C (the report and the log cover what was done).
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for Interrupted {}

/// Logs samples to MCAP, advances the progress bar, and watches Ctrl-C (also used by `check`).
pub(crate) struct CliObserver {
    pub(crate) log: Option<TrajectoryLog>,
    pub(crate) bar: ProgressBar,
    shown: bool,
    started: Instant,
    stop: Arc<AtomicBool>,
    /// Samples not yet counted on the bar, and how many make a tick (a tick reads the clock:
    /// `rsts check` of f64 data ticks every few hundred samples).
    pending: u64,
    tick: u64,
}

/// A flag set by the first Ctrl-C (the run stops after the current piece or sample, and an
/// external integrator is killed at once); a second Ctrl-C exits at once, removing the
/// temporaries of the output files (a previous file at the path stays). See [`interrupt`].
pub(crate) fn stop_on_ctrl_c() -> Arc<AtomicBool> {
    interrupt::stop_gracefully()
}

impl CliObserver {
    /// Clear the progress bar and finish the MCAP log (its statistics): the file appears at its
    /// path. (Dropping the observer instead discards the log.)
    pub(crate) fn finish(&mut self) -> anyhow::Result<Option<rsts_mcap::LogStats>> {
        self.bar.finish_and_clear();
        match self.log.take() {
            Some(log) => {
                let path = log.path().display().to_string();
                Ok(Some(log.finish().map_err(|e| {
                    anyhow::anyhow!("--mcap {path}: {}", rsts_io::error_text(&e))
                })?))
            }
            None => Ok(None),
        }
    }

    /// An observer of `samples` samples logging to `log`, stopped by `stop`.
    pub(crate) fn new(log: Option<TrajectoryLog>, samples: u64, stop: Arc<AtomicBool>) -> Self {
        let bar = ProgressBar::with_draw_target(Some(samples), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} comparing [{bar:40}] {pos}/{len} samples, {elapsed} ({eta} left)",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Self {
            log,
            bar,
            shown: false,
            started: Instant::now(),
            stop,
            pending: 0,
            tick: 1,
        }
    }

    /// Tick the bar every `samples` samples (the last ones of a run are not shown: the bar
    /// is cleared then).
    pub(crate) fn ticking_every(mut self, samples: u64) -> Self {
        self.tick = samples.max(1);
        self
    }
}

/// A logged value, absent when not finite (no nearest point on N was found).
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

fn body(s: &rsts_harness::StateSnapshot) -> BodyState {
    BodyState {
        q: s.q,
        omega: s.omega,
        omega_fixed: s.omega_fixed,
        h: s.h,
        k: s.k,
        g: s.g,
    }
}

impl Observer for CliObserver {
    /// The states are logged, not shown.
    fn wants_states(&self) -> bool {
        self.log.is_some()
    }
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        if let Some(log) = &mut self.log {
            let e = &r.errors;
            log.log_sample(&Sample {
                t: r.t,
                exact: Some(body(&r.exact)),
                integrated: Some(body(&r.integrated)),
                errors: Some(ErrorSample {
                    state_error: e.state_error,
                    orientation_error: e.orientation_error,
                    drift_h: e.drift_h,
                    drift_k: e.drift_k,
                    drift_g: e.drift_g,
                    constraint_drift: e.constraint_drift,
                    off_n: e.off_n,
                    distance_from_n: finite(e.distance_from_n),
                    x_phi: finite(e.x_phi),
                    along_n: finite(e.along_n),
                    phase_error_psi1: finite(e.phase_error[0]),
                    phase_error_psi2: finite(e.phase_error[1]),
                }),
            })
            .map_err(|e| format!("writing the MCAP file: {}", rsts_io::error_text(&e)))?;
        }
        // Show the bar only for runs longer than a second, and only on a terminal.
        self.pending += 1;
        if self.pending >= self.tick {
            output::tick_progress_by(&self.bar, self.started, &mut self.shown, self.pending);
            self.pending = 0;
        }
        Ok(())
    }

    fn should_stop(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

/// Create the MCAP log `path` (its directory too) with the case and the integrator as metadata.
pub(crate) fn open_log(
    path: &std::path::Path,
    case: &impl Serialize,
    integrator: &impl Serialize,
) -> anyhow::Result<TrajectoryLog> {
    let meta = Metadata::new(
        concat!("rsts ", env!("CARGO_PKG_VERSION")),
        case,
        integrator,
    )?;
    TrajectoryLog::create(path, &meta)
        .map_err(|e| anyhow::anyhow!("--mcap {}: {}", path.display(), rsts_io::error_text(&e)))
}

/// The JSON of `rsts compare`: the report plus where the log went.
#[derive(Serialize)]
struct Document<'a> {
    #[serde(flatten)]
    report: &'a Report,
    #[serde(skip_serializing_if = "Option::is_none")]
    mcap: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    events: Option<EventMatchReport>,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    dense: Option<DenseReport>,
    /// Where it ran (the report carries a time): CPU, SIMD path, cores, OS, rsts version and
    /// commit, an --exec integrator's library version.
    environment: Environment,
}

/// Bytes an MCAP log takes per sample (measured: 2000 samples of the default case, 2.44 MB).
const MCAP_BYTES_PER_SAMPLE: f64 = 1300.0;

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    // Everything is checked before any output exists.
    if args.samples > MAX_SAMPLES {
        bail!(
            "--samples: at most {MAX_SAMPLES} samples are supported, got {}",
            args.samples
        );
    }
    let specs = crate::commands::events::parse_specs(&args.event)?;
    if let Some(e) = args.max_event_error {
        if e < 0.0 {
            bail!("--max-event-error: must be non-negative, got {e}");
        }
    }
    let mut config = args.method.config()?;
    if let Some(k) = args.dense {
        check_dense_option(k)?;
    }
    let mut external = None;
    if let Some(command) = &args.exec {
        external = Some(exec_integrator(
            command,
            config.tolerances,
            args.digits,
            args.timeout.exec_timeout,
        )?);
    } else if let Some(d) = args.digits {
        config = config.with_digits(d).context("--digits")?;
    }
    let case = args.case();
    case.validate().map_err(case_error)?;
    if args.pieces == 0 {
        bail!("--pieces: need at least 1");
    }
    if external.is_none() {
        // The point of N and the step budget of the built-in method over the whole grid.
        preflight(&case, &config).map_err(case_error)?;
    } else {
        case.reference_motion(64).map_err(case_error)?;
    }
    if let Some(path) = &args.mcap {
        output::check_output_bytes(
            "--samples",
            "the MCAP log",
            MCAP_BYTES_PER_SAMPLE * args.samples as f64,
        )?;
        let files = args.exec.as_deref().map(rsts_external::command_files);
        let inputs: Vec<_> = files
            .iter()
            .flatten()
            .map(|f| ("--exec", f.as_path()))
            .collect();
        rsts_io::check_outputs(&inputs, &[rsts_io::Output::File("--mcap", path)])?;
        rsts_io::check_writable(path).with_context(|| format!("--mcap {}", path.display()))?;
    }
    if let Some(svg) = &args.svg {
        let inputs = args.exec.as_deref().map(rsts_external::command_files);
        compare_diagram::check_output(
            svg,
            args.samples,
            args.mcap.as_deref(),
            &inputs.unwrap_or_default(),
        )?;
    }
    if external.is_none() {
        if let Some(s) = specs.iter().find(|s| s.name.index() >= 12) {
            bail!(
                "--event {}: the built-in methods locate events of functions of the state (omega, alpha, beta, gamma); the turning points of s1, s2 need an --exec integrator that reports them",
                s.name
            );
        }
    }
    if let Some(exec) = &mut external {
        exec.dense = args.dense;
        exec.events = specs
            .iter()
            .map(|s| {
                (
                    s.name.as_str().to_string(),
                    s.direction.as_str().to_string(),
                )
            })
            .collect();
    }
    let integrator: &mut dyn Integrator = match &mut external {
        Some(exec) => exec,
        None => &mut config,
    };
    let log = match &args.mcap {
        None => None,
        Some(path) => {
            let mut meta = serde_json::json!({
                "method": integrator.name(),
                "rtol": args.method.rtol,
                "atol": args.method.atol,
                "digits": rsts_dynamics::scalar::digits_for_bits(integrator.working_bits()),
            });
            if let Some(command) = &args.exec {
                meta["command"] = command.clone().into();
            }
            Some(open_log(path, &case, &meta)?)
        }
    };
    let stop = stop_on_ctrl_c();
    let mut observer = CliObserver::new(log, args.samples as u64, stop.clone());
    let options = CompareOptions {
        pieces: args.pieces,
    };
    let mut recorder = compare_diagram::Recorder::new(&mut observer, args.samples);
    let mut collector = StateCollector::new(&mut recorder);
    let result = compare_integrator(&case, integrator, &options, &mut collector);
    let (times, states, series) = (collector.times, collector.states, recorder.series);
    let report = match result {
        Ok(r) => r,
        Err(e) if stop.load(Ordering::SeqCst) => {
            // Stopped by Ctrl-C (an external integrator is killed at once): the log of what
            // was compared is finished.
            observer.finish()?;
            return Err(Interrupted(format!("interrupted: {e}")).into());
        }
        // A failed run discards its log: the temporary is removed, a previous file stays.
        Err(e) => return Err(case_error(e)),
    };
    let events = if specs.is_empty() {
        None
    } else {
        let answered = external.as_ref().and_then(|e| e.answered_events.clone());
        Some(
            events_of_run(&case, &specs, answered.as_deref(), &times, &states)
                .map_err(case_error)?,
        )
    };
    if let (Some(ev), Some(log)) = (&events, observer.log.as_mut()) {
        let marks: Vec<rsts_mcap::EventMark> = ev
            .per_event
            .iter()
            .map(|p| rsts_mcap::EventMark {
                name: p.name.clone(),
                t_exact: p.t_exact,
                t_detected: p.t_detected,
                time_error: p.time_error,
            })
            .collect();
        log.log_events(&marks)
            .map_err(|e| anyhow::anyhow!("--mcap: {}", rsts_io::error_text(&e)))?;
    }
    let dense = match (args.dense, &mut external) {
        (None, _) => None,
        (Some(k), Some(exec)) => {
            let samples = exec.answered_dense.take().ok_or_else(|| {
                anyhow::anyhow!("--dense: the external integrator gave no dense samples")
            })?;
            Some(dense_of_samples(&case, k, &samples).map_err(case_error)?)
        }
        (Some(k), None) => Some(dense_of_method(&case, &config, k).map_err(case_error)?),
    };
    let log_stats = observer.finish()?;
    check_finite_report(&report)?;
    if let Some(svg) = &args.svg {
        compare_diagram::write_svg(svg, &case.motion, &report, &series)?;
        eprintln!(
            "SVG: {}: the state error and the drifts of H, K, G against time.",
            svg.display()
        );
    }
    let mcap = args.mcap.as_ref().map(|p| p.display().to_string());
    let mut environment = Environment::detect();
    if let Some(exec) = &external {
        environment.record(exec);
    }
    let doc = Document {
        report: &report,
        mcap: mcap.clone(),
        events: events.clone(),
        dense,
        environment,
    };
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv => output::write_records_csv(out, &[&doc])?,
        Format::Table => {
            write_table(out, &report, &format!("0, {}", args.t_end), &case.motion)?;
            if let Some(ev) = &events {
                writeln!(out, "events: {}", ev.summary())?;
            }
            if let Some(d) = &dense {
                writeln!(out, "dense output: {}", d.summary())?;
            }
            writeln!(out, "{:<26}{}", "environment:", doc.environment.describe())?;
        }
    }
    if let (Some(path), Some(stats)) = (&mcap, log_stats) {
        eprintln!(
            "MCAP log: {path} ({} samples, {} messages). Open it in Foxglove or Lichtblick (Open local file), or run `{} inspect {path}`.",
            stats.samples,
            stats.messages,
            crate::invocation::invocation()
        );
    }
    if !report.complete {
        out.flush()?;
        return Err(Interrupted(format!(
            "interrupted: compared {} of {} samples; the report above and the MCAP file cover them",
            report.samples_compared, args.samples
        ))
        .into());
    }
    if let Some(why) = events
        .as_ref()
        .zip(args.max_event_error)
        .and_then(|(ev, limit)| ev.counts.failure(limit))
    {
        out.flush()?;
        return Err(crate::commands::validate::Failed(format!("{}: {why}", report.method)).into());
    }
    Ok(())
}

/// Check `--dense K` before any work: K from 1 to [`MAX_DENSE`] (every built-in has the dense
/// check; an external integrator is refused later if its answer has no steps).
pub(crate) fn check_dense_option(k: usize) -> anyhow::Result<()> {
    if !(1..=MAX_DENSE).contains(&k) {
        bail!("--dense: K must be between 1 and {MAX_DENSE} samples inside each step, got {k}");
    }
    Ok(())
}

/// A non-finite figure is an error naming it, never a number printed with exit 0.
pub(crate) fn check_finite_report(r: &Report) -> anyhow::Result<()> {
    rsts_harness::check_finite_report(r).map_err(|e| anyhow::anyhow!("{e}"))
}

/// The report as `key: value` lines; `span` is the time interval.
pub(crate) fn write_table(
    out: &mut dyn Write,
    r: &Report,
    span: &str,
    motion: &rsts_closed_form::Motion,
) -> anyhow::Result<()> {
    // The numbers as the report's JSON shows them (f64).
    let [a, b, m, h] = motion.parameters_f64();
    let torus = motion.torus;
    let e = |x: f64| format!("{x:.3e}");
    let mut items = vec![
        (
            "camera",
            format!(
                "{} (a = {a}, b = {b}, m = {m}, h = {h}, torus {torus})",
                r.camera
            ),
        ),
        (
            "method",
            format!(
                "{} ({}{} digits; reference {} digits)",
                r.method,
                match (r.rtol, r.atol) {
                    (Some(rtol), Some(atol)) => format!("rtol {rtol:e}, atol {atol:e}, "),
                    _ => String::new(),
                },
                r.digits,
                r.reference_digits
            ),
        ),
        (
            "samples",
            format!(
                "{} over [{span}]{}",
                r.samples_compared,
                if r.complete { "" } else { " (interrupted)" }
            ),
        ),
        ("max state error", e(r.max_state_error)),
        ("final state error", e(r.final_state_error)),
        (
            "max orientation error",
            format!("{} rad", e(r.max_orientation_error)),
        ),
        ("correct digits", digits_line(&r.correct_digits)),
        (
            "drift of H, K, G",
            format!("{}, {}, {}", e(r.drift.h), e(r.drift.k), e(r.drift.g)),
        ),
        ("constraint drift", e(r.drift.constraints)),
        (
            "drift growth",
            r.drift
                .growth
                .map_or_else(|| "-".to_string(), |g| g.describe()),
        ),
        ("drift of on-N relations", e(r.drift.off_n)),
        (
            "steps (rejected)",
            format!(
                "{} ({})",
                output::or_na(r.steps),
                output::or_na(r.rejected_steps)
            ),
        ),
        ("rhs evaluations", output::or_na(r.rhs_evals)),
        (
            "integration time",
            match (r.integration_seconds, r.wall_seconds) {
                (Some(s), Some(w)) => format!("{s:.6} s (process wall time {w:.6} s)"),
                (Some(s), None) => format!("{s:.6} s"),
                (None, Some(w)) => format!("n/a (process wall time {w:.6} s)"),
                (None, None) => output::NA.to_string(),
            },
        ),
    ];
    items.extend(geometry_lines(r));
    output::write_key_values(out, &items)?;
    Ok(())
}

/// `scd 9.81 (min 9.52), mescd 10.13 (min 9.84)`: at the last sample and the worst.
fn digits_line(d: &rsts_harness::CorrectDigits) -> String {
    let f = |x: f64| {
        if x.is_finite() {
            format!("{x:.2}")
        } else {
            "exact".to_string()
        }
    };
    format!(
        "scd {} (min {}), mescd {} (min {})",
        f(d.scd),
        f(d.scd_min),
        f(d.mescd),
        f(d.mescd_min)
    )
}

/// The geometry of the error (docs/stability.md): distance from N, phase error, what dominates.
fn geometry_lines(r: &Report) -> Vec<(&'static str, String)> {
    let e = |x: f64| format!("{x:.3e}");
    let grows = |g: &Option<rsts_harness::geometry::GrowthSummary>| match g {
        Some(g) => format!("grows like {}", g.describe()),
        None => "too few samples for a growth fit".to_string(),
    };
    let mut lines = Vec::new();
    if let Some(n) = &r.normal {
        lines.push((
            "distance from N",
            format!(
                "max {}, final {} ({}; N normally {} here)",
                e(n.distance_from_n.max),
                e(n.distance_from_n.last),
                grows(&n.growth),
                n.kind
            ),
        ));
    }
    if let Some(p) = &r.phase_error {
        lines.push((
            "phase error",
            format!(
                "psi1 max {}, psi2 max {} rad ({})",
                e(p.psi1.max),
                e(p.psi2.max),
                grows(&p.growth)
            ),
        ));
    }
    if let Some(s) = &r.error_split {
        lines.push((
            "the error is",
            format!(
                "{} (at t = {}: along N {}, off N {})",
                s.summary,
                (s.t * 1e6).round() / 1e6,
                e(s.along_n),
                e(s.departure_from_n)
            ),
        ));
    }
    lines
}
