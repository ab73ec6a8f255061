//! Suite files (TOML): defaults, cases, and their expansion into runs with stable ids.
//!
//! A case names a point (m, h) of N — given directly or placed relative to Σ, to the hyperbola
//! ℓ = 0 or to an equilibrium — the tori, the methods and tolerances, and the thresholds every run
//! must meet. Expansion turns every (torus, method, tolerance) into a [`Run`] with an id
//! `case/t<torus>/<method>@<tol>` (and `case/t<torus>/closed-form` for the check of the closed
//! form itself); ids are unique in a suite and sorted.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice};
use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use serde::{Deserialize, Serialize};

use crate::convergence::convergence_runs;
pub use crate::convergence::ConvergenceSpec;
use crate::ValidateError;

mod expand;
mod run;
mod spec;
#[cfg(test)]
mod tests;

use expand::expand_case;
pub use expand::place_h;
use run::method_config;
pub use run::{Run, RunKind};
pub use spec::{AdapterSpec, CaseSpec, Defaults, Placement, SuiteFile, Thresholds, Tori};

/// A parsed, expanded suite.
#[derive(Clone, Debug, PartialEq)]
pub struct Suite {
    pub name: String,
    /// Runs sorted by id.
    pub runs: Vec<Run>,
    /// A digest of the expanded runs (FNV-1a of their JSON), shared by all shards of a suite.
    pub digest: String,
}

/// Largest number of samples of one run (every sample is kept for the fits).
pub const MAX_SAMPLES: usize = 1_000_000;
/// Most runs a suite may expand to (refused at once above it: the runs are held in memory).
pub const MAX_RUNS: usize = 20_000;
/// Largest suite file read (bytes).
pub const MAX_SUITE_BYTES: u64 = 4 * 1024 * 1024;

/// Default thresholds of the closed-form check (f64 against 50 digits; residual at 50 digits).
pub const DEFAULT_CLOSED_FORM_F64: f64 = 1e-12;
pub const DEFAULT_CLOSED_FORM_RESIDUAL: f64 = 1e-38;

impl Suite {
    /// Read and expand a suite file.
    pub fn load(path: &Path) -> Result<Suite, ValidateError> {
        Suite::load_with(path, None)
    }

    /// Parse and expand suite text; `fallback_name` names a suite without `name`.
    pub fn parse(text: &str, fallback_name: &str) -> Result<Suite, ValidateError> {
        Suite::parse_with(text, fallback_name, None)
    }

    /// Read a suite file; with `exec` = (NAME, adapter), that external integrator replaces the
    /// methods of every case (`rsts validate --exec`).
    pub fn load_with(
        path: &Path,
        exec: Option<(&str, &AdapterSpec)>,
    ) -> Result<Suite, ValidateError> {
        let cannot = |e: std::io::Error| {
            ValidateError::Io(format!("cannot read suite {}: {e}", path.display()))
        };
        let file = std::fs::File::open(path).map_err(cannot)?;
        let mut text = String::new();
        std::io::Read::read_to_string(
            &mut std::io::Read::take(file, MAX_SUITE_BYTES + 1),
            &mut text,
        )
        .map_err(cannot)?;
        if text.len() as u64 > MAX_SUITE_BYTES {
            return Err(ValidateError::Suite(format!(
                "{}: larger than {MAX_SUITE_BYTES} bytes (4 MiB), the most a suite file may have; split it",
                path.display()
            )));
        }
        let fallback = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "suite".into());
        Suite::parse_with(&text, &fallback, exec)
            .map_err(|e| ValidateError::Suite(format!("{}: {}", path.display(), e.detail())))
    }

    /// [`Suite::parse`], with every case's methods replaced by the adapter `exec` when given
    /// (the convergence cases, which hold built-in methods' orders, are then left out).
    pub fn parse_with(
        text: &str,
        fallback_name: &str,
        exec: Option<(&str, &AdapterSpec)>,
    ) -> Result<Suite, ValidateError> {
        let mut file: SuiteFile =
            toml::from_str(text).map_err(|e| ValidateError::Suite(toml_error(text, &e)))?;
        if let Some((name, adapter)) = exec {
            file.adapters.insert(name.to_string(), adapter.clone());
            // Convergence cases hold the built-ins' orders (their min_order is a built-in's).
            file.cases.retain(|case| case.convergence.is_none());
            file.defaults.methods = Some(vec![name.to_string()]);
            for case in &mut file.cases {
                case.methods = Some(vec![name.to_string()]);
            }
        }
        Suite::expand(&file, fallback_name)
    }

    /// Expand every case into runs.
    pub fn expand(file: &SuiteFile, fallback_name: &str) -> Result<Suite, ValidateError> {
        if file.cases.is_empty() {
            return Err(ValidateError::Suite("the suite has no [[case]]".into()));
        }
        for (name, adapter) in &file.adapters {
            check_name(name).map_err(|e| ValidateError::Suite(format!("adapter {e}")))?;
            if name.parse::<MethodName>().is_ok() {
                return Err(ValidateError::Suite(format!(
                    "adapter '{name}': the name of a built-in method"
                )));
            }
            if adapter.command.is_empty() || adapter.command[0].is_empty() {
                return Err(ValidateError::Suite(format!(
                    "adapter '{name}': command must name a program, e.g. command = [\"python3\", \"my_adapter.py\"]"
                )));
            }
            if let Some(t) = adapter.timeout {
                rsts_external::check_timeout(t)
                    .map_err(|e| ValidateError::Suite(format!("[adapters.{name}] timeout: {e}")))?;
            }
        }
        let mut runs = Vec::new();
        let mut names = BTreeSet::new();
        for spec in &file.cases {
            if !names.insert(spec.name.clone()) {
                return Err(ValidateError::Suite(format!(
                    "case name '{}' is used twice",
                    spec.name
                )));
            }
            runs.extend(expand_case(&file.defaults, &file.adapters, spec)?);
            if runs.len() > MAX_RUNS {
                return Err(too_many_runs(runs.len(), &spec.name));
            }
        }
        runs.sort_by(|x, y| x.id.cmp(&y.id));
        for w in runs.windows(2) {
            if w[0].id == w[1].id {
                return Err(ValidateError::Suite(format!(
                    "run id '{}' occurs twice (a method or tolerance listed twice?)",
                    w[0].id
                )));
            }
        }
        let json = serde_json::to_string(&runs).expect("runs serialise");
        Ok(Suite {
            name: file.name.clone().unwrap_or_else(|| fallback_name.into()),
            digest: format!("{:016x}", fnv1a(json.as_bytes())),
            runs,
        })
    }
}

