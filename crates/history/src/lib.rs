//! The validation history (issue 34): every night of `rsts validate` in an SQLite database,
//! regressions found per series from it, and a static dashboard of its trends.
//!
//! Entry points: [`record`] (a report just written), [`import`] (report.json files),
//! [`regressions`], [`dashboard::build`]. The database and the detection are described in
//! docs/validation.md ("History and dashboard").

pub mod dashboard;
pub mod detect;
mod schema;
pub mod series;
pub mod steps;
pub mod store;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use rsts_validate::Report;
use serde::Serialize;

pub use detect::{Regression, SeriesVerdict};
pub use schema::{Migration, APPLICATION_ID, MIGRATIONS, SCHEMA};
pub use series::{Data, Metric, SeriesKey};
pub use store::{History, Night};

/// Errors of a history: all of them bad input or an unusable file (exit code 2).
#[derive(Debug, thiserror::Error)]
pub enum HistoryError {
    #[error("history {0} does not exist")]
    Missing(String),
    #[error("{path} is not an rsts history: {why}")]
    Foreign { path: String, why: String },
    #[error("{path} is a history of a newer rsts (schema {found}; this rsts knows schemas up to {known}): nothing was written")]
    FutureSchema {
        path: String,
        found: i32,
        known: i32,
    },
    #[error("{path} is a history of an older rsts (schema {found}, this rsts reads {known}): record a night into it (`rsts validate ... --history`, `rsts history import`) to migrate it")]
    OldSchema {
        path: String,
        found: i32,
        known: i32,
    },
    #[error("history {0} is locked by another writer (waited {secs} s); nothing was written", secs = store::BUSY_TIMEOUT.as_secs())]
    Locked(String),
    #[error("history: {0}")]
    Corrupt(String),
    #[error("{0}")]
    Usage(String),
    #[error("{0}")]
    Io(String),
    #[error("history: {0}")]
    Sqlite(#[from] rusqlite::Error),
    #[error("{0}")]
    Report(#[from] rsts_validate::ValidateError),
}

/// Record a report just written into the history at `path` (created when missing); the night is
/// the report's `created`. Returns the night's id.
pub fn record(path: &Path, report: &Report, report_dir: &Path) -> Result<i64, HistoryError> {
    let dir = std::fs::canonicalize(report_dir).unwrap_or_else(|_| report_dir.to_path_buf());
    let night = Night::of(report, None, Some(dir), "the report")?;
    History::open_for_writing(path)?.record(&night)
}

/// What [`import`] recorded.
#[derive(Debug, Serialize)]
pub struct Imported {
    /// (report file, night, night id) in the order given.
    pub nights: Vec<(String, String, i64)>,
}

/// Load report.json files (or their directories) into the history at `path`, one night each:
/// the report's `created`, or `night` for a report without one. Every report is read and checked
/// (readable, dated, not already in the history, not given twice) before anything is written;
/// then each night goes in as one transaction.
pub fn import(
    path: &Path,
    reports: &[PathBuf],
    night: Option<&str>,
) -> Result<Imported, HistoryError> {
    if reports.is_empty() {
        return Err(HistoryError::Usage(
            "history import: no report given".into(),
        ));
    }
    let mut loaded = Vec::new();
    for r in reports {
        let report = Report::read(r)?;
        let dir = if r.is_dir() {
            r.clone()
        } else {
            r.parent().map(Path::to_path_buf).unwrap_or_default()
        };
        let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
        loaded.push((r.display().to_string(), report, dir));
    }
    let mut history = History::open_for_writing(path)?;
    let mut nights = Vec::new();
    let mut seen: Vec<&Report> = Vec::new();
    for (name, report, dir) in &loaded {
        let n = Night::of(report, night, Some(dir.clone()), name)?;
        if seen.contains(&report) {
            return Err(HistoryError::Usage(format!(
                "{name}: the same report is given twice"
            )));
        }
        seen.push(report);
        if history.has(&n)? {
            return Err(HistoryError::Usage(format!(
                "{name}: {} already holds this report (night {}); nothing was written",
                path.display(),
                n.night
            )));
        }
        nights.push((name.clone(), n));
    }
    let mut out = Imported { nights: Vec::new() };
    for (name, n) in &nights {
        let id = history.record(n)?;
        out.nights.push((name.clone(), n.night.clone(), id));
    }
    Ok(out)
}

/// The regressed series of a history, one entry each (sorted by suite, case, method, tolerance,
/// metric), and how much was looked at.
#[derive(Debug, Serialize)]
pub struct RegressionReport {
    pub history: String,
    pub nights: usize,
    pub series: usize,
    pub regressions: Vec<Regression>,
}

/// Judge every series of the history at `path` (read only).
pub fn regressions(path: &Path) -> Result<RegressionReport, HistoryError> {
    let data = History::open(path)?.load()?;
    let regressions = data
        .series
        .iter()
        .filter_map(|(key, points)| detect::judge(&data, key, points).regression)
        .collect();
    Ok(RegressionReport {
        history: path.display().to_string(),
        nights: data.nights.len(),
        series: data.series.len(),
        regressions,
    })
}
