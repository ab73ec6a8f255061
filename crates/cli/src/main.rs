//! `rsts`: command-line front end of the Kowalevski-top integrator cross-checker.
//!
//! Parsing and dispatch only. Each subcommand lives in its own file under `commands/` and
//! exposes `Args` (clap), `EXAMPLES` (shown by `--help`) and `run(args, out)`; adding one is a new
//! file, a `pub mod` line in `commands/mod.rs`, a variant of [`Command`] and an arm of
//! [`Command::run`]. Any error is printed as `error: ...` on stderr with exit code 2.

mod args;
mod commands;
mod external;
mod interrupt;
mod invocation;
mod jobs;
mod output;

use std::io::{self, Write};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use commands::{
    bench, check, compare, convergence, dashboard, diagram, events, explicit, history, identify,
    inspect, integrate, reference, surfaces, table1, table2, validate,
};

/// Exit code for bad input and any other error (the same code clap uses for usage errors).
const EXIT_ERROR: u8 = 2;
/// Exit code of `rsts validate` when a run missed its thresholds or regressed, and of
/// `rsts identify` for a state not on N.
const EXIT_FAILED: u8 = 1;
/// Exit code of `rsts inspect` when only part of a damaged file could be read.
const EXIT_RECOVERED: u8 = 3;

const TOP_EXAMPLES: &str = "\
Examples:
  rsts integrate
  rsts integrate --a 1 --b 0.5 --omega -0.3,0.2,0.5 --alpha 1,0,0 --beta 0,1,0 --t-end 100 --samples 101 --format csv
  rsts compare --mcap out/compare.mcap
  rsts inspect out/compare.mcap --channel /errors --format csv
  rsts explicit --m -0.7092 --h 1.5643 --torus 3 --t-end 20 --samples 5 --digits 60 --format json

Run `rsts <COMMAND> --help` for the options and more examples of each command.";

/// Cross-checker of ODE integrators for the Kowalevski top in two constant force fields
/// (Reyman–Semenov-Tian-Shansky problem, inertia diag(2, 2, 1)).
#[derive(Debug, Parser)]
#[command(name = "rsts", version, after_help = TOP_EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per run: the size of the largest command's options costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
enum Command {
    /// Integrate the Euler–Poisson equations from one state and print the samples with H, K, G.
    #[command(after_help = integrate::EXAMPLES)]
    Integrate(integrate::Args),
    /// Evaluate the closed-form motion on the invariant manifold N (f64 or any number of digits).
    #[command(after_help = explicit::EXAMPLES)]
    Explicit(explicit::Args),
    /// Which motion of N a state is on: m, h, camera, torus, phases, distance from N.
    #[command(after_help = identify::EXAMPLES)]
    Identify(identify::Args),
    /// Draw the (m, h) plane (admissible region, Σ, cameras) or describe one point of it.
    #[command(after_help = diagram::EXAMPLES)]
    Diagram(diagram::Args),
    /// Compare an integrator with the closed form along a motion; optionally log it to MCAP.
    #[command(after_help = compare::EXAMPLES)]
    Compare(compare::Args),
    /// Check a trajectory computed elsewhere (CSV, JSON, npy, MCAP) against the closed form on N.
    #[command(after_help = check::EXAMPLES)]
    Check(check::Args),
    /// Exact event times along the motion on N: zeros of state components, of gamma, turning points of s1, s2.
    #[command(after_help = events::EXAMPLES)]
    Events(events::Args),
    /// The exact motion on N at any times (H, K, G per row): CSV, JSON or npy.
    #[command(after_help = reference::EXAMPLES)]
    Reference(reference::Args),
    /// Summarise an MCAP log of `rsts compare`, or extract one of its series.
    #[command(after_help = inspect::EXAMPLES)]
    Inspect(inspect::Args),
    /// Work-precision benchmark against the closed form: error, time, steps per method and tolerance.
    #[command(after_help = bench::EXAMPLES)]
    Bench(bench::Args),
    /// Observed order of integrators at fixed steps: error against step, least-squares order over the asymptotic window.
    #[command(after_help = convergence::EXAMPLES)]
    Convergence(convergence::Args),
    /// Run a validation suite (every camera, the hard cases) in parallel: report, plots, baseline, shards.
    #[command(after_help = validate::EXAMPLES)]
    Validate(validate::Args),
    /// A validation history: load reports into it, list the series that regressed.
    #[command(after_help = history::EXAMPLES)]
    History(history::Args),
    /// Write the static dashboard of a validation history: overview, trends, nights.
    #[command(after_help = dashboard::EXAMPLES)]
    Dashboard(dashboard::Args),
    /// Bearing surfaces of one integral manifold: PLY meshes, shaded PNG pictures, MCAP scene.
    #[command(after_help = surfaces::EXAMPLES)]
    Surfaces(surfaces::Args),
    /// The seed's Table 1 recomputed: roots of Phi and oscillation segments per camera.
    #[command(after_help = table1::EXAMPLES)]
    Table1(table1::Args),
    /// Partial pendulum motions and symmetry planes of the bearing surfaces per camera (Table 2).
    #[command(after_help = table2::EXAMPLES)]
    Table2(table2::Args),
}

