//! `rsts check FILE`: a trajectory computed elsewhere (CSV, JSON, npy, or the integrated channel
//! of an rsts MCAP log) against the closed-form motion on N — given by (m, h, torus, phases) or
//! identified from the first row — with the report of `rsts compare`.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{anyhow, bail, Context};
use clap::Args as ClapArgs;
use serde::Serialize;

use rsts_closed_form::{Decimal, Motion};
use rsts_dynamics::State;
use rsts_external::{F64Chunk, Survey, TrajectoryReader};
use rsts_harness::events::{exact_event_times, match_events, read_detected, EventMatchReport};
use rsts_harness::{CheckMotion, CheckReport, CheckRequest, CheckStream};

use crate::args::{case_error, decimal, finite_f64, ExactFieldArgs};
use crate::commands::compare::{
    check_finite_report, open_log, stop_on_ctrl_c, write_table, CliObserver, Interrupted,
};
use crate::commands::validate::Failed;
use crate::output::{self, Format};

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

/// The JSON of `rsts check`: the library's report and where the log went.
/// Formats `rsts check -` reads from standard input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum InputFormat {
    Csv,
    Json,
    Npy,
}

/// The first chunk of a trajectory: as f64 numbers for f64 data (analysed in double-double),
/// as read otherwise (high-precision data).
enum FirstChunk {
    F64(F64Chunk),
    Read(rsts_external::RawTrajectory),
}

/// A file opened for f64 data in one pass ([`TrajectoryReader::open_f64`]) has a value of
/// more than 17 digits at this place: `rsts check` reads it again, surveyed.
#[derive(Debug)]
struct HighPrecisionFile(String);

impl std::fmt::Display for HighPrecisionFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: a value of more than 17 digits", self.0)
    }
}

impl std::error::Error for HighPrecisionFile {}

/// The trajectory of FILE (`one_pass`: opened for f64 data, [`TrajectoryReader::open_f64`];
/// else read through once first: its survey), or of standard input for `-` (surveyed from its
/// first chunk), and its first chunk.
fn open_input(
    args: &Args,
    one_pass: bool,
) -> anyhow::Result<(TrajectoryReader, Survey, FirstChunk)> {
    use rsts_external::FileFormat;
    let (mut reader, survey) = if args.file.as_os_str() != "-" {
        if args.input_format.is_some() {
            bail!("--input-format: only for standard input (FILE -); a file's format is its extension");
        }
        let open = match one_pass {
            true => TrajectoryReader::open_f64,
            false => TrajectoryReader::open_surveyed,
        };
        let (reader, survey) = open(&args.file).map_err(|e| anyhow!("{e}"))?;
        (reader, Some(survey))
    } else {
        let Some(format) = args.input_format else {
            bail!("FILE -: give the format of standard input with --input-format csv, json or npy");
        };
        let format = match format {
            InputFormat::Csv => FileFormat::Csv,
            InputFormat::Json => FileFormat::Json,
            InputFormat::Npy => FileFormat::Npy,
        };
        let input = Box::new(std::io::stdin());
        let reader =
            TrajectoryReader::from_reader(input, format, "<stdin>").map_err(|e| anyhow!("{e}"))?;
        (reader, None)
    };
    if let Some(mut survey) = survey.filter(|s| !s.is_high_precision()) {
        let mut first = F64Chunk::default();
        if !reader
            .next_chunk_f64(&mut first)
            .map_err(|e| anyhow!("{e}"))?
        {
            bail!("no samples");
        }
        if let Some(place) = first.long_at.as_ref().filter(|_| reader.reread_if_long()) {
            return Err(HighPrecisionFile(place.clone()).into());
        }
        survey.add_times(&first.times);
        return Ok((reader, survey, FirstChunk::F64(first)));
    }
    let first = reader
        .next_chunk()
        .map_err(|e| anyhow!("{e}"))?
        .context("no samples")?;
    let survey = survey.unwrap_or_else(|| reader.survey_of_first(&first));
    let first = if survey.is_high_precision() {
        FirstChunk::Read(first)
    } else {
        FirstChunk::F64(F64Chunk::of_raw(&first))
    };
    Ok((reader, survey, first))
}

#[derive(Serialize)]
struct Document<'a> {
    #[serde(flatten)]
    report: &'a CheckReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    mcap: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    events: Option<EventMatchReport>,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    // A file is read in one pass as f64 data, and again, surveyed, when it has a longer value
    // (nothing is written before the analysis ends).
    match run_reading(&args, out, true) {
        Err(e) if e.is::<HighPrecisionFile>() => run_reading(&args, out, false),
        done => done,
    }
}

