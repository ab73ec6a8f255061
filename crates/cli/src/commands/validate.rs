//! `rsts validate`: run a validation suite (or one shard of it) in parallel, write report.json,
//! report.md and SVG plots, compare with a baseline; `rsts validate merge` joins shard reports.
//!
//! Exit codes: 0 all runs pass (and no regression), 1 some run missed its thresholds, could not be
//! done, or regressed against the baseline (each named on stderr), 2 bad input.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::bail;
use clap::{Args as ClapArgs, Subcommand};

use rsts_validate::suite::AdapterSpec;
use rsts_validate::{merge_dirs, validate, Options, Report, RunResult, Shard, Status, Suite};

use crate::external::TimeoutArgs;
use crate::failure::Failed;

/// Shown at the end of `rsts validate --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the CI suite (241 runs, seconds) on all cores: report in out/quick
  rsts validate --suite validation/quick.toml --report out/quick

  # again, with that report as the baseline: exit 1 names every run that regressed (on a busy
  # machine a run may take 2x longer than in the baseline: a time regression)
  # exit: 0, 1
  rsts validate --suite validation/quick.toml --report out/quick-again --baseline out/quick/report.json

  # the suite in two shards (one per machine of a job array), then their merge
  rsts validate --suite validation/quick.toml --report out/shard-1 --shard 1/2 --jobs 2
  rsts validate --suite validation/quick.toml --report out/shard-2 --shard 2/2 --jobs 2
  rsts validate merge out/shard-1 out/shard-2 --report out/quick-merged

  # the nightly sweep (602 runs; scripts/nightly.sh compares it with the last passing night)
  # takes: 1 min with 2 cores
  rsts validate --suite validation/nightly.toml --report out/nightly --jobs 2

  # your own integrator through the CI suite (docs/own-integrator.md)
  cargo build --release -p example-adapter-rk4
  rsts validate --suite validation/quick.toml --report out/mine --exec target/release/example-adapter-rk4 --exec-name my-rk4

Exit code 1 names every run that missed a threshold or regressed (error grown 10x, time grown 2x);
exit code 2 is bad input (suite, shard, missing baseline). See docs/validation.md.";

/// Options of `rsts validate`.
#[derive(Debug, Clone, ClapArgs)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Args {
    #[command(subcommand)]
    pub merge: Option<MergeCommand>,
    /// The suite file (TOML)
    #[arg(long, value_name = "FILE")]
    pub suite: Option<PathBuf>,
    /// Directory for report.json, report.md and plots/ (written whole when the suite is done;
    /// a new, empty or previous report directory)
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// A previous report.json (or its directory) to check for regressions
    #[arg(long, value_name = "OLD/report.json")]
    pub baseline: Option<PathBuf>,
    /// Run only shard K of N (1 <= K <= N): the runs whose index in the id-sorted list is K-1 mod N
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Threads (default: one per core; at most 8 per core)
    #[arg(long, value_name = "J")]
    pub jobs: Option<usize>,
    /// Only list the run ids (of the shard, if given) and exit
    #[arg(long)]
    pub list: bool,
    /// Run this external integrator (rsts-integrator/1) instead of every case's methods
    #[arg(long, value_name = "COMMAND")]
    pub exec: Option<String>,
    /// Name of the --exec integrator in run ids and reports
    #[arg(long, value_name = "NAME", default_value = "exec", requires = "exec")]
    pub exec_name: String,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// Record the run as a night in this validation history (SQLite; created when missing)
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
}

#[derive(Debug, Clone, Subcommand)]
pub enum MergeCommand {
    /// Join the reports of the shards of one suite into the report of the whole suite
    Merge(MergeArgs),
}

/// Options of `rsts validate merge`.
#[derive(Debug, Clone, ClapArgs)]
pub struct MergeArgs {
    /// Report directories (or report.json files) of the shards
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// Directory for the merged report.json, report.md and plots/
    #[arg(long, value_name = "DIR")]
    pub report: PathBuf,
    /// A previous report.json (or its directory) to check for regressions
    #[arg(long, value_name = "OLD/report.json")]
    pub baseline: Option<PathBuf>,
    /// Record the merged report as one night in this validation history
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
}

