//! `rsts bench`: work–precision measurement of integrators against the closed form (issue 5):
//! for each method and tolerance the largest state error over the samples, the integration time
//! (median of repeats), steps and right-hand-side evaluations; a table, JSON rows, and a
//! log–log diagram of error against time. External integrators (`--exec`, e.g. heyoka through
//! scripts/adapters/heyoka_adapter.py) are measured the same way and drawn dashed beside ours.
//! The flow is [`rsts_harness::bench()`]; this parses, calls and formats. An ensemble's shards
//! (`--shard K/N`) and their merge (`rsts bench merge`, [`merge`]) are
//! [`rsts_harness::bench::merge`]'s.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{anyhow, bail, Context};
use clap::{Args as ClapArgs, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use rsts_closed_form::Camera;
use rsts_dynamics::integrators::MethodName;
use rsts_harness::bench::{
    bench_ensemble, bench_with_dense, diagrams, BenchObserver, BenchReport, EnsemblePlan,
};
use rsts_harness::shard::Shard;
use rsts_harness::{BenchMethod, BenchRequest, Case, HarnessError};

mod bands;
mod merge;

use crate::args::{case_error, count, finite_f64, CaseArgs, MethodParser};
use crate::external::{ExecMethod, TimeoutArgs};
use crate::output::{self, Cell, Format, Tabular};

/// Shown at the end of `rsts bench --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the defaults: camera I+ (a=1, b=0.5, m=0.3, h=-0.375), T=100, 101 samples,
  # dop853 and taylor-f64 at 1e-8, 1e-10, 1e-12, 1e-14, median of 3 repeats
  rsts bench

  # f64 methods, JSON rows and a work-precision diagram
  rsts bench --methods dop853,dopri5,taylor-f64 --tolerances 1e-8,1e-10,1e-12,1e-14,1e-15 \\
      --format json --svg out/wp-f64.svg

  # cost in right-hand-side evaluations rather than seconds (fair to a Python integrator)
  rsts bench --methods dop853,taylor-f64 --cost rhs-evals --repeats 1 --svg out/wp-evals.svg

  # tolerance proportionality: max error = C tol^p fitted per method, a line per method in the
  # table, fits in the JSON, points and fitted lines in the SVG
  rsts bench --methods dop853,dopri5,taylor-f64 --tolerances 1e-6,1e-8,1e-10,1e-12,1e-14 \
      --repeats 1 --svg-tolerance out/tolerance.svg

  # extended and multiple precision (taylor-mp at 90 digits)
  rsts bench --methods taylor-dd,taylor-mp --digits 90 --tolerances 1e-20,1e-30,1e-50,1e-80

  # side by side with heyoka (an external integrator: scripts/install_adapters.sh heyoka)
  # needs: heyoka
  rsts bench --methods taylor-f64 --exec \".venv-adapters/bin/python scripts/adapters/heyoka_adapter.py f64\" \\
      --tolerances 1e-8,1e-10,1e-12,1e-14 --svg out/wp.svg

  # an ensemble: 18 motions, two from each camera (seed 2013 unless --seed), the median and
  # 5–95 % band of the error and time per method and tolerance; --svg shades the bands
  rsts bench --ensemble 18 --t-end 20 --repeats 1 --svg out/wp-ensemble.svg

  # the same ensemble in two shards (one per machine or task of a job array), then their merge
  # into the report of the whole ensemble: the same rows, fits and bands (docs/benchmarks.md)
  rsts bench --ensemble 18 --t-end 20 --repeats 1 --shard 1/2 --json out/ens-1.json
  rsts bench --ensemble 18 --t-end 20 --repeats 1 --shard 2/2 --json out/ens-2.json
  rsts bench merge out/ens-1.json out/ens-2.json --json out/ens.json --svg out/wp-ens.svg

  # any program speaking rsts-integrator/1 (docs/own-integrator.md); repeat --exec for more
  cargo build --release -p example-adapter-rk4
  rsts bench --exec target/release/example-adapter-rk4 --tolerances 1e-6,1e-8,1e-10

A tolerance below what a method can deliver (its unit round-off: 1e-17 for dop853, 1e-20 for
taylor-f64 and 1e-36 for taylor-dd, whose state is compensated) is skipped with a note on stderr.
taylor-mp runs at --digits D for all its tolerances; default: ceil(-log10(smallest tolerance)) + 10
digits; an external integrator gets its parameters and initial state with as many digits. The
closed-form reference is evaluated
64 bits beyond each method (at least 30 + 19 digits), once per precision. See docs/benchmarks.md.";

/// Options of `rsts bench`.
#[derive(Debug, Clone, ClapArgs)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Args {
    #[command(subcommand)]
    pub merge: Option<MergeCommand>,
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T > 0
    #[arg(long, value_name = "T", default_value = "100", value_parser = crate::args::decimal, allow_hyphen_values = true)]
    pub t_end: rsts_closed_form::Decimal,
    /// Number N >= 2 of samples evenly spaced on [0, T] where the error is measured
    #[arg(long, value_name = "N", default_value = "101", value_parser = count)]
    pub samples: usize,
    /// Methods, comma-separated (default: dop853,taylor-f64, or none when --exec is given)
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = MethodParser)]
    pub methods: Option<Vec<MethodName>>,
    /// An external integrator speaking rsts-integrator/1 (a command, split like a shell would);
    /// may be repeated. Its rows are named by its answer and drawn dashed
    #[arg(long, value_name = "COMMAND")]
    pub exec: Vec<String>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// Tolerances (rtol = atol), comma-separated
    #[arg(long, value_name = "LIST", default_value = "1e-8,1e-10,1e-12,1e-14", value_delimiter = ',', value_parser = finite_f64)]
    pub tolerances: Vec<f64>,
    /// Decimal digits of taylor-mp and of the requests to --exec integrators (10 to 10000;
    /// default: ceil(-log10(smallest tolerance)) + 10)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Runs per method and tolerance (1 to 1000); the time reported is their median
    #[arg(long, value_name = "K", default_value = "3", value_parser = count)]
    pub repeats: usize,
    /// Event NAME[:up|down|both] to locate (repeatable; docs/events.md): each row gets the events'
    /// counts and time errors (built-ins: one more untimed run, events located in its samples
    /// by Hermite interpolation; --exec: asked in the request)
    #[arg(long = "event", value_name = "NAME[:DIR]")]
    pub event: Vec<String>,
    /// With --event: exit with status 1 when a row misses an event or a time error exceeds E
    #[arg(long, value_name = "E", value_parser = finite_f64, requires = "event")]
    pub max_event_error: Option<f64>,
    /// Check the dense output of every row: K samples (1 to 64) inside each of the integrator's
    /// own steps, evaluated by its interpolant (one more, untimed run; docs/compare.md): the
    /// columns dense_max_error and step_max_error
    #[arg(long, value_name = "K")]
    pub dense: Option<usize>,
    /// Run over an ensemble of N motions (1 to 1000) drawn from the cameras (docs/benchmarks.md):
    /// --m, --h, --torus and the phases are replaced by each motion's; the table shows per method
    /// and tolerance the median and 5–95 % band of the error and time, the JSON adds the motions,
    /// the bands and each row's motion, --svg draws the bands
    #[arg(long, value_name = "N", value_parser = count)]
    pub ensemble: Option<usize>,
    /// Seed of the ensemble's motions (the same seed draws the same motions)
    #[arg(long, value_name = "S", default_value_t = rsts_harness::ensemble::DEFAULT_SEED, requires = "ensemble")]
    pub seed: u64,
    /// Cameras the ensemble's motions are drawn from, comma-separated (I+, I-, II+, II-, III,
    /// IV+, IV-, V, VI; default: all nine), in turn
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = camera, requires = "ensemble")]
    pub cameras: Vec<Camera>,
    /// Run only shard K of N of the ensemble (1 <= K <= N): the motions whose index is K-1 mod N;
    /// its report (--json) is for `rsts bench merge`, which joins the N shards
    #[arg(long, value_name = "K/N", requires = "ensemble")]
    pub shard: Option<String>,
    #[command(flatten)]
    pub output: Outputs,
}