impl Command {
    fn run(self, out: &mut dyn Write) -> anyhow::Result<()> {
        match self {
            Command::Integrate(args) => integrate::run(args, out),
            Command::Explicit(args) => explicit::run(args, out),
            Command::Identify(args) => identify::run(args, out),
            Command::Diagram(args) => diagram::run(args, out),
            Command::Compare(args) => compare::run(args, out),
            Command::Check(args) => check::run(args, out),
            Command::Events(args) => events::run(args, out),
            Command::Reference(args) => reference::run(args, out),
            Command::Inspect(args) => inspect::run(args, out),
            Command::Bench(args) => bench::run(args, out),
            Command::Convergence(args) => convergence::run(args, out),
            Command::Validate(args) => validate::run(args, out),
            Command::History(args) => history::run(args, out),
            Command::Dashboard(args) => dashboard::run(args, out),
            Command::Surfaces(args) => surfaces::run(args, out),
            Command::Table1(args) => table1::run(args, out),
            Command::Table2(args) => table2::run(args, out),
        }
    }
}

/// True when the error is a closed stdout (e.g. `rsts integrate | head`): not worth a message.
fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|cause| {
        cause
            .downcast_ref::<io::Error>()
            .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// Standard output whose errors say so ("writing stdout: No space left on device").
struct Stdout<W: Write>(W);

impl<W: Write> Stdout<W> {
    fn name(e: io::Error) -> io::Error {
        if e.kind() == io::ErrorKind::BrokenPipe {
            e
        } else {
            io::Error::new(e.kind(), format!("writing stdout: {e}"))
        }
    }
}

impl<W: Write> Write for Stdout<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf).map_err(Self::name)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.flush().map_err(Self::name)
    }
}

fn main() -> ExitCode {
    interrupt::install();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // Usage errors print `error: ...` and exit 2; --help and --version exit 0.
        Err(e) => e.exit(),
    };
    let stdout = io::stdout();
    let mut out = Stdout(io::BufWriter::new(stdout.lock()));
    let result = cli
        .command
        .run(&mut out)
        .and_then(|()| out.flush().map_err(anyhow::Error::from));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            // Best effort: if stderr itself is gone there is nobody to tell.
            let _ = writeln!(io::stderr(), "error: {e:#}");
            if e.downcast_ref::<inspect::Recovered>().is_some() {
                ExitCode::from(EXIT_RECOVERED)
            } else if e.downcast_ref::<compare::Interrupted>().is_some() {
                ExitCode::from(interrupt::exit_code())
            } else if e.downcast_ref::<validate::Failed>().is_some()
                || e.downcast_ref::<identify::NotOnN>().is_some()
                || e.downcast_ref::<history::Regressed>().is_some()
            {
                ExitCode::from(EXIT_FAILED)
            } else {
                ExitCode::from(EXIT_ERROR)
            }
        }
    }
}
