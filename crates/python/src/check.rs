//! `rsts.check`: a trajectory computed elsewhere, as arrays, against the closed form
//! (`rsts check FILE --format json`, the same [`rsts_harness::check`]).

use pyo3::prelude::*;
use rug::Float;

use rsts_closed_form::Motion;
use rsts_dynamics::State;
use rsts_harness::reference::check_times;
use rsts_harness::{check_finite_report, CheckMotion, CheckRequest, HarnessError};

use crate::case::whole;
use crate::compare::{finish, Watch};
use crate::{arrays, harness_error, report_dict, value_error, Interrupts};

/// Check a trajectory computed elsewhere — `times` (1-D, strictly increasing, any spacing) and
/// `states` (shape (len(times), 9): omega, alpha, beta per row) — against the exact motion on N:
/// a dict with the keys of `rsts check FILE --format json` (file, case, start_state_error,
/// start_distance_from_N, and the report of `rsts.compare`: max_state_error, drift, ...).
///
/// The motion is given by m and h (with torus, phase1, phase2: the angles at t = 0), or, without
/// them, identified from the first row, which must lie on N (relative distance <= 1e-8).
/// `digits`: the decimal digits the data carry (default 15, float64); the reference is
/// evaluated 64 bits beyond (at least 30 digits). `name` is the report's `method`.
///
/// The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt. Bad input (shapes,
/// NaN, times not increasing, a motion that does not exist) raises ValueError.
#[pyfunction]
#[pyo3(signature = (times, states, a = 1.0, b = 0.5, m = None, h = None, torus = None, phase1 = None, phase2 = None, digits = None, name = "arrays"))]
#[allow(clippy::too_many_arguments)]
pub fn check<'py>(
    py: Python<'py>,
    times: &Bound<'py, PyAny>,
    states: &Bound<'py, PyAny>,
    a: f64,
    b: f64,
    m: Option<f64>,
    h: Option<f64>,
    torus: Option<i64>,
    phase1: Option<f64>,
    phase2: Option<f64>,
    digits: Option<i64>,
    name: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let exact = |name, x: f64| {
        rsts_closed_form::motion::binary(name, x).map_err(|e| value_error(&[name], e.error))
    };
    let (a, b) = (exact("a", a)?, exact("b", b)?);
    let motion = match (m, h) {
        (Some(m), Some(h)) => CheckMotion::Given(Motion {
            a,
            b,
            m: exact("m", m)?,
            h: exact("h", h)?,
            torus: whole("torus", torus.unwrap_or(0))?,
            phase1: exact("phase1", phase1.unwrap_or(0.0))?,
            phase2: exact("phase2", phase2.unwrap_or(0.0))?,
        }),
        (None, None) if torus.is_none() && phase1.is_none() && phase2.is_none() => {
            CheckMotion::Identify { a, b }
        }
        (None, None) => {
            return Err(value_error(
                &["torus", "phase1", "phase2"],
                "need m and h (without them the whole motion is identified from the first row)",
            ))
        }
        _ => return Err(value_error(&["m", "h"], "give both or neither")),
    };
    let digits = match digits {
        None => 15,
        Some(d) if (1..=10_000).contains(&d) => d as u32,
        Some(d) => {
            return Err(value_error(
                &["digits"],
                format!("must be between 1 and 10000, got {d}"),
            ))
        }
    };
    let request = CheckRequest {
        file: "<arrays>".into(),
        name: name.to_string(),
        motion,
        digits,
    };
    request.validate().map_err(|e| match e {
        HarnessError::Dynamics(_) => value_error(&["a", "b"], e),
        e => harness_error(e),
    })?;
    let t = arrays::vector(times, "times")?;
    check_times(&t).map_err(|e| value_error(&["times"], e))?;
    let x = arrays::states(states, "states", Some(t.len()), Some(&t))?;
    let result = py.detach(move || {
        let bits = request.reference_bits();
        let times: Vec<Float> = t.iter().map(|&t| Float::with_val(bits, t)).collect();
        let states: Vec<State<Float>> = x
            .iter()
            .map(|r| State::from_slice(r).map(|v| Float::with_val(bits, *v)))
            .collect();
        let mut watch = Watch(Interrupts::new());
        let result = rsts_harness::check(&request, &times, &states, &mut watch);
        Ok::<_, HarnessError>((result, watch.0.take()))
    });
    let report = finish(result, None)?;
    check_finite_report(&report.report).map_err(harness_error)?;
    report_dict(py, &report)
}
