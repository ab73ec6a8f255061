//! `rsts.identify`: which motion of N a state is on (`rsts identify --format json`, the same
//! flow, [`rsts_flows::identify`]).

use pyo3::prelude::*;

use rsts_flows::identify::{identify as identify_flow, IdentifyRequest};

use crate::case::{digits_arg, number, numbers, Int};
use crate::{arrays, flow_error, report_dict};

/// Which motion of N the state (omega, alpha, beta) is on, in the fields a > b > 0: a dict with
/// the keys of `rsts identify --format json` — on_N, a, b, m, h, camera, tori, torus, phase1,
/// phase2 (the angles at which `Case(a, b, m, h, torus, phase1, phase2)` starts at the state),
/// distance_from_N, relative_distance_from_N, residual, normal, digits.
///
/// Numbers as in `Case`: the state's nine components as floats (their exact binary values) or
/// as decimal strings, a and b likewise. With `digits` (16 to 100000) the computation carries
/// that many digits and m, h, a, b and the phases are decimal strings; a state written by
/// `explicit` to D digits gives back its decimals to about D digits.
///
/// A state whose relative distance from N exceeds `tolerance` gives
/// {"on_N": False, "distance_from_N": ..., "relative_distance_from_N": ..., "tolerance": ...}
/// (the CLI prints the same and exits with 1). Bad input (9 finite numbers, |alpha| = |beta| = 1,
/// alpha.beta = 0 within 1e-9, a > b > 0) raises ValueError.
#[pyfunction]
#[pyo3(signature = (state, a = None, b = None, tolerance = 1e-9, digits = None))]
pub fn identify<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    a: Option<&Bound<'py, PyAny>>,
    b: Option<&Bound<'py, PyAny>>,
    tolerance: f64,
    digits: Option<Int>,
) -> PyResult<Bound<'py, PyAny>> {
    let digits = crate::case::int("digits", digits)?;
    let state = match numbers("state", state)? {
        Some(x) => x,
        None => arrays::state(state, "state")?
            .iter()
            .map(|&x| crate::case::time("state", x))
            .collect::<PyResult<Vec<_>>>()?,
    };
    let state: [rsts_flows::Decimal; 9] = state.try_into().map_err(|v: Vec<_>| {
        crate::value_error(
            &["state"],
            format!("expected 9 numbers (omega, alpha, beta), got {}", v.len()),
        )
    })?;
    let field = |name, x: Option<&Bound<'py, PyAny>>, default: &str| match x {
        Some(x) => number(name, x),
        None => Ok(rsts_flows::Decimal::parse(default).expect("a default")),
    };
    let request = IdentifyRequest {
        a: field("a", a, "1")?,
        b: field("b", b, "0.5")?,
        state,
        tolerance,
        digits: digits_arg(digits, rsts_flows::identify::DIGITS)?,
    };
    let outcome = py
        .detach(move || identify_flow(&request))
        .map_err(|e| {
            // The state's components are one argument here.
            match e {
                rsts_flows::FlowError::Input { names, message }
                    if names == ["omega", "alpha", "beta"] =>
                {
                    rsts_flows::FlowError::input(&["state"], message)
                }
                e => e,
            }
        })
        .map_err(flow_error)?;
    report_dict(py, &outcome)
}