/// A suite that expands to more than [`MAX_RUNS`] runs (counted up to case `name`).
fn too_many_runs(runs: usize, name: &str) -> ValidateError {
    ValidateError::Suite(format!(
        "the suite expands to {runs} runs by case '{name}', more than the {MAX_RUNS} a suite may have; split it into several suites (or shards of one)"
    ))
}

/// FNV-1a, 64 bits (the harness's, shared with the shards of a benchmark).
pub use rsts_harness::shard::fnv1a;

/// The tolerance as it appears in a run id: `1e-12`, `2.5e-8`.
pub fn tol_label(x: f64) -> String {
    format!("{x:e}")
}

/// A case name usable in ids and file names: letters, digits, `-`, `_`, `.`, `+`.
fn check_name(name: &str) -> Result<(), ValidateError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.+".contains(c))
    {
        return Err(ValidateError::Suite(format!(
            "case name '{name}': use only ASCII letters, digits and - _ . + (it is part of run ids and file names)"
        )));
    }
    Ok(())
}

fn finite(what: &str, name: &str, v: f64) -> Result<f64, ValidateError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ValidateError::Suite(format!(
            "{what}: {name} must be a finite number, got {v}"
        )))
    }
}

/// A TOML error as one short message: where (line, column), what (quoted values cut at 40
/// characters), and the line around the place (40 characters either side) — not the whole line
/// (one of 200 kB used to be printed, twice).
fn toml_error(text: &str, e: &toml::de::Error) -> String {
    let message = cut_quoted(e.message().trim());
    let Some(span) = e.span() else {
        return message;
    };
    let at = span.start.min(text.len());
    let at = (0..=at)
        .rev()
        .find(|&k| text.is_char_boundary(k))
        .unwrap_or(0);
    let line_start = text[..at].rfind('\n').map_or(0, |k| k + 1);
    let line_end = text[at..].find('\n').map_or(text.len(), |k| at + k);
    let line_no = text[..at].matches('\n').count() + 1;
    let before: Vec<char> = text[line_start..at].chars().collect();
    let after: Vec<char> = text[at..line_end].chars().collect();
    let column = before.len() + 1;
    const SIDE: usize = 40;
    let head: String = before[before.len().saturating_sub(SIDE)..].iter().collect();
    let tail: String = after[..after.len().min(SIDE)].iter().collect();
    format!(
        "line {line_no}, column {column}: {message}: {}{head}{tail}{}",
        if before.len() > SIDE { "…" } else { "" },
        if after.len() > SIDE { "…" } else { "" },
    )
}

/// `text` with every quoted part ("…" or '…') longer than 40 characters cut
/// ([`rsts_io::cut`]).
fn cut_quoted(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(k) = rest.find(['"', '\'']) {
        let q = rest[k..].chars().next().unwrap_or('"');
        out.push_str(&rest[..=k]);
        rest = &rest[k + 1..];
        let Some(end) = rest.find(q) else {
            out.push_str(&rsts_io::cut(rest));
            return out;
        };
        out.push_str(&rsts_io::cut(&rest[..end]));
        out.push(q);
        rest = &rest[end + 1..];
    }
    out.push_str(rest);
    out
}