/// Where a benchmark's report goes: stdout in a format, and files (`rsts bench` and
/// `rsts bench merge` alike).
#[derive(Debug, Clone, ClapArgs)]
pub struct Outputs {
    /// Write the work-precision diagram (max error against seconds, log-log) to this SVG file
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// The cost the work-precision diagram draws against the error (its vertical axis):
    /// seconds favour compiled code over a Python integrator, evaluations and steps do not.
    /// The table shows all three
    #[arg(long, visible_alias = "x-axis", value_enum, value_name = "COST", default_value_t = Cost::Seconds)]
    pub cost: Cost,
    /// Write the tolerance-proportionality diagram (max error against tolerance, log-log, with
    /// each method's fitted C·tol^p) to this SVG file
    #[arg(long, value_name = "FILE")]
    pub svg_tolerance: Option<PathBuf>,
    /// Write the JSON report (that of --format json) to this file too, whole or not at all
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

#[derive(Debug, Clone, Subcommand)]
pub enum MergeCommand {
    /// Join the shards of an ensemble (`rsts bench --ensemble N --shard K/N --json FILE`) into
    /// the report of the whole ensemble
    Merge(merge::Args),
}

/// A camera label of Table 1.
fn camera(s: &str) -> Result<Camera, String> {
    s.trim().parse()
}

impl Args {
    fn case(&self) -> Case {
        self.case.case(&self.t_end, self.samples)
    }
}

/// The cost axis of the work-precision diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Cost {
    Seconds,
    RhsEvals,
    Steps,
}

