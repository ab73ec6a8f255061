//! `rsts compare`: integrate from the closed-form state at t = 0 and compare with the closed form
//! along the motion; report errors, drifts and cost; optionally log everything to MCAP.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

use rsts_harness::{compare, Case, Observer, Report, SampleRecord};
use rsts_mcap::{BodyState, ErrorSample, Metadata, Sample, TrajectoryLog};

use crate::args::{count, finite_f64, CaseArgs, MethodArgs, MAX_SAMPLES};
use crate::output::{self, Format};

/// Shown at the end of `rsts compare --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the built-in default case: camera I+ (a=1, b=0.5, m=0.3, h=-0.375), T=100, 1001 samples, dop853 at 1e-12
  rsts compare --mcap out/compare.mcap

  # a loose Dopri5 run in camera V on its third torus, JSON report
  rsts compare --m -0.7092 --h 1.5643 --torus 2 --method dopri5 --rtol 1e-6 --atol 1e-6 --format json

  # the Taylor integrator at 60 digits (the closed form is evaluated 64 bits beyond it)
  rsts compare --method taylor-mp --digits 60 --rtol 1e-55 --atol 1e-55 --t-end 20 --samples 21

Open the MCAP file in Foxglove or Lichtblick (Open local file) with the layout
docs/foxglove/compare.json (Layouts > Import layout); see docs/mcap.md for the channels.
Ctrl-C stops the run after the current piece and still leaves a complete, readable MCAP file.";

/// Options of `rsts compare`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T >= 0
    #[arg(long, value_name = "T", default_value = "100", value_parser = finite_f64, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Number N >= 1 of samples evenly spaced on [0, T]
    #[arg(long, value_name = "N", default_value = "1001", value_parser = count)]
    pub samples: usize,
    #[command(flatten)]
    pub method: MethodArgs,
    /// Decimal digits of taylor-mp (10 to 10000; default 50)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Write the comparison to this MCAP file (Foxglove schemas)
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Output format of the report
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

impl Args {
    fn case(&self) -> Case {
        self.case.case(self.t_end, self.samples)
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

/// Logs samples to MCAP, advances the progress bar, and watches Ctrl-C.
struct CliObserver {
    log: Option<TrajectoryLog>,
    bar: ProgressBar,
    shown: bool,
    started: Instant,
    stop: Arc<AtomicBool>,
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
                }),
            })
            .map_err(|e| format!("writing the MCAP file: {e}"))?;
        }
        // Show the bar only for runs longer than a second, and only on a terminal.
        if !self.shown
            && self.started.elapsed() > Duration::from_secs(1)
            && std::io::stderr().is_terminal()
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        self.bar.inc(1);
        Ok(())
    }

    fn should_stop(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

/// The JSON of `rsts compare`: the report plus where the log went.
#[derive(Serialize)]
struct Document<'a> {
    #[serde(flatten)]
    report: &'a Report,
    #[serde(skip_serializing_if = "Option::is_none")]
    mcap: Option<String>,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if args.samples > MAX_SAMPLES {
        bail!(
            "--samples: at most {MAX_SAMPLES} samples are supported, got {}",
            args.samples
        );
    }
    let mut config = args.method.config()?;
    if let Some(d) = args.digits {
        config = config.with_digits(d).context("--digits")?;
    }
    let case = args.case();
    case.validate().map_err(|e| anyhow::anyhow!("{e}"))?;
    let log = match &args.mcap {
        None => None,
        Some(path) => {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("--mcap: cannot create {}", dir.display()))?;
            }
            let integrator = serde_json::json!({
                "method": config.method.as_str(),
                "rtol": config.tolerances.rtol,
                "atol": config.tolerances.atol,
                "digits": rsts_dynamics::scalar::digits_for_bits(config.working_bits()),
            });
            let meta = Metadata::new(
                concat!("rsts ", env!("CARGO_PKG_VERSION")),
                &case,
                &integrator,
            )?;
            Some(
                TrajectoryLog::create(path, &meta)
                    .with_context(|| format!("--mcap {}", path.display()))?,
            )
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // A second Ctrl-C exits at once (the MCAP file then keeps all but the open chunk).
        let _ = ctrlc::set_handler(move || {
            if stop.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
    let bar =
        ProgressBar::with_draw_target(Some(args.samples as u64), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} comparing [{bar:40}] {pos}/{len} samples, {elapsed} ({eta} left)",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let mut observer = CliObserver {
        log,
        bar,
        shown: false,
        started: Instant::now(),
        stop: stop.clone(),
    };
    let result = compare(&case, &config, &mut observer);
    observer.bar.finish_and_clear();
    let log_stats = match observer.log.take() {
        Some(log) => Some(log.finish().context("finishing the MCAP file")?),
        None => None,
    };
    let report = result.map_err(|e| anyhow::anyhow!("{e}"))?;
    let mcap = args.mcap.as_ref().map(|p| p.display().to_string());
    match args.format {
        Format::Json => output::write_json(
            out,
            &Document {
                report: &report,
                mcap: mcap.clone(),
            },
        )?,
        Format::Table | Format::Csv => write_table(out, &args, &report)?,
    }
    if let (Some(path), Some(stats)) = (&mcap, log_stats) {
        writeln!(
            out,
            "\nMCAP log: {path} ({} samples, {} messages). Open it in Foxglove or Lichtblick (Open local file), or run `rsts inspect {path}`.",
            stats.samples, stats.messages
        )?;
    }
    if !report.complete {
        out.flush()?;
        return Err(Interrupted(format!(
            "interrupted: compared {} of {} samples; the report above and the MCAP file cover them",
            report.samples_compared, args.samples
        ))
        .into());
    }
    Ok(())
}

fn write_table(out: &mut dyn Write, args: &Args, r: &Report) -> anyhow::Result<()> {
    let e = |x: f64| format!("{x:.3e}");
    output::write_key_values(
        out,
        &[
            (
                "camera",
                format!(
                    "{} (a = {}, b = {}, m = {}, h = {}, torus {})",
                    r.camera,
                    args.case.fields.a,
                    args.case.fields.b,
                    args.case.m,
                    args.case.h,
                    args.case.torus
                ),
            ),
            (
                "method",
                format!(
                    "{} (rtol {:e}, atol {:e}, {} digits; reference {} digits)",
                    r.method, r.rtol, r.atol, r.digits, r.reference_digits
                ),
            ),
            (
                "samples",
                format!(
                    "{} over [0, {}]{}",
                    r.samples_compared,
                    args.t_end,
                    if r.complete { "" } else { " (interrupted)" }
                ),
            ),
            ("max state error", e(r.max_state_error)),
            ("final state error", e(r.final_state_error)),
            (
                "max orientation error",
                format!("{} rad", e(r.max_orientation_error)),
            ),
            (
                "drift of H, K, G",
                format!("{}, {}, {}", e(r.drift.h), e(r.drift.k), e(r.drift.g)),
            ),
            ("constraint drift", e(r.drift.constraints)),
            ("distance from N", e(r.drift.off_n)),
            (
                "steps (rejected)",
                format!("{} ({})", r.steps, r.rejected_steps),
            ),
            ("rhs evaluations", r.rhs_evals.to_string()),
            (
                "integration time",
                format!("{:.6} s", r.integration_seconds),
            ),
        ],
    )?;
    Ok(())
}
