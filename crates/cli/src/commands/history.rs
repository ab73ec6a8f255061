//! `rsts history`: load report.json files into a validation history (`import`) and list the
//! series that regressed (`regressions`). The database, the series and how regressions are found
//! are in rsts-history and docs/validation.md.
//!
//! Exit codes: 0 done (no regression), 1 some series regressed (`regressions`), 2 bad input (a
//! missing, locked, foreign or newer database, an unreadable report; nothing written).

use std::io::Write;
use std::path::PathBuf;

use clap::{Args as ClapArgs, Subcommand, ValueEnum};

/// Shown at the end of `rsts history --help`.
pub const EXAMPLES: &str = "\
Examples:
  # two nights of the quick suite, each recorded as it runs
  rsts validate --suite validation/quick.toml --report out/night-1 --history out/history.sqlite
  rsts validate --suite validation/quick.toml --report out/night-2 --history out/history.sqlite

  # reports written before: their `created` time is the night (--night for older reports)
  rsts history import out/night-1/report.json --history out/imported.sqlite

  # the regressed series (exit 1 when there is one), as text or JSON
  # exit: 0, 1
  rsts history regressions out/history.sqlite
  # exit: 0, 1
  rsts history regressions out/history.sqlite --format json

Exit code 0: nothing regressed; 1: some series regressed; 2: bad input. See docs/validation.md.";

#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    pub command: HistoryCommand,
}

#[derive(Debug, Clone, Subcommand)]
pub enum HistoryCommand {
    /// Load report.json files (or report directories) into a history, one night each
    Import(ImportArgs),
    /// List the series that regressed: one entry each (exit 1 when there is one)
    Regressions(RegressionsArgs),
}

#[derive(Debug, Clone, ClapArgs)]
pub struct ImportArgs {
    /// report.json files or report directories
    #[arg(value_name = "REPORT", required = true)]
    pub reports: Vec<PathBuf>,
    /// The history database (created when missing)
    #[arg(long, value_name = "FILE")]
    pub history: PathBuf,
    /// The night (UTC, YYYY-MM-DDTHH:MM:SSZ or YYYY-MM-DD) of reports that have no `created` time
    #[arg(long, value_name = "TIME")]
    pub night: Option<String>,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

#[derive(Debug, Clone, ClapArgs)]
pub struct RegressionsArgs {
    /// The history database
    #[arg(value_name = "FILE")]
    pub history: PathBuf,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// Some series regressed (exit code 1).
#[derive(Debug)]
pub struct Regressed(pub usize);

impl std::fmt::Display for Regressed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} series regressed", self.0)
    }
}
impl std::error::Error for Regressed {}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    match args.command {
        HistoryCommand::Import(a) => {
            let done = rsts_history::import(&a.history, &a.reports, a.night.as_deref())?;
            for (report, night, id) in &done.nights {
                writeln!(out, "{report}: night {night} (id {id})")?;
            }
            writeln!(
                out,
                "{} night(s) recorded in {}",
                done.nights.len(),
                a.history.display()
            )?;
            Ok(())
        }
        HistoryCommand::Regressions(a) => {
            let report = rsts_history::regressions(&a.history)?;
            match a.format {
                Format::Json => {
                    serde_json::to_writer_pretty(&mut *out, &report)?;
                    writeln!(out)?;
                }
                Format::Text => {
                    writeln!(
                        out,
                        "{}: {} nights, {} series, {} regressed",
                        report.history,
                        report.nights,
                        report.series,
                        report.regressions.len()
                    )?;
                    for r in &report.regressions {
                        let size = match (r.ulps, r.z) {
                            (Some(u), _) => format!("{u} ulps"),
                            (_, Some(z)) => {
                                format!("{:.2}x, {z:.1} standard errors", r.after / r.before)
                            }
                            _ => String::new(),
                        };
                        writeln!(
                            out,
                            "REGRESSION {} [{} {}] {} ({}): {:.6e} -> {:.6e} ({size}); last good {} ({}), first bad {} ({}); {}",
                            r.run_id,
                            r.method,
                            r.tolerance,
                            r.metric,
                            r.kind,
                            r.before,
                            r.after,
                            r.last_good_night,
                            r.last_good_commit,
                            r.first_bad_night,
                            r.first_bad_commit,
                            r.environment_text
                        )?;
                    }
                }
            }
            if report.regressions.is_empty() {
                Ok(())
            } else {
                out.flush()?;
                Err(Regressed(report.regressions.len()).into())
            }
        }
    }
}