impl From<Cost> for diagrams::Cost {
    fn from(c: Cost) -> Self {
        match c {
            Cost::Seconds => diagrams::Cost::Seconds,
            Cost::RhsEvals => diagrams::Cost::RhsEvals,
            Cost::Steps => diagrams::Cost::Steps,
        }
    }
}

/// Notes to stderr, and a progress bar on a terminal once a benchmark has run a second.
struct Progress {
    bar: ProgressBar,
    started: Instant,
    shown: bool,
}

impl BenchObserver for Progress {
    fn note(&mut self, text: &str) {
        eprintln!("{text}");
    }

    fn start(&mut self, total: usize) {
        self.bar.set_length(total as u64);
        self.started = Instant::now();
    }

    fn running(&mut self, what: &str) -> Result<(), HarnessError> {
        self.bar.set_message(what.to_string());
        Ok(())
    }

    fn done(&mut self) {
        output::tick_progress(&self.bar, self.started, &mut self.shown);
    }
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if let Some(MergeCommand::Merge(m)) = args.merge {
        return merge::run(m, out);
    }
    let case = args.case();
    let specs = crate::args::event_specs(&args.event)?;
    if let Some(e) = args.max_event_error {
        if e < 0.0 {
            bail!("--max-event-error: must be non-negative, got {e}");
        }
    }
    let shard: Option<Shard> = args
        .shard
        .as_deref()
        .map(str::parse)
        .transpose()
        .map_err(case_error)?;
    // The program files an --exec command names are inputs no output may replace.
    let files: Vec<PathBuf> = args
        .exec
        .iter()
        .flat_map(|c| rsts_external::command_files(c))
        .collect();
    args.output.check("--exec", &files)?;
    let default_methods = [MethodName::Dop853, MethodName::TaylorF64];
    let given = match &args.methods {
        Some(m) => m.as_slice(),
        None if args.exec.is_empty() => &default_methods,
        None => &[],
    };
    let mut execs: Vec<ExecMethod> = args
        .exec
        .iter()
        .map(|command| ExecMethod {
            command: command.clone(),
            timeout: args.timeout.exec_timeout,
        })
        .collect();
    let mut methods: Vec<BenchMethod> = given.iter().map(|m| BenchMethod::BuiltIn(*m)).collect();
    methods.extend(execs.iter_mut().map(|e| BenchMethod::Outside(e)));
    let request = BenchRequest {
        case,
        methods,
        tolerances: args.tolerances.clone(),
        repeats: args.repeats,
        digits: args.digits,
        events: specs,
    };
    let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{spinner} bench [{bar:30}] {pos}/{len} {msg} {elapsed}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let mut progress = Progress {
        bar,
        started: Instant::now(),
        shown: false,
    };
    if let Some(k) = args.dense {
        rsts_flows::compare::check_dense(k).map_err(crate::failure::flow_error)?;
        if args.ensemble.is_some() {
            bail!("--dense: not with --ensemble (the dense check is one more run per row of one motion)");
        }
    }
    let report = match args.ensemble {
        Some(n) => {
            let plan = EnsemblePlan {
                n,
                seed: args.seed,
                cameras: args.cameras.clone(),
                shard,
            };
            bench_ensemble(request, &plan, &mut progress)
        }
        None => bench_with_dense(request, args.dense, &mut progress),
    }
    .map_err(case_error)?;
    progress.bar.finish_and_clear();

