//! `rsts compare`: integrate from the closed-form state at t = 0 and compare with the closed form
//! along the motion; report errors, drifts and cost; optionally log everything to MCAP. The
//! flow is the library's ([`rsts_flows::compare`]): this file parses the options into its
//! request and formats its outcome.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;

use rsts_flows::compare::{compare, CompareRequest, Method};
use rsts_flows::log::Mcap;
use rsts_flows::{Limits, Times};

use crate::args::{count, decimal, finite_f64, CaseArgs, MethodArgs};
use crate::external::{exec_integrator, TimeoutArgs};
use crate::output::{self, Format};
use crate::report_table::write_table;
use crate::watch::{flow_error, log_note, Failed, Interrupted, Watch};

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

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    // Everything is checked before any output exists: the options here, the rest by the flow.
    let events = crate::args::event_specs(&args.event)?;
    let mut config = args.method.config()?;
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
    let method = match &mut external {
        Some(exec) => Method::Outside(exec),
        None => Method::Builtin(config),
    };
    let request = CompareRequest {
        motion: args.case.motion(),
        times: Times::grid(args.t_end.clone(), args.samples),
        method,
        events,
        dense: args.dense,
        pieces: args.pieces,
        mcap: args.mcap.as_ref().map(|path| Mcap {
            path: path.clone(),
            command: args.exec.clone(),
        }),
        svg: args.svg.clone(),
        limits: Limits {
            max_event_error: args.max_event_error,
            ..Limits::default()
        },
    };
    let mut watch = Watch::new(Some(args.samples as u64), 1);
    let outcome = compare(request, &mut watch);
    watch.clear();
    let outcome = outcome.map_err(flow_error)?;
    match args.format {
        Format::Json => output::write_json(out, &outcome)?,
        Format::Csv => output::write_records_csv(out, &[&outcome])?,
        Format::Table => {
            let span = format!("0, {}", args.t_end);
            write_table(out, &outcome.report, &span, &args.case.motion())?;
            if let Some(ev) = &outcome.events {
                writeln!(out, "events: {}", ev.summary())?;
            }
            if let Some(d) = &outcome.dense {
                writeln!(out, "dense output: {}", d.summary())?;
            }
            writeln!(
                out,
                "{:<26}{}",
                "environment:",
                outcome.environment.describe()
            )?;
        }
    }
    log_note(outcome.mcap.as_deref(), outcome.log);
    if let Some(svg) = &args.svg {
        eprintln!(
            "SVG: {}: the state error and the drifts of H, K, G against time.",
            svg.display()
        );
    }
    if let Some(what) = outcome.stopped() {
        out.flush()?;
        return Err(Interrupted(format!(
            "interrupted: {what}; the report above and the MCAP file cover them"
        ))
        .into());
    }
    if let rsts_flows::Verdict::Fail(why) = &outcome.verdict {
        out.flush()?;
        return Err(Failed(why.join("; ")).into());
    }
    Ok(())
}
