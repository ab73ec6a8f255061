//! `rsts.check`: a trajectory computed elsewhere — a file, or arrays — against the closed form:
//! the flow of `rsts check FILE` ([`rsts_flows::check`]), its document as a dict.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyList, PyString, PyTuple};

use rsts_closed_form::events::EventName;
use rsts_closed_form::{Decimal, Motion};
use rsts_flows::check::{CheckRequest, DetectedEvents, Source};
use rsts_flows::Limits;
use rsts_harness::events::DetectedEvent;
use rsts_harness::reference::check_times;
use rsts_harness::CheckMotion;

use crate::case::{int, number, whole, Case, Int};
use crate::compare::{event_specs, finish, Watch};
use crate::{arrays, report_dict, value_error, Interrupts};

/// A path argument (str or os.PathLike), if it is one.
fn path(obj: &Bound<'_, PyAny>) -> Option<PathBuf> {
    if obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__").unwrap_or(false) {
        obj.extract::<PathBuf>().ok()
    } else {
        None
    }
}

/// `events=`: a file (path) or a list of (name, t) pairs or {"name", "t"} dicts in time order.
fn detected(obj: &Bound<'_, PyAny>) -> PyResult<DetectedEvents> {
    if let Some(p) = path(obj) {
        return Ok(DetectedEvents::File(p));
    }
    let list = obj.cast::<PyList>().map_err(|_| {
        value_error(
            &["events"],
            format!(
                "expected a file path or a list of (name, t), got {}",
                arrays::describe(obj)
            ),
        )
    })?;
    let mut out: Vec<DetectedEvent> = Vec::new();
    for (i, item) in list.iter().enumerate() {
        let (name, t): (String, f64) = if let Ok(pair) = item.cast::<PyTuple>() {
            pair.extract()
        } else {
            item.get_item("name")
                .and_then(|n| n.extract())
                .and_then(|n| Ok((n, item.get_item("t")?.extract()?)))
        }
        .map_err(|_| {
            value_error(
                &["events"],
                format!("events[{i}]: expected (name, t) or {{\"name\", \"t\"}}"),
            )
        })?;
        let name = EventName::parse(name.trim()).ok_or_else(|| {
            value_error(&["events"], format!("events[{i}]: unknown event '{name}'"))
        })?;
        if !t.is_finite() {
            return Err(value_error(
                &["events"],
                format!("events[{i}]: the time is not a finite number"),
            ));
        }
        if out.last().is_some_and(|last| t < last.t) {
            return Err(value_error(
                &["events"],
                format!("events[{i}]: t = {t} is before the previous event's; list events in time order"),
            ));
        }
        out.push(DetectedEvent { name, t });
    }
    Ok(DetectedEvents::List(out))
}