    args.output.write(&report, out)?;
    if let Some(limit) = args.max_event_error {
        for (row, l) in report.rows.iter().zip(&report.labels) {
            if let Some(why) = row.events.and_then(|ev| ev.failure(limit)) {
                out.flush()?;
                return Err(crate::failure::Failed(format!(
                    "{} at tolerance {:e}: {why}",
                    l.label, row.tolerance
                ))
                .into());
            }
        }
    }
    Ok(())
}

impl Outputs {
    /// Refuse at once an output file that cannot be written, that is one of `inputs` (the same
    /// file by device and inode: a path, a hard link or a symbolic link) or another output.
    fn check(&self, what: &str, inputs: &[PathBuf]) -> anyhow::Result<()> {
        let outputs: Vec<(&str, &PathBuf)> = [
            ("--svg", &self.svg),
            ("--svg-tolerance", &self.svg_tolerance),
            ("--json", &self.json),
        ]
        .into_iter()
        .filter_map(|(option, path)| path.as_ref().map(|p| (option, p)))
        .collect();
        let named: Vec<rsts_io::Input> = inputs.iter().map(|p| (what, p.as_path())).collect();
        let files: Vec<rsts_io::Output> = outputs
            .iter()
            .map(|(option, p)| rsts_io::Output::File(option, p.as_path()))
            .collect();
        rsts_io::check_outputs(&named, &files)?;
        for (option, path) in outputs {
            rsts_io::check_writable(path)
                .with_context(|| format!("{option} {}", path.display()))?;
        }
        Ok(())
    }

