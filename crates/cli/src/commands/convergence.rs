//! `rsts convergence`: the observed order of integrators at fixed steps along one motion
//! (issue 18). The runs and the fit are `rsts_harness::convergence`; this parses, calls and
//! formats (table, JSON, CSV, SVG).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{anyhow, bail, Context};
use clap::Args as ClapArgs;

use rsts_dynamics::integrators::{MethodName, Tolerances, MAX_MP_DIGITS};
use rsts_harness::convergence::{halvings, FixedStepIntegrator, FixedStepMethod};
use rsts_harness::{convergence, ConvergencePlan, ConvergenceReport};

use crate::args::{case_error, count, finite_f64, CaseArgs, MethodParser};
use crate::external::{exec_integrator, TimeoutArgs};
use crate::output::{self, Cell, Format, Tabular};

/// Shown at the end of `rsts convergence --help`.
pub const EXAMPLES: &str = "\
Examples:
  # rk4 and dopri5 at steps 0.5, 0.25, ..., 0.5/2^6 over T = 10 (camera I+), orders fitted
  rsts convergence --methods rk4,dopri5 --step 0.5 --halvings 6

  # no steps: the default sweep, min(0.5, T/(N-1)) and 8 halvings
  rsts convergence --methods rk4,dopri5

  # Taylor at a fixed order 6, given steps, JSON and a log-log diagram
  rsts convergence --methods taylor-f64 --order 6 --steps 0.5,0.25,0.125,0.0625,0.03125 \\
      --format json --svg out/convergence.svg

  # an adapter that honours \"step\" in its request (docs/own-integrator.md)
  cargo build --release -p example-adapter-rk4
  rsts convergence --exec \"target/release/example-adapter-rk4 --tableau heun\" --step 0.5 --halvings 8

A step h is used as the sample spacing T/(N-1) over a whole number of steps; the rows give the
step used. The order is the least-squares slope of log(max error) against log(step) over the
asymptotic window, found automatically; a second run of agreeing slopes is a regime of its own.
The floor below is judged against the round-off the method's precision allows after that many
steps (u*|x|*n): \"round-off\" or \"above round-off\" (a solver tolerance, a wrong coefficient);
--strict exits 1 on a floor above round-off or on competing windows. Every excluded step is
listed with why (pre-asymptotic, noise, floor). See docs/convergence.md.";

