//! `rsts bench`: work–precision measurement of integrators against the closed form (issue 5):
//! for each method and tolerance the largest state error over the samples, the integration time
//! (median of repeats), steps and right-hand-side evaluations; a table, JSON rows, and a
//! log–log diagram of error against time. External integrators (`--exec`, e.g. heyoka through
//! scripts/adapters/heyoka_adapter.py) are measured the same way and drawn dashed beside ours.

use std::collections::btree_map::{BTreeMap, Entry};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context};
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances, MAX_MP_DIGITS};
use rsts_harness::{
    measure_against, measure_integrator, preflight, reference_bits, reference_bits_for, BenchRow,
    Case, Integrator, Reference,
};

mod plots;

use rsts_harness::environment::Environment;
use rsts_harness::proportionality::{fit_tolerances, ToleranceFit};

use rsts_harness::bench::run_once;
use rsts_harness::events::events_of_run;

use crate::args::{case_error, count, finite_f64, CaseArgs, MethodParser, MAX_SAMPLES};
use crate::external::{exec_integrator, TimeoutArgs};
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
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T > 0
    #[arg(long, value_name = "T", default_value = "100", value_parser = finite_f64, allow_hyphen_values = true)]
    pub t_end: f64,
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
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

impl Args {
    fn case(&self) -> Case {
        self.case.case(self.t_end, self.samples)
    }
}

/// The cost axis of the work-precision diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Cost {
    Seconds,
    RhsEvals,
    Steps,
}

impl Cost {
    /// The cost of a row.
    fn of(&self, row: &BenchRow) -> f64 {
        match self {
            Cost::Seconds => row.integration_seconds,
            Cost::RhsEvals => row.rhs_evals as f64,
            Cost::Steps => row.steps as f64,
        }
    }

    fn label(&self, repeats: usize) -> String {
        match self {
            Cost::Seconds => format!("integration seconds (median of {repeats})"),
            Cost::RhsEvals => "right-hand-side evaluations".into(),
            Cost::Steps => "accepted steps".into(),
        }
    }
}

/// The JSON of `rsts bench`: the case, the settings and the rows (built-in methods, then the
/// external integrators).
#[derive(Serialize)]
struct Document<'a> {
    case: &'a Case,
    repeats: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    taylor_mp_digits: Option<u32>,
    rows: &'a [BenchRow],
    /// Tolerance proportionality per method (two tolerances or more).
    fits: &'a [ToleranceFit],
    environment: &'a Environment,
}

/// A row with how it is labelled and drawn.
pub(crate) struct Labelled {
    pub(crate) row: BenchRow,
    pub(crate) label: String,
    /// An external integrator (drawn dashed).
    pub(crate) external: bool,
}

/// Default digits of taylor-mp for the smallest tolerance `tol`.
pub fn default_mp_digits(tol: f64) -> u32 {
    let d = (-tol.log10()).ceil().max(0.0) as u32 + 10;
    d.clamp(10, MAX_MP_DIGITS)
}