    /// The diagrams and the JSON file (each written whole), then the report on `out`.
    fn write(&self, report: &BenchReport, out: &mut dyn Write) -> anyhow::Result<()> {
        if let Some(path) = &self.svg {
            let cost = diagrams::Cost::from(self.cost);
            for label in cost.left_out(report) {
                eprintln!(
                    "note: --svg: {label} left out of the diagram: its {} are not known",
                    cost.name()
                );
            }
            let chart = diagrams::work_precision(report, cost);
            let svg = rsts_plots::render_svg(&chart).map_err(|e| anyhow!("--svg: {e}"))?;
            rsts_io::write_atomic(path, svg.as_bytes())
                .with_context(|| format!("--svg {}", path.display()))?;
            eprintln!("work-precision diagram: {}", path.display());
        }
        if let Some(path) = &self.svg_tolerance {
            let chart = diagrams::tolerance_proportionality(report);
            let svg =
                rsts_plots::render_svg(&chart).map_err(|e| anyhow!("--svg-tolerance: {e}"))?;
            rsts_io::write_atomic(path, svg.as_bytes())
                .with_context(|| format!("--svg-tolerance {}", path.display()))?;
            eprintln!("tolerance-proportionality diagram: {}", path.display());
        }
        if let Some(path) = &self.json {
            let mut json = Vec::new();
            output::write_json(&mut json, report)?;
            rsts_io::write_atomic(path, &json)
                .with_context(|| format!("--json {}", path.display()))?;
            eprintln!("report: {}", path.display());
        }
        match self.format {
            Format::Json => output::write_json(out, report)?,
            Format::Csv => output::write_records_csv(out, &report.rows)?,
            Format::Table if report.ensemble.is_some() => bands::write_table(out, report)?,
            Format::Table => {
                let case = &report.case;
                writeln!(
                    out,
                    "a = {}, b = {}, m = {}, h = {}, torus {}, T = {}, {} samples; time: median of {} runs",
                    case.motion.a, case.motion.b, case.motion.m, case.motion.h, case.motion.torus, case.t_end, case.samples, report.repeats
                )?;
                writeln!(out, "{}", report.environment.describe())?;
                output::write_table(out, &table(report))?;
                write_fits(out, report, "")?;
            }
        }
        Ok(())
    }
}

/// A line `fit METHOD{qualifier}: …` per tolerance fit.
fn write_fits(out: &mut dyn Write, report: &BenchReport, qualifier: &str) -> anyhow::Result<()> {
    for f in &report.fits {
        let label = report.label_of_method(&f.method);
        writeln!(out, "fit {label}{qualifier}: {}", f.describe())?;
    }
    Ok(())
}

/// The rows as a table, rounded for reading (CSV and JSON carry the full precision).
fn table(report: &BenchReport) -> Tabular {
    let with_events = report.rows.iter().any(|r| r.events.is_some());
    let mut header = vec![
        "method",
        "tolerance",
        "max error",
        "scd min",
        "mescd min",
        "seconds (min..max)",
        "steps",
        "rhs evals",
    ];
    if with_events {
        header.extend(["events missed", "max event error"]);
    }
    let with_dense = report.rows.iter().any(|r| r.dense.is_some());
    if with_dense {
        header.extend(["step max error", "dense max error"]);
    }
    let mut t = Tabular::new(header);
    for (r, l) in report.rows.iter().zip(&report.labels) {
        let mut row = vec![
            Cell::Text(l.label.clone()),
            Cell::Text(format!("{:e}", r.tolerance)),
            Cell::Text(format!("{:.2e}", r.max_error)),
            Cell::Text(format!("{:.2}", r.correct_digits.scd_min)),
            Cell::Text(format!("{:.2}", r.correct_digits.mescd_min)),
            Cell::Text(format!(
                "{:.3e} ({:.2e}..{:.2e})",
                r.integration_seconds, r.time_min, r.time_max
            )),
            Cell::Text(output::or_na(r.steps)),
            Cell::Text(output::or_na(r.rhs_evals)),
        ];
        if with_events {
            let ev = r.events.as_ref();
            row.push(Cell::Text(
                ev.map_or("-".into(), |e| format!("{} of {}", e.missed, e.exact)),
            ));
            row.push(Cell::Text(
                ev.and_then(|e| e.max_time_error)
                    .map_or("-".into(), |x| format!("{x:.2e}")),
            ));
        }
        if let Some(d) = r.dense.as_ref().filter(|_| with_dense) {
            row.push(Cell::Text(format!("{:.2e}", d.step_max_error)));
            row.push(Cell::Text(format!("{:.2e}", d.dense_max_error)));
        }
        t.push(row);
    }
    t
}
