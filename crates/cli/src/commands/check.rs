//! `rsts check FILE`: a trajectory computed elsewhere (CSV, JSON, npy, or the integrated channel
//! of an rsts MCAP log) against the closed-form motion on N — given by (m, h, torus, phases) or
//! identified from the first row — with the report of `rsts compare`. The flow is the
//! library's ([`rsts_flows::check`]): this file parses the options into its request and
//! formats its outcome.

use std::io::Write;
use std::path::PathBuf;

use anyhow::bail;
use clap::Args as ClapArgs;

use rsts_closed_form::{Decimal, Motion};
use rsts_external::FileFormat;
use rsts_flows::check::{check, CheckRequest, DetectedEvents, Source};
use rsts_flows::log::Mcap;
use rsts_flows::{Limits, Verdict};
use rsts_harness::CheckMotion;

use crate::args::{decimal, finite_f64, ExactFieldArgs};
use crate::output::{self, Format};
use crate::report_table::write_table;
use crate::watch::{flow_error, log_note, Failed, Interrupted, Watch};

/// Shown at the end of `rsts check --help`.
pub const EXAMPLES: &str = "\
Examples:
  # a trajectory written by rsts integrate from the start of camera V's third torus
  # (rsts reference --m -0.7092 --h 1.5643 --torus 2 --times 0 prints that state)
  mkdir -p out
  rsts integrate --omega=-1.0788400339538464,-0.3702277283006931,0 \\
      --alpha=-0.5266712206715436,-0.8500690709091504,0 --beta=-0.8500690709091504,0.5266712206715436,0 \\
      --t-end 20 --samples 201 --method dopri5 --rtol 1e-9 --atol 1e-9 --format csv > out/traj.csv
  rsts check out/traj.csv

  # the motion given: camera V, third torus; fail (exit 1) above an error of 1e-6
  rsts check out/traj.csv --m -0.7092 --h 1.5643 --torus 2 --max-error 1e-6 --format json

  # log the comparison for a viewer
  rsts check out/traj.csv --mcap out/check.mcap

  # a trajectory on standard input
  rsts check - --input-format csv < out/traj.csv

FILE by extension: .csv (header t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3;
other columns ignored), .json ({\"samples\": [{\"t\", \"omega\", \"alpha\", \"beta\"}]}, and the
\"stats\" of `rsts integrate --format json`, reported as the run's cost), .npy
(float64, shape (N, 10), or (N, 13) as `rsts reference -o x.npy` writes it), .mcap
(/integrated/state of an rsts log). Times strictly increasing,
any spacing. Without --m/--h the motion is identified from the first row (which must lie on N).
Values with at most 17 significant digits are read as f64; a file with longer values is read
exactly at its precision. See docs/own-integrator.md.";

/// Options of `rsts check`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The trajectory: .csv, .json, .npy or .mcap; `-` reads standard input (with --input-format)
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Format of standard input (FILE `-`); a file's format is its extension
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub input_format: Option<InputFormat>,
    #[command(flatten)]
    pub fields: ExactFieldArgs,
    /// Value m of the partial integral of N (with --h; without both: identified from the first row)
    #[arg(long, value_name = "M", value_parser = decimal, allow_hyphen_values = true, requires = "h")]
    pub m: Option<Decimal>,
    /// Energy h (with --m)
    #[arg(long, value_name = "H", value_parser = decimal, allow_hyphen_values = true, requires = "m")]
    pub h: Option<Decimal>,
    /// Which Liouville torus (0-based; with --m/--h; default 0)
    #[arg(long, value_name = "K", requires = "m")]
    pub torus: Option<usize>,
    /// Angle psi1 on the torus at t = 0 (radians; with --m/--h; default 0)
    #[arg(long, value_name = "X", value_parser = decimal, allow_hyphen_values = true, requires = "m")]
    pub phase1: Option<Decimal>,
    /// Angle psi2 on the torus at t = 0 (radians; with --m/--h; default 0)
    #[arg(long, value_name = "Y", value_parser = decimal, allow_hyphen_values = true, requires = "m")]
    pub phase2: Option<Decimal>,
    /// Decimal digits the data carry (default: 15 for f64 data, else those of the longest value);
    /// the reference is evaluated 64 bits beyond (at least 30 digits)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Exit with status 1 when the max state error exceeds E
    #[arg(long, value_name = "E", value_parser = finite_f64)]
    pub max_error: Option<f64>,
    /// Report a first row far from the motion given (a start offset) without exiting 1
    #[arg(long)]
    pub allow_start_offset: bool,
    /// Events the integrator detected: CSV with columns name and t, or JSON {"events": [{"name", "t"}]}, matched
    /// with the exact events of the same names in (t_first, t_last] of the trajectory
    #[arg(long, value_name = "EVENTS")]
    pub events: Option<PathBuf>,
    /// With --events: also expect events of NAME (repeatable; names in the file are expected anyway)
    #[arg(long = "event", value_name = "NAME", requires = "events")]
    pub event: Vec<String>,
    /// With --events: exit with status 1 when an event is missed or a time error exceeds E
    #[arg(long, value_name = "E", value_parser = finite_f64, requires = "events")]
    pub max_event_error: Option<f64>,
    /// Write the comparison to this MCAP file (the layout of `rsts compare`; the file's trajectory
    /// is the integrated motion)
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Output format of the report
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    #[command(flatten)]
    pub jobs: crate::jobs::JobsArgs,
    /// Not for files (refused with why): see `rsts compare --dense`
    #[arg(long, value_name = "K", hide = true)]
    pub dense: Option<String>,
}

/// Formats `rsts check -` reads from standard input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum InputFormat {
    Csv,
    Json,
    Npy,
}