fn finish(report: &Report, dir: &std::path::Path, out: &mut dyn Write) -> anyhow::Result<()> {
    let s = &report.summary;
    writeln!(
        out,
        "{}: {} runs{}: {} passed, {} failed, {} errors{}; {:.1} s",
        report.suite,
        s.runs,
        report
            .shard
            .map(|sh| format!(" (shard {sh} of {} runs)", report.total_runs))
            .unwrap_or_default(),
        s.passed,
        s.failed,
        s.errors,
        report
            .baseline
            .as_ref()
            .map(|b| format!(
                "; {} regressions against the baseline ({} runs compared)",
                b.regressions.len(),
                b.runs_compared
            ))
            .unwrap_or_default(),
        report.timing.wall_seconds
    )?;
    writeln!(
        out,
        "report: {}, {} and {}",
        dir.join("report.json").display(),
        dir.join("report.md").display(),
        dir.join("plots").display()
    )?;
    let problems = report.problems();
    if problems.is_empty() {
        return Ok(());
    }
    out.flush()?;
    Err(Failed(format!(
        "{} problem(s):\n  {}",
        problems.len(),
        problems.join("\n  ")
    ))
    .into())
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if let Some(MergeCommand::Merge(m)) = args.merge {
        if let Some(b) = &m.baseline {
            Report::read(b).map_err(|e| anyhow::anyhow!("--baseline: {e}"))?;
        }
        check_history(m.history.as_deref())?;
        let report = merge_dirs(&m.dirs, &m.report, m.baseline.as_deref())?;
        record_history(m.history.as_deref(), &report, &m.report)?;
        return finish(&report, &m.report, out);
    }
    let Some(suite) = args.suite else {
        bail!("--suite FILE is required (or `rsts validate merge DIR... --report DIR`)");
    };
    let shard: Option<Shard> = args
        .shard
        .as_deref()
        .map(str::parse)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--shard: {e}"))?;
    let exec = match &args.exec {
        None => None,
        Some(command) => {
            let argv = rsts_external::split_command(command)
                .map_err(|e| anyhow::anyhow!("--exec: {e}"))?;
            rsts_external::check_program(&argv[0]).map_err(|e| anyhow::anyhow!("--exec: {e}"))?;
            rsts_external::check_timeout(args.timeout.exec_timeout)
                .map_err(|e| anyhow::anyhow!("--exec-timeout: {e}"))?;
            Some((
                args.exec_name.clone(),
                AdapterSpec {
                    command: argv,
                    timeout: Some(args.timeout.exec_timeout),
                },
            ))
        }
    };
    // Inputs named by their options before anything runs (the library reads them again).
    let loaded = Suite::load_with(&suite, exec.as_ref().map(|(n, a)| (n.as_str(), a)))
        .map_err(|e| anyhow::anyhow!("--suite: {}", e.detail()))?;
    if let Some(b) = &args.baseline {
        Report::read(b).map_err(|e| anyhow::anyhow!("--baseline: {e}"))?;
    }
    if args.list {
        let s = loaded;
        let runs = match shard {
            Some(sh) => sh.select(&s.runs),
            None => s.runs,
        };
        for r in runs {
            writeln!(out, "{}\t{}", r.id, r.camera)?;
        }
        return Ok(());
    }
    let Some(report_dir) = args.report else {
        bail!("--report DIR is required");
    };
    if let Some(j) = args.jobs {
        rsts_harness::threads::check_jobs(j).map_err(|e| anyhow::anyhow!("--jobs: {e}"))?;
    }
    check_history(args.history.as_deref())?;
    let opts = Options {
        suite,
        report_dir: report_dir.clone(),
        baseline: args.baseline,
        shard,
        jobs: args.jobs.unwrap_or(0),
        exec,
    };
    let done = AtomicUsize::new(0);
    let tty = std::io::stderr().is_terminal();
    let progress = |r: &RunResult| {
        let k = done.fetch_add(1, Ordering::Relaxed) + 1;
        if tty || r.status != Status::Pass {
            let mark = match r.status {
                Status::Pass => "ok",
                Status::Fail => "FAIL",
                Status::Error => "ERROR",
            };
            eprintln!("[{k}] {mark} {} ({:.2} s)", r.id, r.timing.wall_seconds);
        }
    };
    let report = validate(&opts, &progress)?;
    record_history(args.history.as_deref(), &report, &report_dir)?;
    finish(&report, &report_dir, out)
}

/// `--history FILE`: refuse a database that cannot take the night before anything runs.
fn check_history(history: Option<&std::path::Path>) -> anyhow::Result<()> {
    if let Some(h) = history {
        rsts_history::History::check_for_writing(h)
            .map_err(|e| anyhow::anyhow!("--history: {e}"))?;
    }
    Ok(())
}

/// `--history FILE`: record the report just written as a night.
fn record_history(
    history: Option<&std::path::Path>,
    report: &Report,
    dir: &std::path::Path,
) -> anyhow::Result<()> {
    if let Some(h) = history {
        let id = rsts_history::record(h, report, dir).map_err(|e| {
            anyhow::anyhow!(
                "--history: {e} (the report in {} was written)",
                dir.display()
            )
        })?;
        eprintln!("history: night {id} recorded in {}", h.display());
    }
    Ok(())
}