/// [`run`], FILE opened in one pass or surveyed ([`open_input`]).
fn run_reading(args: &Args, out: &mut dyn Write, one_pass: bool) -> anyhow::Result<()> {
    if args.dense.is_some() {
        bail!("--dense: a trajectory file does not say where its integrator's steps are or how it interpolates; check dense output with `rsts compare --dense K` (a built-in method, or --exec with an adapter that reports its step times)");
    }
    if let Some(e) = args.max_error {
        if e < 0.0 {
            bail!("--max-error: must be non-negative, got {e}");
        }
    }
    if let Some(d) = args.digits {
        if !(1..=10_000).contains(&d) {
            bail!("--digits: must be between 1 and 10000, got {d}");
        }
    }
    let (a, b) = (args.fields.a.clone(), args.fields.b.clone());
    rsts_dynamics::Fields::new(a.to_f64(), b.to_f64()).map_err(|e| anyhow!("--a/--b: {e}"))?;
    let stdin = args.file.as_os_str() == "-";
    let name = args
        .file
        .file_name()
        .filter(|_| !stdin)
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| {
            if stdin {
                "<stdin>".to_string()
            } else {
                args.file.display().to_string()
            }
        });
    let mut request = CheckRequest {
        file: if stdin {
            "<stdin>".to_string()
        } else {
            args.file.display().to_string()
        },
        name,
        motion: match (&args.m, &args.h) {
            (Some(m), Some(h)) => CheckMotion::Given(Motion {
                a,
                b,
                m: m.clone(),
                h: h.clone(),
                torus: args.torus.unwrap_or(0),
                phase1: args.phase1.clone().unwrap_or_default(),
                phase2: args.phase2.clone().unwrap_or_default(),
            }),
            _ => CheckMotion::Identify { a, b },
        },
        digits: 15,
    };
    // The motion given is checked before the file is read.
    request.validate().map_err(case_error)?;
    if let Some(path) = &args.mcap {
        let mut inputs = vec![("FILE", args.file.as_path())];
        inputs.extend(args.events.as_deref().map(|e| ("--events", e)));
        rsts_io::check_outputs(&inputs, &[rsts_io::Output::File("--mcap", path)])?;
        rsts_io::check_writable(path).with_context(|| format!("--mcap {}", path.display()))?;
    }
    let detected = match &args.events {
        None => None,
        Some(path) => {
            Some(read_detected(path).map_err(|e| anyhow!("--events {}: {e}", path.display()))?)
        }
    };
    let mut event_specs = crate::commands::events::parse_specs(&args.event)?;
    if let Some(e) = args.max_event_error {
        if e < 0.0 {
            bail!("--max-event-error: must be non-negative, got {e}");
        }
    }
    let (mut reader, survey, first) = open_input(args, one_pass)?;
    let high = survey.is_high_precision();
    request.digits = match args.digits {
        Some(d) => d,
        None if high => survey.digits as u32,
        None => 15,
    };
    let bits = request.reference_bits();
    let (t0, state0) = match &first {
        FirstChunk::F64(c) => {
            let wide = |x: &f64| rug::Float::with_val(bits, *x);
            (
                wide(&c.times[0]),
                State::from_slice(&c.states[0].each_ref().map(wide)),
            )
        }
        FirstChunk::Read(raw) => {
            let s = raw.to_samples_at(bits, high);
            (s.times[0].clone(), s.states[0].clone())
        }
    };
    let start = rsts_harness::Check::start(&request, &t0, &state0, survey.extent).map_err(|e| {
        if matches!(request.motion, CheckMotion::Given(_)) {
            case_error(e)
        } else {
            anyhow!("{e}")
        }
    })?;
    let log = match &args.mcap {
        None => None,
        Some(path) => {
            let meta =
                serde_json::json!({"method": "check", "file": args.file.display().to_string()});
            Some(open_log(path, start.case(), &meta)?)
        }
    };
    let stop = stop_on_ctrl_c();
    // Samples come in microseconds: the bar is ticked every 256.
    let mut observer =
        CliObserver::new(log, survey.rows.unwrap_or(0) as u64, stop).ticking_every(256);
    if survey.rows.is_none() {
        // A CSV stream: its length is known at its end.
        observer.bar.unset_length();
    }
    let pool = args.jobs.pool()?;
    let mut stream = CheckStream::new(start);
    // Chunk after chunk: the reference of a chunk in parallel, its samples recorded in order.
    let analysed = pool.install(|| -> anyhow::Result<()> {
        match first {
            FirstChunk::F64(chunk) => {
                let more = stream
                    .feed_f64(&chunk.times, &chunk.states, &mut observer)
                    .map_err(|e| anyhow!("{e}"))?;
                drop(chunk);
                if more {
                    let rest =
                        rsts_external::check_rest_f64(&mut reader, &mut stream, &mut observer)
                            .map_err(|e| anyhow!("{e}"))?;
                    if let rsts_external::RestF64::HighPrecision(place) = rest {
                        return Err(HighPrecisionFile(place).into());
                    }
                }
            }
            FirstChunk::Read(raw) => {
                let samples = raw.to_samples_at(bits, high);
                drop(raw);
                let more = stream
                    .feed(&samples.times, &samples.states, &mut observer)
                    .map_err(|e| anyhow!("{e}"))?;
                drop(samples);
                if more {
                    rsts_external::check_rest(&mut reader, &mut stream, bits, high, &mut observer)
                        .map_err(|e| anyhow!("{e}"))?;
                }
            }
        }
        Ok(())
    });
    if let Err(e) = analysed {
        // A failed check discards its log: the temporary is removed, a previous file stays.
        observer.bar.finish_and_clear();
        drop(observer);
        return Err(e);
    }
    let mut report = stream.finish();
    let log_stats = observer.finish()?;
    // What the run cost is known only where the file states it (JSON `stats`).
    report.report.set_stated_stats(&reader.stated_stats());
    check_finite_report(&report.report)?;
    let mcap = args.mcap.as_ref().map(|p| p.display().to_string());
    let case = &report.case;
    let events = match &detected {
        None => None,
        Some(found) => {
            for d in found {
                if !event_specs.iter().any(|s| s.name == d.name) {
                    event_specs.push(rsts_closed_form::events::EventSpec {
                        name: d.name,
                        direction: Default::default(),
                    });
                }
            }
            let exact = exact_event_times(&case.motion, &event_specs, report.span.0, report.span.1)
                .map_err(|e| anyhow!("--events: {e}"))?;
            Some(match_events(&exact, found))
        }
    };
    if let Some(offset) = &report.start_offset {
        eprintln!("warning: {}: {}", args.file.display(), offset.describe());
    }
    let doc = Document {
        report: &report,
        mcap: mcap.clone(),
        events: events.clone(),
    };
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv => output::write_records_csv(out, &[&doc])?,
        Format::Table => {
            output::write_key_values(
                out,
                &[
                    ("file", report.file.clone()),
                    (
                        "motion",
                        format!(
                            "{} (phases {:.12}, {:.12} at t = 0)",
                            if case.identified {
                                "identified from the first row"
                            } else {
                                "given"
                            },
                            case.motion.phase1.to_f64(),
                            case.motion.phase2.to_f64()
                        ),
                    ),
                    (
                        "start state error",
                        format!("{:.3e}", report.start_state_error),
                    ),
                ],
            )?;
            let (t_first, t_last) = report.span;
            write_table(
                out,
                &report.report,
                &format!("{t_first}, {t_last}"),
                &case.motion,
            )?;
            if let Some(ev) = &events {
                writeln!(out, "events: {}", ev.summary())?;
            }
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
    if !report.report.complete {
        out.flush()?;
        let of = survey.rows.map_or(String::new(), |n| format!(" of {n}"));
        return Err(Interrupted(format!(
            "interrupted: checked {}{of} samples",
            report.report.samples_compared
        ))
        .into());
    }
    if let Some(why) = events
        .as_ref()
        .zip(args.max_event_error)
        .and_then(|(ev, limit)| ev.counts.failure(limit))
    {
        out.flush()?;
        return Err(Failed(format!("{}: {why}", args.file.display())).into());
    }
    if let (Some(offset), false) = (&report.start_offset, args.allow_start_offset) {
        out.flush()?;
        return Err(Failed(format!(
            "{}: start offset {:.3e} (--allow-start-offset to report it without failing)",
            args.file.display(),
            offset.error
        ))
        .into());
    }
    if let Some(limit) = args.max_error {
        let e = report.report.max_state_error;
        if e.is_nan() || e > limit {
            out.flush()?;
            return Err(Failed(format!(
                "{}: max state error {e:.3e} exceeds --max-error {limit:e}",
                args.file.display(),
            ))
            .into());
        }
    }
    Ok(())
}