/// Most samples of a benchmark: the closed-form reference keeps every sample in high precision
/// (about 1 kB each).
pub const MAX_BENCH_SAMPLES: usize = 1_000_000;
/// Most repeats of each run.
pub const MAX_REPEATS: usize = 1000;
/// Most steps of a whole benchmark (every method, tolerance and repeat), as estimated up front.
pub const MAX_TOTAL_STEPS: f64 = 2e9;

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if args.samples > MAX_BENCH_SAMPLES {
        bail!(
            "--samples: at most {MAX_BENCH_SAMPLES} samples are supported by bench (the reference keeps them all in high precision), got {}",
            args.samples
        );
    }
    const { assert!(MAX_BENCH_SAMPLES <= MAX_SAMPLES) };
    let case = args.case();
    case.validate().map_err(case_error)?;
    let specs = crate::commands::events::parse_specs(&args.event)?;
    if let Some(e) = args.max_event_error {
        if e < 0.0 {
            bail!("--max-event-error: must be non-negative, got {e}");
        }
    }
    if !methods_only_state_events(&args, &specs) {
        bail!("--event: the built-in methods locate events of functions of the state (omega, alpha, beta, gamma), not the turning points s1, s2");
    }
    if args.t_end <= 0.0 || args.samples < 2 {
        bail!("--t-end/--samples: a benchmark needs T > 0 and at least 2 samples");
    }
    if !(1..=MAX_REPEATS).contains(&args.repeats) {
        bail!(
            "--repeats: need 1 to {MAX_REPEATS} repeats (the time is their median), got {}",
            rsts_dynamics::short(args.repeats as f64)
        );
    }
    if args.tolerances.is_empty() {
        bail!("--tolerances: give at least one tolerance");
    }
    for &tol in &args.tolerances {
        Tolerances::new(tol, tol).context("--tolerances")?;
    }
    let default_methods = [MethodName::Dop853, MethodName::TaylorF64];
    let given = match &args.methods {
        Some(m) => m.as_slice(),
        None if args.exec.is_empty() => &default_methods,
        None => &[],
    };
    let mut methods: Vec<MethodName> = Vec::new();
    for m in given {
        if !methods.contains(m) {
            methods.push(*m);
        }
    }
    if methods.is_empty() && args.exec.is_empty() {
        bail!("--methods: give at least one method (or an --exec integrator)");
    }
    if let Some(path) = &args.svg {
        rsts_io::check_writable(path).with_context(|| format!("--svg {}", path.display()))?;
    }
    if let Some(path) = &args.svg_tolerance {
        rsts_io::check_writable(path)
            .with_context(|| format!("--svg-tolerance {}", path.display()))?;
    }
    let smallest = args
        .tolerances
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    if let Some(d) = args.digits {
        if !(10..=MAX_MP_DIGITS).contains(&d) {
            bail!("--digits: must be between 10 and {MAX_MP_DIGITS}, got {d}");
        }
    }
    let mp_digits = match args.digits {
        Some(d) => d,
        None => default_mp_digits(smallest),
    };
    let uses_mp = methods.contains(&MethodName::TaylorMp);

    // Which runs to do; unreachable tolerances are noted and skipped.
    let mut jobs = Vec::new();
    for &method in &methods {
        for &tol in &args.tolerances {
            // The method's round-off, asked of a config at a tolerance it accepts (it refuses
            // one below its round-off, which bench skips instead).
            let mut probe = MethodConfig::new(method, Tolerances::new(1.0, 1.0)?, None)?;
            if method == MethodName::TaylorMp {
                probe = probe.with_digits(mp_digits).context("--digits")?;
            }
            let unit = probe.min_tolerance();
            if tol < unit {
                eprintln!(
                    "note: skipping {} at tolerance {tol:e}: below its unit round-off {unit:.2e}",
                    label_of(method, mp_digits)
                );
                continue;
            }
            let mut config = MethodConfig::new(method, Tolerances::new(tol, tol)?, None)?;
            if method == MethodName::TaylorMp {
                config = config.with_digits(mp_digits).context("--digits")?;
            }
            jobs.push(config);
        }
    }
    // External integrators: one run per command and tolerance, requests at `mp_digits` digits.
    let mut externals = Vec::new();
    for command in &args.exec {
        for &tol in &args.tolerances {
            externals.push(exec_integrator(
                command,
                Tolerances::new(tol, tol)?,
                Some(mp_digits),
                args.timeout.exec_timeout,
            )?);
        }
    }
    if jobs.is_empty() && externals.is_empty() {
        bail!(
            "--tolerances: no method can reach any of the tolerances given (all below round-off)"
        );
    }
    // Every job is checked (the point, the step budget) before any runs, the whole bench too.
    let mut total_steps = 0.0;
    for config in &jobs {
        preflight(&case, config).map_err(case_error)?;
        total_steps += estimate_steps(&case, config)? * args.repeats as f64;
    }
    if total_steps > MAX_TOTAL_STEPS {
        bail!(
            "--repeats/--tolerances/--t-end: the benchmark needs at least about {} steps in all ({} runs of {} repeats), more than the limit of {}; ask for fewer",
            rsts_dynamics::short(total_steps),
            jobs.len(),
            args.repeats,
            rsts_dynamics::short(MAX_TOTAL_STEPS)
        );
    }
    if let Some(path) = &args.svg {
        rsts_io::check_writable(path).with_context(|| format!("--svg {}", path.display()))?;
    }
    if let Some(path) = &args.svg_tolerance {
        rsts_io::check_writable(path)
            .with_context(|| format!("--svg-tolerance {}", path.display()))?;
    }

    let bar = ProgressBar::with_draw_target(
        Some((jobs.len() + externals.len()) as u64),
        ProgressDrawTarget::hidden(),
    );
    bar.set_style(
        ProgressStyle::with_template("{spinner} bench [{bar:30}] {pos}/{len} {msg} {elapsed}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let started = Instant::now();
    let mut shown = false;
    let mut references: BTreeMap<u32, Reference> = BTreeMap::new();
    let mut rows: Vec<Labelled> = Vec::new();
    let mut reference_at = |bits: u32| -> anyhow::Result<Reference> {
        Ok(match references.entry(bits) {
            Entry::Occupied(e) => e.get().clone(),
            Entry::Vacant(e) => e
                .insert(Reference::new(&case, bits).map_err(|e| anyhow!("{e}"))?)
                .clone(),
        })
    };
    let mut tick = |bar: &ProgressBar| {
        if !shown && started.elapsed() > Duration::from_secs(1) && std::io::stderr().is_terminal() {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
        bar.inc(1);
    };
    for config in &jobs {
        let label = label_of(config.method, mp_digits);
        bar.set_message(format!("{label} at {:e}", config.tolerances.rtol));
        let reference = reference_at(reference_bits(config))?;
        let mut row = measure_against(&reference, config, args.repeats)
            .map_err(|e| anyhow!("{label} at tolerance {:e}: {e}", config.tolerances.rtol))?;
        if !specs.is_empty() {
            let mut once = *config;
            let (times, states) = run_once(&reference, &mut once).map_err(|e| anyhow!("{e}"))?;
            let ev = events_of_run(&case, &specs, None, &times, &states).map_err(case_error)?;
            row.events = Some(ev.counts());
        }
        rows.push(Labelled {
            row,
            label,
            external: false,
        });
        tick(&bar);
    }
    for exec in &mut externals {
        exec.events = specs
            .iter()
            .map(|s| {
                (
                    s.name.as_str().to_string(),
                    s.direction.as_str().to_string(),
                )
            })
            .collect();
        let tol = exec.tolerances.rtol;
        bar.set_message(format!("{} at {tol:e}", exec.name()));
        let reference = reference_at(reference_bits_for(exec.working_bits()))?;
        let mut row = measure_integrator(&reference, exec, args.repeats)
            .map_err(|e| anyhow!("--exec at tolerance {tol:e}: {e}"))?;
        if !specs.is_empty() {
            let answered = exec.answered_events.clone();
            let (times, states) = match answered {
                Some(_) => (Vec::new(), Vec::new()),
                None => run_once(&reference, exec).map_err(|e| anyhow!("{e}"))?,
            };
            let t_end = [case.t_end];
            let times = if times.is_empty() {
                t_end.to_vec()
            } else {
                times
            };
            let ev = events_of_run(&case, &specs, answered.as_deref(), &times, &states)
                .map_err(case_error)?;
            row.events = Some(ev.counts());
        }
        rows.push(Labelled {
            label: row.method.clone(),
            row,
            external: true,
        });
        tick(&bar);
    }
    bar.finish_and_clear();

    for l in &rows {
        let r = &l.row;
        if !(r.max_error.is_finite() && r.integration_seconds.is_finite()) {
            bail!(
                "{} at tolerance {}: the maximum error is not finite (the integrated motion left f64's range)",
                l.label,
                rsts_dynamics::short(r.tolerance)
            );
        }
    }
    let plain: Vec<BenchRow> = rows.iter().map(|l| l.row.clone()).collect();
    let fits = fit_tolerances(&plain);
    let environment = Environment::detect();
    if let Some(path) = &args.svg {
        let svg = plots::render(&case, args.repeats, &rows, args.cost)?;
        rsts_io::write_atomic(path, svg.as_bytes())
            .with_context(|| format!("--svg {}", path.display()))?;
        eprintln!("work-precision diagram: {}", path.display());
    }
    if let Some(path) = &args.svg_tolerance {
        let svg = plots::render_tolerance(&case, &rows, &fits)?;
        rsts_io::write_atomic(path, svg.as_bytes())
            .with_context(|| format!("--svg-tolerance {}", path.display()))?;
        eprintln!("tolerance-proportionality diagram: {}", path.display());
    }
    match args.format {
        Format::Json => output::write_json(
            out,
            &Document {
                case: &case,
                repeats: args.repeats,
                taylor_mp_digits: uses_mp.then_some(mp_digits),
                rows: &plain,
                fits: &fits,
                environment: &environment,
            },
        )?,
        Format::Csv => output::write_records_csv(out, &plain)?,
        Format::Table => {
            writeln!(
                out,
                "a = {}, b = {}, m = {}, h = {}, torus {}, T = {}, {} samples; time: median of {} runs",
                case.a, case.b, case.m, case.h, case.torus, case.t_end, case.samples, args.repeats
            )?;
            writeln!(out, "{}", environment.describe())?;
            output::write_table(out, &table(&rows))?;
            for f in &fits {
                let label = rows
                    .iter()
                    .find(|l| l.row.method == f.method)
                    .map_or(f.method.as_str(), |l| l.label.as_str());
                writeln!(out, "fit {label}: {}", f.describe())?;
            }
        }
    }
    if let Some(limit) = args.max_event_error {
        for l in &rows {
            if let Some(why) = l.row.events.and_then(|ev| ev.failure(limit)) {
                out.flush()?;
                return Err(crate::commands::validate::Failed(format!(
                    "{} at tolerance {:e}: {why}",
                    l.label, l.row.tolerance
                ))
                .into());
            }
        }
    }
    Ok(())
}

/// False when a built-in method would have to locate s1 or s2.
fn methods_only_state_events(args: &Args, specs: &[rsts_closed_form::events::EventSpec]) -> bool {
    let builtins = args.methods.as_ref().is_some_and(|m| !m.is_empty()) || args.exec.is_empty();
    !builtins || specs.iter().all(|s| s.name.index() < 12)
}

/// The optimistic step estimate of one run of `config` on `case` (its initial state from the
/// closed form in f64).
fn estimate_steps(case: &Case, config: &MethodConfig) -> anyhow::Result<f64> {
    use rsts_dynamics::integrators::{OutputGrid, Problem};
    let motion = rsts_closed_form::ExplicitMotion::<f64>::new(
        case.a,
        case.b,
        case.m,
        case.h,
        rsts_closed_form::TorusChoice {
            torus: case.torus,
            phase1: case.phase1,
            phase2: case.phase2,
        },
    )
    .map_err(case_error)?;
    let s = motion.at(&0.0);
    let problem = Problem {
        fields: rsts_dynamics::Fields::new(case.a, case.b)?,
        initial: rsts_dynamics::State {
            omega: [s.omega[0], s.omega[1], s.omega[2]],
            alpha: [s.alpha[0], s.alpha[1], s.alpha[2]],
            beta: [s.beta[0], s.beta[1], s.beta[2]],
        },
    };
    let grid = OutputGrid::new(case.t_end, case.samples)?;
    Ok(config.estimate_steps(&problem, &grid))
}

/// taylor-mp carries its digits in tables and legends.
fn label_of(method: MethodName, mp_digits: u32) -> String {
    match method {
        MethodName::TaylorMp => format!("taylor-mp-{mp_digits}d"),
        m => m.as_str().to_string(),
    }
}

/// The rows as a table, rounded for reading (CSV and JSON carry the full precision).
fn table(rows: &[Labelled]) -> Tabular {
    let with_events = rows.iter().any(|l| l.row.events.is_some());
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
    let mut t = Tabular::new(header);
    for l in rows {
        let r = &l.row;
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
            Cell::Int(r.steps),
            Cell::Int(r.rhs_evals),
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
        t.push(row);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_digits_cover_the_smallest_tolerance() {
        assert_eq!(default_mp_digits(1e-70), 80);
        assert_eq!(default_mp_digits(1e-8), 18);
        assert_eq!(default_mp_digits(0.5), 11);
    }
}
