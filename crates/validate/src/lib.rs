//! Validation suites (issue 6): run every camera and the hard cases of a TOML suite in parallel,
//! judge each run against its thresholds, fit how errors grow, compare with a baseline, write
//! report.json, report.md and SVG plots, and split a suite into shards that merge back into the
//! report of the whole suite.
//!
//! Entry points: [`Suite::load`], [`validate`], [`merge_dirs`]. The format of suites and reports is
//! in docs/validation.md.

pub mod closed_form_check;
mod convergence;
/// The growth fits live in the harness (compare reports them too).
pub use rsts_harness::growth;
pub mod plots;
pub mod report;
pub mod run;
pub mod shard;
pub mod suite;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use report::{merge, Report};
pub use run::{RunResult, Status};
pub use shard::Shard;
pub use suite::Suite;

/// Errors of a validation (bad input or I/O); failed runs are not errors but part of the report.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    #[error("suite: {0}")]
    Suite(String),
    #[error("{0}")]
    Usage(String),
    #[error("{0}")]
    Io(String),
    #[error("{0}")]
    Run(String),
}

impl ValidateError {
    /// The message without the `suite: ` of a suite error: what to put after a prefix that
    /// already says where (a file, a case, an option), so no prefix is repeated.
    pub fn detail(&self) -> String {
        match self {
            Self::Suite(s) => s.clone(),
            other => other.to_string(),
        }
    }
}

/// Options of a validation.
#[derive(Clone, Debug, Default)]
pub struct Options {
    pub suite: PathBuf,
    pub report_dir: PathBuf,
    pub baseline: Option<PathBuf>,
    pub shard: Option<Shard>,
    /// Threads; 0: one per core.
    pub jobs: usize,
    /// An external integrator (name, adapter) replacing the methods of every case.
    pub exec: Option<(String, suite::AdapterSpec)>,
}

/// Run a suite (or one shard of it), compare with the baseline, write the report and the plots.
/// `progress` sees each run as it finishes.
pub fn validate(
    opts: &Options,
    progress: &(dyn Fn(&RunResult) + Sync),
) -> Result<Report, ValidateError> {
    let exec = opts.exec.as_ref().map(|(n, a)| (n.as_str(), a));
    let mut inputs = vec![("--suite", opts.suite.as_path())];
    inputs.extend(opts.baseline.as_deref().map(|b| ("--baseline", b)));
    spare_inputs(&inputs, &opts.report_dir)?;
    let suite = Suite::load_with(&opts.suite, exec)?;
    // Read the baseline first: a missing one is an error before any work.
    let baseline = opts.baseline.as_deref().map(Report::read).transpose()?;
    // And make sure the report can be written before the suite runs.
    let out = report_dir(&opts.report_dir)?;
    let runs = match opts.shard {
        Some(sh) => sh.select(&suite.runs),
        None => suite.runs.clone(),
    };
    let started = Instant::now();
    let results = run::execute_all(&runs, opts.jobs, progress)?;
    let mut report = Report::new(
        &suite.name,
        &suite.digest,
        suite.runs.len(),
        opts.shard,
        results,
        started.elapsed().as_secs_f64(),
    );
    if let Some(b) = &baseline {
        report.compare_with(b);
    }
    write_all(&report, out)?;
    Ok(report)
}

/// Merge the reports in `dirs` (shards of one suite) into `out`; optionally compare with a
/// baseline.
pub fn merge_dirs(
    dirs: &[PathBuf],
    out: &Path,
    baseline: Option<&Path>,
) -> Result<Report, ValidateError> {
    let mut inputs: Vec<(&str, &Path)> = dirs.iter().map(|d| ("DIR", d.as_path())).collect();
    inputs.extend(baseline.map(|b| ("--baseline", b)));
    spare_inputs(&inputs, out)?;
    let baseline = baseline.map(Report::read).transpose()?;
    let dir = report_dir(out)?;
    let parts = dirs
        .iter()
        .map(|d| Report::read(d))
        .collect::<Result<Vec<_>, _>>()?;
    let mut report = merge(&parts)?;
    if let Some(b) = &baseline {
        report.compare_with(b);
    }
    write_all(&report, dir)?;
    Ok(report)
}

/// Refuse a report directory that is or holds one of the inputs (it is replaced whole: the
/// input would be lost), before anything is read or run.
fn spare_inputs(inputs: &[rsts_io::Input], dir: &Path) -> Result<(), ValidateError> {
    rsts_io::check_outputs(inputs, &[rsts_io::Output::Dir("--report", dir)])
        .map_err(|e| ValidateError::Usage(e.to_string()))
}

/// Start the report directory `dir` (written whole, see [`write_all`]): refused at once when it
/// cannot be written, or when it exists and holds anything a report does not write (replacing the
/// directory would delete it — the suite file itself, notes): the error names that file.
fn report_dir(dir: &Path) -> Result<rsts_io::AtomicDir, ValidateError> {
    let io = |e: std::io::Error| ValidateError::Io(format!("--report {}: {e}", dir.display()));
    if dir.is_dir() {
        if let Some(foreign) = not_from_a_report(dir).map_err(io)? {
            return Err(ValidateError::Usage(format!(
                "--report {}: the directory holds {}, which a report does not write; the directory \
                 is replaced whole when the report is written and it would be lost: give a new or \
                 empty directory, or an earlier report",
                dir.display(),
                foreign.display()
            )));
        }
    }
    rsts_io::check_writable_dir(dir).map_err(io)?;
    rsts_io::AtomicDir::create(dir).map_err(io)
}

/// The first entry of `dir` that a report does not write (report.json, report.md, plots/*.svg,
/// regular files only), or `None` when replacing `dir` loses nothing of the user's.
fn not_from_a_report(dir: &Path) -> std::io::Result<Option<PathBuf>> {
    let regular = |p: &Path| std::fs::symlink_metadata(p).is_ok_and(|m| m.is_file());
    for entry in std::fs::read_dir(dir)? {
        let p = entry?.path();
        let name = p.file_name().unwrap_or_default().to_string_lossy();
        let ours = match name.as_ref() {
            "report.json" | "report.md" => regular(&p),
            "plots" => {
                if !std::fs::symlink_metadata(&p).is_ok_and(|m| m.is_dir()) {
                    return Ok(Some(p));
                }
                for plot in std::fs::read_dir(&p)? {
                    let q = plot?.path();
                    if !(q.extension().is_some_and(|e| e == "svg") && regular(&q)) {
                        return Ok(Some(q));
                    }
                }
                true
            }
            _ => false,
        };
        if !ours {
            return Ok(Some(p));
        }
    }
    Ok(None)
}

/// Write report.json, report.md and the plots into the staging directory of `dir` and move it
/// into place: a failed or interrupted run leaves the previous report (or none), never a part.
fn write_all(report: &Report, dir: rsts_io::AtomicDir) -> Result<(), ValidateError> {
    let staging = dir.staging().to_path_buf();
    let plots = plots::write_plots(report, &staging)?;
    report.write(&staging, &plots)?;
    dir.commit()
        .map_err(|e| ValidateError::Io(format!("--report: {e}")))
}