impl Args {
    /// The motion given (--m, --h, …) or to be identified.
    fn motion(&self) -> CheckMotion {
        let (a, b) = (self.fields.a.clone(), self.fields.b.clone());
        match (&self.m, &self.h) {
            (Some(m), Some(h)) => CheckMotion::Given(Motion {
                a,
                b,
                m: m.clone(),
                h: h.clone(),
                torus: self.torus.unwrap_or(0),
                phase1: self.phase1.clone().unwrap_or_default(),
                phase2: self.phase2.clone().unwrap_or_default(),
            }),
            _ => CheckMotion::Identify { a, b },
        }
    }

    /// FILE, or standard input in the format given.
    fn source(&self) -> anyhow::Result<Source> {
        if self.file.as_os_str() != "-" {
            if self.input_format.is_some() {
                bail!("--input-format: only for standard input (FILE -); a file's format is its extension");
            }
            return Ok(Source::File(self.file.clone()));
        }
        let format = match self.input_format {
            None => bail!(
                "FILE -: give the format of standard input with --input-format csv, json or npy"
            ),
            Some(InputFormat::Csv) => FileFormat::Csv,
            Some(InputFormat::Json) => FileFormat::Json,
            Some(InputFormat::Npy) => FileFormat::Npy,
        };
        Ok(Source::Stream {
            input: Box::new(std::io::stdin()),
            format,
        })
    }
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if args.dense.is_some() {
        bail!("--dense: a trajectory file does not say where its integrator's steps are or how it interpolates; check dense output with `rsts compare --dense K` (a built-in method, or --exec with an adapter that reports its step times)");
    }
    let request = CheckRequest {
        motion: args.motion(),
        source: args.source()?,
        digits: args.digits,
        events: args.events.clone().map(DetectedEvents::File),
        expect: crate::args::event_specs(&args.event)?,
        mcap: args.mcap.clone().map(Mcap::at),
        jobs: args.jobs.jobs,
        limits: Limits {
            max_error: args.max_error,
            max_event_error: args.max_event_error,
            allow_start_offset: args.allow_start_offset,
        },
    };
    // Samples come in microseconds: the bar is ticked every 256.
    let mut watch = Watch::new(None, 256);
    let outcome = check(request, &mut watch);
    watch.clear();
    let outcome = outcome.map_err(flow_error)?;
    let report = &outcome.report;
    let case = &report.case;
    if let Some(offset) = &report.start_offset {
        eprintln!("warning: {}: {}", report.file, offset.describe());
    }
    match args.format {
        Format::Json => output::write_json(out, &outcome)?,
        Format::Csv => output::write_records_csv(out, &[&outcome])?,
        Format::Table => {
            let how = match case.identified {
                true => "identified from the first row",
                false => "given",
            };
            let (p1, p2) = (case.motion.phase1.to_f64(), case.motion.phase2.to_f64());
            output::write_key_values(
                out,
                &[
                    ("file", report.file.clone()),
                    (
                        "motion",
                        format!("{how} (phases {p1:.12}, {p2:.12} at t = 0)"),
                    ),
                    (
                        "start state error",
                        format!("{:.3e}", report.start_state_error),
                    ),
                ],
            )?;
            let (t_first, t_last) = report.span;
            let span = format!("{t_first}, {t_last}");
            write_table(out, &report.report, &span, &case.motion)?;
            if let Some(ev) = &outcome.events {
                writeln!(out, "events: {}", ev.summary())?;
            }
        }
    }
    log_note(outcome.mcap.as_deref(), outcome.log);
    if let Some(what) = outcome.stopped() {
        out.flush()?;
        return Err(Interrupted(format!("interrupted: {what}")).into());
    }
    if let Verdict::Fail(why) = &outcome.verdict {
        out.flush()?;
        return Err(Failed(why.join("; ")).into());
    }
    Ok(())
}
