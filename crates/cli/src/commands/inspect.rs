//! `rsts inspect`: summary of an MCAP log written by `rsts compare`, or one series as CSV/JSON.
//! A truncated or damaged file is read as far as it goes: what could be recovered is printed and
//! the command says what was wrong and exits with status 3.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args as ClapArgs, ValueEnum};

use rsts_mcap::inspect;

/// Shown at the end of `rsts inspect --help`.
pub const EXAMPLES: &str = "\
Examples:
  # a log to look at (rsts compare --help)
  rsts compare --mcap out/compare.mcap

  # channels, schemas, message counts, time range, the case and the largest errors
  rsts inspect out/compare.mcap

  # the summary as one JSON document
  rsts inspect out/compare.mcap --format json

  # the error series as CSV (columns t, state_error, orientation_error, drift_h, ..., log_time)
  rsts inspect out/compare.mcap --channel /errors --format csv

Every CRC of the file is checked (chunks, data section, summary). Exit status: 0 for a healthy
file, 3 when the file is truncated or damaged and only part of it could be read (that part is
printed; a cut file says \"truncated at byte N\"), the same with or without --channel; 2 for any
other error.";

/// Output format: the summary is `table` or `json`; a `--channel` series is `csv` or `json`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InspectFormat {
    /// The summary as text (the default without --channel)
    Table,
    /// A --channel series as CSV (the default with --channel)
    Csv,
    /// The summary or the series as one JSON document
    Json,
}

/// Options of `rsts inspect`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The MCAP file
    pub file: PathBuf,
    /// Extract this channel (topic), e.g. /errors or /integrated/state
    #[arg(long, value_name = "NAME")]
    pub channel: Option<String>,
    /// Output format: table or json for the summary (default table), csv or json for a
    /// --channel series (default csv)
    #[arg(long, value_enum)]
    pub format: Option<InspectFormat>,
}

/// The file was only partly readable: the recovered part has been printed.
#[derive(Debug)]
pub struct Recovered(pub String);

impl std::fmt::Display for Recovered {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}
impl std::error::Error for Recovered {}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let (recovered, notes) = match &args.channel {
        None => {
            let format = match args.format {
                None | Some(InspectFormat::Table) => InspectFormat::Table,
                Some(InspectFormat::Json) => InspectFormat::Json,
                Some(InspectFormat::Csv) => anyhow::bail!(
                    "--format csv is for a series (--channel NAME); the summary is table or json"
                ),
            };
            let s = inspect::summarize(&args.file)
                .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
            if format == InspectFormat::Json {
                crate::output::write_json(out, &s)?;
            } else {
                write!(out, "{s}")?;
            }
            (s.recovered, s.notes.clone())
        }
        Some(topic) => {
            let format = match args.format {
                None | Some(InspectFormat::Csv) => InspectFormat::Csv,
                Some(InspectFormat::Json) => InspectFormat::Json,
                Some(InspectFormat::Table) => anyhow::bail!(
                    "--format table is for the summary; a --channel series is csv or json"
                ),
            };
            let series = inspect::extract(&args.file, topic).map_err(|e| match e {
                inspect::InspectError::UnknownTopic { .. }
                | inspect::InspectError::NotJson { .. } => {
                    anyhow::anyhow!("--channel {topic}: {}: {e}", args.file.display())
                }
                e => anyhow::anyhow!("{}: {e}", args.file.display()),
            })?;
            if format == InspectFormat::Json {
                write!(out, "{}", series.to_json())?;
            } else {
                write!(out, "{}", series.to_csv())?;
            }
            (series.recovered, series.notes.clone())
        }
    };
    if recovered {
        out.flush()?;
        let why = if notes.is_empty() {
            "the file is incomplete".to_string()
        } else {
            notes.join("; ")
        };
        return Err(Recovered(format!(
            "{} is truncated or damaged ({why}); what could be recovered is shown above",
            args.file.display()
        ))
        .into());
    }
    Ok(())
}