/// Options of `rsts convergence`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T > 0
    #[arg(long, value_name = "T", default_value = "10", value_parser = crate::args::decimal, allow_hyphen_values = true)]
    pub t_end: rsts_closed_form::Decimal,
    /// Number N >= 2 of samples evenly spaced on [0, T] where the error is measured
    #[arg(long, value_name = "N", default_value = "11", value_parser = count)]
    pub samples: usize,
    /// Built-in methods at fixed steps, comma-separated: rk4, dopri5, dop853 (step control
    /// off), taylor-f64, taylor-dd, taylor-mp (at --order); default rk4 when no --exec
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = MethodParser)]
    pub methods: Option<Vec<MethodName>>,
    /// Order P of the Taylor methods (1 to 400)
    #[arg(long, value_name = "P")]
    pub order: Option<usize>,
    /// Decimal digits of taylor-mp and of the requests to --exec integrators (10 to 10000)
    #[arg(long, value_name = "D", default_value_t = 40)]
    pub digits: u32,
    /// An external integrator speaking rsts-integrator/1 that honours "step" in its request;
    /// may be repeated
    #[arg(long, value_name = "COMMAND")]
    pub exec: Vec<String>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// rtol = atol sent to --exec integrators with the step (heyoka takes its order from it)
    #[arg(long, value_name = "R", default_value = "1e-10", value_parser = finite_f64, allow_hyphen_values = true)]
    pub exec_tolerance: f64,
    /// Steps, comma-separated (at least 3); without --steps and --step, the default sweep:
    /// min(0.5, T/(N-1)) and 8 halvings
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = finite_f64, conflicts_with_all = ["step", "halvings"])]
    pub steps: Option<Vec<f64>>,
    /// Largest step H of a sweep H, H/2, ..., H/2^K (with --halvings)
    #[arg(long, value_name = "H", value_parser = finite_f64, allow_hyphen_values = true, requires = "halvings")]
    pub step: Option<f64>,
    /// Number K of halvings of --step (2 to 40)
    #[arg(long, value_name = "K", requires = "step")]
    pub halvings: Option<u32>,
    /// Write the diagram (max error against step, log-log, fitted lines) to this SVG file
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Exit 1 when a fit has an error floor above round-off or competing windows (the report
    /// is written first)
    #[arg(long)]
    pub strict: bool,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let steps = match (&args.steps, args.step, args.halvings) {
        (Some(s), _, _) => s.clone(),
        (None, Some(h), Some(k)) => {
            if !(2..=40).contains(&k) {
                bail!("--halvings: need 2 to 40 halvings, got {k}");
            }
            halvings(h, k)
        }
        _ => {
            let steps = ConvergencePlan::default_steps(&args.case.case(&args.t_end, args.samples));
            eprintln!(
                "steps: none given, the default sweep {} to {} ({} halvings; --steps or --step \
                 with --halvings to choose)",
                steps[0],
                rsts_dynamics::short(steps[steps.len() - 1]),
                steps.len() - 1
            );
            steps
        }
    };
    if !(10..=MAX_MP_DIGITS).contains(&args.digits) {
        bail!(
            "--digits: must be between 10 and {MAX_MP_DIGITS}, got {}",
            args.digits
        );
    }
    let case = args.case.case(&args.t_end, args.samples);
    let plan = ConvergencePlan::new(case, &steps).map_err(case_error)?;
    let given = match &args.methods {
        Some(m) => m.clone(),
        None if args.exec.is_empty() => vec![MethodName::Rk4],
        None => Vec::new(),
    };
    let mut builtins = Vec::new();
    for m in given {
        builtins.push(FixedStepMethod::new(m, args.order, args.digits).map_err(case_error)?);
    }
    if args.order.is_some() && !builtins.iter().any(|b| b.order.is_some()) {
        bail!("--order: only the Taylor methods take a fixed order");
    }
    let tolerance =
        Tolerances::new(args.exec_tolerance, args.exec_tolerance).context("--exec-tolerance")?;
    let mut externals = Vec::new();
    for command in &args.exec {
        externals.push(exec_integrator(
            command,
            tolerance,
            Some(args.digits),
            args.timeout.exec_timeout,
        )?);
    }
    if let Some(path) = &args.svg {
        let files: Vec<_> = args
            .exec
            .iter()
            .flat_map(|c| rsts_external::command_files(c))
            .collect();
        let inputs: Vec<_> = files.iter().map(|f| ("--exec", f.as_path())).collect();
        rsts_io::check_outputs(&inputs, &[rsts_io::Output::File("--svg", path)])?;
        rsts_io::check_writable(path).with_context(|| format!("--svg {}", path.display()))?;
    }
    let mut methods: Vec<&mut dyn FixedStepIntegrator> = Vec::new();
    for b in &mut builtins {
        methods.push(b);
    }
    for e in &mut externals {
        methods.push(e);
    }
    let report = convergence(&plan, &mut methods).map_err(case_error)?;
    if let Some(path) = &args.svg {
        let svg = render(&report)?;
        rsts_io::write_atomic(path, svg.as_bytes())
            .with_context(|| format!("--svg {}", path.display()))?;
        eprintln!("convergence diagram: {}", path.display());
    }
    match args.format {
        Format::Json => output::write_json(out, &report)?,
        Format::Csv => output::write_records_csv(out, &report.rows)?,
        Format::Table => write_table(out, &report)?,
    }
    let doubts: Vec<String> = report.fits.iter().flat_map(|f| f.doubts()).collect();
    if args.strict && !doubts.is_empty() {
        out.flush()?;
        return Err(crate::failure::Failed(format!("--strict: {}", doubts.join("; "))).into());
    }
    Ok(())
}

/// The rows, then a line per fit with its window and excluded steps.
fn write_table(out: &mut dyn Write, report: &ConvergenceReport) -> anyhow::Result<()> {
    let c = &report.case;
    writeln!(
        out,
        "a = {}, b = {}, m = {}, h = {}, torus {}, T = {}, {} samples; fixed steps",
        c.motion.a, c.motion.b, c.motion.m, c.motion.h, c.motion.torus, c.t_end, c.samples
    )?;
    let mut t = Tabular::new([
        "method",
        "step",
        "max error",
        "final error",
        "steps",
        "rhs evals",
    ]);
    for r in &report.rows {
        t.push(vec![
            Cell::Text(r.method.clone()),
            Cell::Text(format!("{:.6e}", r.step)),
            Cell::Text(format!("{:.3e}", r.max_error)),
            Cell::Text(format!("{:.3e}", r.final_error)),
            Cell::Int(r.steps),
            Cell::Int(r.rhs_evals),
        ]);
    }
    output::write_table(out, &t)?;
    for f in &report.fits {
        writeln!(out, "{}: {}", f.method, f.describe())?;
        for e in &f.excluded {
            writeln!(out, "  excluded step {:.3e}: {}", e.step, e.why)?;
        }
    }
    Ok(())
}

/// The convergence diagram ([`rsts_harness::convergence::diagram`]) as SVG.
fn render(report: &ConvergenceReport) -> anyhow::Result<String> {
    let chart = rsts_harness::convergence::diagram::chart(report);
    rsts_plots::render_svg(&chart).map_err(|e| anyhow!("--svg: {e}"))
}