/// Check a trajectory computed elsewhere against the exact motion on N: a dict with the keys of
/// `rsts check FILE --format json` (file, case, start_state_error, start_distance_from_n, the
/// report of `rsts.compare`: max_state_error, drift, ...; with `events`, "events").
///
/// The trajectory is a file — `source` a path (str or os.PathLike): .csv, .json, .npy or
/// .mcap, read as `rsts check FILE` reads it, a chunk at a time — or arrays: `source` the times
/// (1-D, strictly increasing, any spacing) and `states` (shape (len(times), 9): omega, alpha,
/// beta per row), analysed a chunk at a time like a file's rows.
///
/// The motion is `case` (a `Case`), or given by m and h (with torus, phase1, phase2: the angles
/// at t = 0) in fields a, b, or, without them, identified from the first row, which must lie on
/// N (relative distance <= 1e-8). Numbers as in `Case`: a str is the decimal it holds, a float
/// its exact binary value. `digits`: the decimal digits the data carry (default 15 for float64
/// arrays; a file's as `rsts check` decides); the reference is evaluated 64 bits beyond (at
/// least 30 digits). `name` is the report's `method` for arrays ("arrays").
///
/// `events`: the events the integrator detected — a file (CSV name,t or JSON {"events": [...]})
/// or a list of (name, t) — matched with the exact events of the same names (and of `expect`,
/// names such as "omega1") in (t_first, t_last].
///
/// The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt. Bad input (shapes,
/// NaN, times not increasing, a file that is not a trajectory, a motion that does not exist)
/// raises ValueError.
#[pyfunction]
#[pyo3(signature = (source, states = None, a = None, b = None, m = None, h = None, torus = None, phase1 = None, phase2 = None, case = None, digits = None, name = "arrays", events = None, expect = None))]
#[allow(clippy::too_many_arguments)]
pub fn check<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    states: Option<&Bound<'py, PyAny>>,
    a: Option<&Bound<'py, PyAny>>,
    b: Option<&Bound<'py, PyAny>>,
    m: Option<&Bound<'py, PyAny>>,
    h: Option<&Bound<'py, PyAny>>,
    torus: Option<Int>,
    phase1: Option<&Bound<'py, PyAny>>,
    phase2: Option<&Bound<'py, PyAny>>,
    case: Option<Case>,
    digits: Option<Int>,
    name: &str,
    events: Option<&Bound<'py, PyAny>>,
    expect: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyAny>> {
    let digits = int("digits", digits)?;
    let given = |name, x: Option<&Bound<'py, PyAny>>, default: i64| match x {
        Some(x) => number(name, x),
        None => Ok(Decimal::from_integer(default)),
    };
    let motion = match (case, m, h) {
        (Some(case), None, None)
            if [a, b, phase1, phase2].iter().all(Option::is_none) && torus.is_none() =>
        {
            CheckMotion::Given(case.motion)
        }
        (Some(_), ..) => {
            return Err(value_error(
                &["case"],
                "the case gives the whole motion: not with a, b, m, h, torus, phase1, phase2",
            ))
        }
        (None, Some(m), Some(h)) => CheckMotion::Given(Motion {
            a: given("a", a, 1)?,
            b: match b {
                Some(b) => number("b", b)?,
                None => Decimal::parse("0.5").expect("a decimal"),
            },
            m: number("m", m)?,
            h: number("h", h)?,
            torus: whole("torus", torus.unwrap_or(Int::of(0)))?,
            phase1: given("phase1", phase1, 0)?,
            phase2: given("phase2", phase2, 0)?,
        }),
        (None, None, None) if torus.is_none() && phase1.is_none() && phase2.is_none() => {
            CheckMotion::Identify {
                a: given("a", a, 1)?,
                b: match b {
                    Some(b) => number("b", b)?,
                    None => Decimal::parse("0.5").expect("a decimal"),
                },
            }
        }
        (None, None, None) => {
            return Err(value_error(
                &["torus", "phase1", "phase2"],
                "need m and h (without them the whole motion is identified from the first row)",
            ))
        }
        _ => return Err(value_error(&["m", "h"], "give both or neither")),
    };
    let digits = match digits {
        None => None,
        Some(d) => Some(u32::try_from(d).map_err(|_| {
            value_error(&["digits"], format!("must be between 1 and 10000, got {d}"))
        })?),
    };
    let source = match (path(source), states) {
        (Some(file), None) => Source::File(file),
        (Some(_), Some(_)) => {
            return Err(value_error(
                &["states"],
                "a file holds the states: give the path alone",
            ))
        }
        (None, Some(states)) => {
            let t = arrays::vector(source, "times")?;
            check_times(&t).map_err(|e| value_error(&["times"], e))?;
            let x = arrays::state_rows(states, "states", t.len())?;
            Source::Arrays {
                times: t,
                states: Box::new(x),
                name: name.to_string(),
            }
        }
        (None, None) => {
            return Err(value_error(
                &["states"],
                format!(
                    "give a file path, or times and states; got {} alone",
                    arrays::describe(source)
                ),
            ))
        }
    };
    let request = CheckRequest {
        motion,
        source,
        digits,
        events: events.map(detected).transpose()?,
        expect: event_specs(expect, "expect")?,
        mcap: None,
        jobs: None,
        limits: Limits::default(),
    };
    let result = py.detach(move || {
        let mut watch = Watch(Interrupts::new());
        let result = rsts_flows::check::check(request, &mut watch);
        (result, watch.0.take())
    });
    let outcome = finish(result, None)?;
    report_dict(py, &outcome)
}
