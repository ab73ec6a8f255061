//! The Python package `rsts` (module `rsts._rsts`): the exact reference, identify, compare,
//! check and bench of the CLI, from Python, with numpy arrays in and out.
//!
//! Two faces, one library: every function parses its arguments, calls the same library function
//! as the CLI command of the same name, and returns the CLI's report as a dict, converted from
//! the same serde serialisation ([`report_dict`]: the JSON text of `--format json`, read by
//! `json.loads`), so a field added to a report appears here without a change.
//!
//! Long Rust work runs with the GIL released ([`Python::detach`]) and polls for Ctrl-C
//! ([`Interrupts`]); errors become `ValueError` (bad input), `RuntimeError` (a failed run) or
//! the exception a Python integrator raised, unchanged.

use std::time::{Duration, Instant};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod arrays;
mod bench;
mod case;
mod check;
mod compare;
mod convergence;
mod events;
mod identify;

/// An input's name as this package spells it: the CLI's option without `--`, `_` for `-`
/// (`t-end` → `t_end`).
pub(crate) fn python_name(name: &str) -> String {
    name.replace('-', "_")
}

/// `ValueError` with the message `names: message` (the CLI's message, naming the Python
/// arguments where the CLI names its options).
pub(crate) fn value_error(names: &[impl AsRef<str>], message: impl std::fmt::Display) -> PyErr {
    if names.is_empty() {
        PyValueError::new_err(message.to_string())
    } else {
        let names: Vec<String> = names.iter().map(|n| python_name(n.as_ref())).collect();
        PyValueError::new_err(format!("{}: {message}", names.join("/")))
    }
}

/// A flow's error as the CLI words it, by its kind: `ValueError` for bad input (naming the
/// inputs it concerns), `RuntimeError` for a run that failed, `KeyboardInterrupt` for one
/// that was stopped. Nothing is read from the message.
pub(crate) fn flow_error(e: rsts_flows::FlowError) -> PyErr {
    use rsts_flows::ErrorKind;
    match e.kind() {
        ErrorKind::BadInput => value_error(&e.names(), e),
        ErrorKind::Failed => PyRuntimeError::new_err(e.to_string()),
        ErrorKind::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
    }
}

/// A harness error as the CLI words it (see [`flow_error`]).
pub(crate) fn harness_error(e: rsts_harness::HarnessError) -> PyErr {
    flow_error(e.into())
}

/// A report as a dict: its serde serialisation, the JSON text the CLI prints with
/// `--format json` (field order kept, a NaN as null), read by Python's `json.loads`.
pub(crate) fn report_dict<'py>(
    py: Python<'py>,
    report: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(report)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot serialise the report: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Polls Python's signal handlers (Ctrl-C → `KeyboardInterrupt`) from Rust work running with
/// the GIL released: at most every 50 ms, it takes the GIL for a moment and runs them.
pub(crate) struct Interrupts {
    last: Instant,
    pub(crate) error: Option<PyErr>,
}

impl Interrupts {
    pub(crate) fn new() -> Self {
        Self {
            last: Instant::now(),
            error: None,
        }
    }

    /// True once a signal handler raised (the exception is kept in `error`).
    pub(crate) fn stopped(&mut self) -> bool {
        if self.error.is_none() && self.last.elapsed() >= Duration::from_millis(50) {
            self.last = Instant::now();
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                self.error = Some(e);
            }
        }
        self.error.is_some()
    }

    /// The exception a signal handler raised, if any.
    pub(crate) fn take(&mut self) -> Option<PyErr> {
        self.error.take()
    }
}

/// Exact reference motions and integrator checks for the Kowalevski top in two constant
/// fields (the Reyman–Semenov-Tian-Shansky problem): the Python face of the `rsts` CLI.
///
/// See docs/python.md. The reports are the CLI's `--format json` documents, as dicts.
#[pymodule]
fn _rsts(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "METHODS",
        rsts_dynamics::integrators::MethodName::ALL
            .iter()
            .map(|n| n.as_str())
            .collect::<Vec<_>>(),
    )?;
    m.add_class::<case::Case>()?;
    m.add_function(wrap_pyfunction!(identify::identify, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(bench::bench, m)?)?;
    m.add_function(wrap_pyfunction!(check::check, m)?)?;
    m.add_function(wrap_pyfunction!(convergence::convergence, m)?)?;
    m.add_function(wrap_pyfunction!(events::events, m)?)?;
    Ok(())
}
