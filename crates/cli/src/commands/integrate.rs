//! `rsts integrate`: integrate the Euler–Poisson equations from one state with one method and
//! print the state and the first integrals H, K, G at N times evenly spaced on [0, T].

use std::io::Write;

use anyhow::Context;
use clap::Args as ClapArgs;
use serde::Serialize;

use rsts_dynamics::integrals;
use rsts_dynamics::integrators::{MethodName, Stats};

use crate::args::{GridArgs, MethodArgs, ProblemArgs};
use crate::output::{self, Cell, Format};

/// Shown at the end of `rsts integrate --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the built-in default case (a=1, b=0.5, omega=0.3,-0.2,0.5, alpha=1,0,0, beta=0,1,0, T=10, 11 samples, dop853)
  rsts integrate

  # everything explicit, CSV output
  rsts integrate --a 1 --b 0.5 --omega -0.3,0.2,0.5 --alpha 1,0,0 --beta 0,1,0 \\
      --t-end 100 --samples 101 --method dop853 --rtol 1e-12 --atol 1e-12 --format csv

  # fixed-step RK4 with step 1e-3, JSON output
  rsts integrate --method rk4 --step 1e-3 --format json";

/// Options of `rsts integrate`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub problem: ProblemArgs,
    #[command(flatten)]
    pub grid: GridArgs,
    #[command(flatten)]
    pub method: MethodArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

/// One output time.
#[derive(Debug, Serialize)]
struct Sample {
    t: f64,
    omega: [f64; 3],
    alpha: [f64; 3],
    beta: [f64; 3],
    #[serde(rename = "H")]
    h: f64,
    #[serde(rename = "K")]
    k: f64,
    #[serde(rename = "G")]
    g: f64,
    /// Largest of | |α|²−1 |, | |β|²−1 |, |α·β| (table summary only).
    #[serde(skip)]
    constraint_error: f64,
}

/// The JSON document.
#[derive(Debug, Serialize)]
struct Report {
    a: f64,
    b: f64,
    method: &'static str,
    t_end: f64,
    rtol: f64,
    atol: f64,
    samples: Vec<Sample>,
    stats: Stats,
}

const COLUMNS: [&str; 13] = [
    "t", "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
    "H", "K", "G",
];

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let problem = args.problem.problem()?;
    let grid = args.grid.grid()?;
    let config = args.method.config()?;
    if config.step.is_some() && config.method != MethodName::Rk4 {
        eprintln!(
            "warning: --step is only used by rk4; {} chooses its own steps",
            config.method
        );
    }
    let options = if config.method == MethodName::Rk4 {
        "--t-end/--step/--rtol"
    } else {
        "--t-end/--rtol/--atol"
    };
    config
        .check_budget(&problem, &grid)
        .with_context(|| options.to_string())?;
    let mut solution = config.propagate_f64(&problem, &grid)?;
    // With T = 0 the integrators return the initial state once; the grid still has N times.
    if grid.t_end == 0.0 && solution.states.len() == 1 {
        solution.times = grid.times();
        solution.states = vec![problem.initial.clone(); grid.samples];
    }
    anyhow::ensure!(
        solution.states.len() == grid.samples,
        "{} returned {} samples instead of {}",
        solution.method,
        solution.states.len(),
        grid.samples
    );
    let stats = solution.stats;
    let method = solution.method;
    // The states are consumed into the samples: memory holds one copy of the run.
    let samples: Vec<Sample> = solution
        .times
        .into_iter()
        .zip(solution.states)
        .map(|(t, s)| {
            let i = integrals(&problem.fields, &s);
            Sample {
                t,
                omega: s.omega,
                alpha: s.alpha,
                beta: s.beta,
                h: i.h,
                k: i.k,
                g: i.g,
                constraint_error: s.constraint_error(),
            }
        })
        .collect();
    if let Some(s) = samples
        .iter()
        .find(|s| ![s.h, s.k, s.g].iter().all(|x| x.is_finite()))
    {
        anyhow::bail!(
            "the first integrals are not finite at t = {} (the state left f64's range)",
            rsts_dynamics::short(s.t)
        );
    }
    let report = Report {
        a: problem.fields.a,
        b: problem.fields.b,
        method,
        t_end: grid.t_end,
        rtol: config.tolerances.rtol,
        atol: config.tolerances.atol,
        samples,
        stats,
    };
    match args.format {
        Format::Json => output::write_json(out, &report)?,
        Format::Csv => output::write_csv_rows(out, &columns(), rows(&report))?,
        Format::Table => write_human(out, &report, config.step)?,
    }
    Ok(())
}

/// The CSV/table rows of the samples, made on demand.
fn rows(report: &Report) -> impl Iterator<Item = Vec<Cell>> + '_ {
    report.samples.iter().map(|s| {
        let mut row = vec![Cell::Num(s.t)];
        row.extend(
            s.omega
                .iter()
                .chain(&s.alpha)
                .chain(&s.beta)
                .chain([&s.h, &s.k, &s.g])
                .map(|&x| Cell::Num(x)),
        );
        row
    })
}

fn columns() -> Vec<String> {
    COLUMNS.iter().map(|c| c.to_string()).collect()
}

/// Largest |f(sample) − f(first sample)|.
fn max_drift(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> f64 {
    let Some(first) = samples.first() else {
        return 0.0;
    };
    let f0 = f(first);
    samples
        .iter()
        .map(|s| (f(s) - f0).abs())
        .fold(0.0, f64::max)
}

fn write_human(out: &mut dyn Write, report: &Report, step: Option<f64>) -> std::io::Result<()> {
    let s = &report.samples;
    let method = match (report.method, step) {
        ("rk4", Some(h)) => format!("rk4, fixed step {h:e}"),
        ("rk4", None) => "rk4, step from rtol".to_string(),
        (m, _) => format!("{m}, rtol {:e}, atol {:e}", report.rtol, report.atol),
    };
    output::write_key_values(
        out,
        &[
            ("fields", format!("a = {}, b = {}", report.a, report.b)),
            ("method", method),
            (
                "grid",
                format!("{} samples on [0, {}]", s.len(), report.t_end),
            ),
        ],
    )?;
    writeln!(out)?;
    output::write_table_rows(out, &columns(), || rows(report))?;
    writeln!(out)?;
    let st = &report.stats;
    let max_constraint = s.iter().map(|x| x.constraint_error).fold(0.0, f64::max);
    output::write_key_values(
        out,
        &[
            (
                "steps",
                format!(
                    "{} accepted, {} rejected, {} rhs evaluations, {:.6} s",
                    st.accepted_steps, st.rejected_steps, st.rhs_evals, st.integration_seconds
                ),
            ),
            (
                "max drift",
                format!(
                    "H {:.3e}, K {:.3e}, G {:.3e}",
                    max_drift(s, |x| x.h),
                    max_drift(s, |x| x.k),
                    max_drift(s, |x| x.g)
                ),
            ),
            ("max constraint error", format!("{max_constraint:.3e}")),
        ],
    )
}
