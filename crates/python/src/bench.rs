//! `rsts.bench`: work against precision of built-in methods and Python callables
//! (`rsts bench --format json`, the same [`rsts_harness::bench()`] and report type).

use pyo3::prelude::*;

use rsts_dynamics::integrators::{MethodName, Tolerances};
use rsts_harness::bench::{BenchIntegrator, BenchObserver, OutsideMethod};
use rsts_harness::{BenchMethod, BenchRequest, HarnessError};

use crate::case::{int, whole, Case, Int};
use crate::compare::{finish_harness, Callable};
use crate::{arrays, report_dict, value_error, Interrupts};

impl BenchIntegrator for Callable {}

/// A callable as a method of a benchmark: the same callable at each tolerance.
struct CallableMethod(Callable);

impl OutsideMethod for CallableMethod {
    fn what(&self) -> String {
        self.0.name.clone()
    }

    fn at(
        &mut self,
        tolerances: Tolerances,
        _digits: u32,
    ) -> Result<Box<dyn BenchIntegrator>, HarnessError> {
        Ok(Box::new(self.0.at(tolerances)))
    }
}

/// Notes kept for Python's warnings; Ctrl-C polled between runs.
struct Watch {
    interrupts: Interrupts,
    notes: Vec<String>,
}

impl BenchObserver for Watch {
    fn note(&mut self, text: &str) {
        self.notes.push(text.to_string());
    }

    fn running(&mut self, _what: &str) -> Result<(), HarnessError> {
        if self.interrupts.stopped() {
            return Err(HarnessError::Observer("interrupted".into()));
        }
        Ok(())
    }
}

/// Measure work against precision: each integrator at each tolerance (rtol = atol) along
/// `case` (default: `Case.default()`), the largest state error at `samples` times evenly spaced
/// on [0, t_end] against the closed form, the time (median of `repeats` runs), steps and
/// evaluations. A dict with the keys of `rsts bench --format json`: case, repeats,
/// taylor_mp_digits (with taylor-mp), rows (method, tolerance, max_error, scd, mescd, scd_min,
/// mescd_min, integration_seconds, time_min, time_median, time_max, steps, rhs_evals), fits
/// (max error = C tol^p per method), environment.
///
/// `integrators`: built-in method names (rsts.METHODS) and Python callables
/// `f(x0, times, a, b, rtol, atol)` (as for rsts.compare), mixed; the built-ins' rows come
/// first. A callable is called `repeats` times per tolerance; its time is measured around its
/// call (steps and rhs_evals are None: not seen from outside); its row is named by its
/// `__qualname__`. A tolerance below a built-in's round-off is skipped with a warning.
/// `digits`: taylor-mp's decimal digits (default: those of the smallest tolerance + 10).
///
/// An exception a callable raises propagates unchanged; an answer of the wrong shape, with NaN
/// or not an array raises ValueError naming what was wrong; bad input raises ValueError with
/// the CLI's message. The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt
/// (between runs).
#[pyfunction]
#[pyo3(
    signature = (integrators, case = None, tolerances = vec![1e-6, 1e-8, 1e-10], t_end = 100.0, samples = Int::of(101), repeats = Int::of(3), digits = None),
    text_signature = "(integrators, case=None, tolerances=(1e-06, 1e-08, 1e-10), t_end=100.0, samples=101, repeats=3, digits=None)"
)]
#[allow(clippy::too_many_arguments)]
pub fn bench<'py>(
    py: Python<'py>,
    integrators: &Bound<'py, PyAny>,
    case: Option<Case>,
    tolerances: Vec<f64>,
    t_end: f64,
    samples: Int,
    repeats: Int,
    digits: Option<Int>,
) -> PyResult<Bound<'py, PyAny>> {
    let digits = int("digits", digits)?;
    let case = Case::or_default(case)?;
    let samples = whole("samples", samples)?;
    let repeats = whole("repeats", repeats)?;
    let digits = digits
        .map(|d| {
            u32::try_from(d).map_err(|_| {
                value_error(
                    &["digits"],
                    format!(
                        "must be between 10 and {}, got {d}",
                        rsts_dynamics::integrators::MAX_MP_DIGITS
                    ),
                )
            })
        })
        .transpose()?;
    let list: Vec<Bound<'py, PyAny>> =
        if integrators.extract::<String>().is_ok() || integrators.is_callable() {
            vec![integrators.clone()]
        } else {
            integrators
                .try_iter()
                .map_err(|_| {
                    value_error(
                        &["integrators"],
                        format!(
                            "expected a list of method names and callables, got {}",
                            arrays::describe(integrators)
                        ),
                    )
                })?
                .collect::<PyResult<_>>()?
        };
    let mut builtins = Vec::new();
    let mut callables = Vec::new();
    // Any tolerance: each callable is re-made at the benchmark's tolerances.
    let any = Tolerances::new(1e-8, 1e-8).map_err(|e| value_error(&["tolerances"], e))?;
    for item in &list {
        if let Ok(name) = item.extract::<String>() {
            let method: MethodName = name.parse().map_err(|e| value_error(&["integrators"], e))?;
            builtins.push(method);
        } else if item.is_callable() {
            callables.push(CallableMethod(Callable::new(item, any)?));
        } else {
            return Err(value_error(
                &["integrators"],
                format!(
                    "expected method names (one of {}) or callables f(x0, times, a, b, rtol, atol), got {}",
                    MethodName::ALL.map(|m| m.as_str()).join(", "),
                    arrays::describe(item)
                ),
            ));
        }
    }
    let mut methods: Vec<BenchMethod> = builtins.into_iter().map(BenchMethod::BuiltIn).collect();
    methods.extend(
        callables
            .iter_mut()
            .map(|c| BenchMethod::Outside(c as &mut (dyn OutsideMethod + Send))),
    );
    let request = BenchRequest {
        case: case.on_grid(crate::case::time("t_end", t_end)?, samples),
        methods,
        tolerances,
        repeats,
        digits,
        events: Vec::new(),
    };
    let (result, notes) = py.detach(|| {
        let mut watch = Watch {
            interrupts: Interrupts::new(),
            notes: Vec::new(),
        };
        let result = rsts_harness::bench(request, &mut watch).map_err(rename);
        (Ok((result, watch.interrupts.take())), watch.notes)
    });
    let warnings = py.import("warnings")?;
    for note in notes {
        warnings.call_method1("warn", (note.trim_start_matches("note: "),))?;
    }
    let callable_error = callables.iter().find_map(|c| c.0.take_error());
    let report = finish_harness(result, callable_error)?;
    report_dict(py, &report)
}

/// The CLI's option names as this function's arguments (`methods` → `integrators`,
/// `t-end` → `t_end`).
fn rename(e: HarnessError) -> HarnessError {
    match e {
        HarnessError::Setting(names, message) => HarnessError::Setting(
            names
                .into_iter()
                .map(|n| match n.as_str() {
                    "methods" => "integrators".into(),
                    "t-end" => "t_end".into(),
                    _ => n,
                })
                .collect(),
            message,
        ),
        e => e,
    }
}
