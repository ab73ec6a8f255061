//! `rsts.events`: exact event times along a motion of N (`rsts events --format json`, the same
//! [`rsts_closed_form::events::events_report`]).

use pyo3::prelude::*;

use rsts_closed_form::events::{events_report, EventCase, EventSpec};

use crate::case::whole;
use crate::{report_dict, value_error};

/// The exact times in (t_start, t_end] at which the event functions `names` cross zero along the
/// motion (a, b, m, h, torus, phase1, phase2): a dict with the keys of `rsts events --format
/// json` — case, events: [{name, t, direction, state: {omega, alpha, beta}}]. Names as in the CLI:
/// "omega1".."beta3", "gamma1".."gamma3", "s1", "s2", each optionally with ":up", ":down" or
/// ":both". With `digits`, times and states are decimal strings of that many digits; without,
/// floats correctly rounded. Bad input (an unknown name, an empty window, a motion that does not
/// exist) raises ValueError. See docs/events.md.
#[pyfunction]
#[pyo3(signature = (names, m = 0.3, h = -0.375, a = 1.0, b = 0.5, torus = 0, phase1 = 0.0, phase2 = 0.0, t_start = 0.0, t_end = 10.0, digits = None))]
#[allow(clippy::too_many_arguments)]
pub fn events<'py>(
    py: Python<'py>,
    names: Vec<String>,
    m: f64,
    h: f64,
    a: f64,
    b: f64,
    torus: i64,
    phase1: f64,
    phase2: f64,
    t_start: f64,
    t_end: f64,
    digits: Option<i64>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut specs: Vec<EventSpec> = Vec::new();
    for n in &names {
        let spec: EventSpec = n.parse().map_err(|e| value_error(&["names"], e))?;
        specs.push(spec);
    }
    if specs.is_empty() {
        return Err(value_error(&["names"], "give at least one event name"));
    }
    if t_end.partial_cmp(&t_start) != Some(std::cmp::Ordering::Greater) {
        return Err(value_error(
            &["t_start", "t_end"],
            "the window (t_start, t_end] is empty",
        ));
    }
    let digits = match digits {
        None => None,
        Some(d) if (16..=10_000).contains(&d) => Some(d as u32),
        Some(d) => {
            return Err(value_error(
                &["digits"],
                format!("must be 16 to 10000, got {d}"),
            ))
        }
    };
    let motion =
        rsts_closed_form::Motion::from_f64s([a, b, m, h], whole("torus", torus)?, [phase1, phase2])
            .map_err(|e| value_error(&[e.name], e.error))?;
    let case = EventCase {
        motion,
        t_start,
        t_end,
        digits,
        camera: String::new(),
    };
    let report = py
        .detach(move || events_report(case, &specs))
        .map_err(|e| crate::harness_error(e.into()))?;
    report_dict(py, &report)
}
