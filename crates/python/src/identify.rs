//! `rsts.identify`: which motion of N a state is on (`rsts identify --format json`).

use pyo3::prelude::*;

use rsts_dynamics::State;
use rsts_harness::identify::{identify_state, Identification};

use crate::{arrays, report_dict, value_error};

/// Which motion of N the state (omega, alpha, beta) is on, in the fields a > b > 0: a dict with
/// the keys of `rsts identify --format json` — on_N, m, h, camera, tori, torus, phase1, phase2
/// (the angles at which `Case(a, b, m, h, torus, phase1, phase2)` starts at the state),
/// distance_from_N, relative_distance_from_N, residual, normal, digits.
///
/// A state whose relative distance from N exceeds `tolerance` gives
/// {"on_N": False, "distance_from_N": ..., "relative_distance_from_N": ..., "tolerance": ...}
/// (the CLI prints the same and exits with 1). Bad input (9 finite numbers, |alpha| = |beta| = 1,
/// alpha.beta = 0 within 1e-9, a > b > 0) raises ValueError.
#[pyfunction]
#[pyo3(signature = (state, a = 1.0, b = 0.5, tolerance = 1e-9))]
pub fn identify<'py>(
    py: Python<'py>,
    state: &Bound<'py, PyAny>,
    a: f64,
    b: f64,
    tolerance: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let x = arrays::state(state, "state")?;
    let s = State::from_slice(&x);
    let result = py.detach(move || identify_state(&a, &b, &s, tolerance, 17));
    match result {
        Err(e) => {
            // The state's components are one argument here.
            let names: Vec<&str> = if e.parameters == ["omega", "alpha", "beta"] {
                vec!["state"]
            } else {
                e.parameters.clone()
            };
            Err(value_error(&names, e.message))
        }
        Ok(Identification::OffN(off)) => report_dict(py, &off),
        Ok(Identification::OnN(doc, _)) => report_dict(py, &doc),
    }
}
