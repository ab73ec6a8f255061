//! `rsts.events`: exact event times along a motion of N (`rsts events --format json`, the same
//! flow, [`rsts_flows::events`]).

use pyo3::prelude::*;

use rsts_closed_form::events::{EventCase, EventRecord, EventsReport};
use rsts_flows::events::{event_specs, events as events_flow, EventsRequest};
use rsts_flows::{Decimal, FlowError, Sink};

use crate::case::{digits_arg, int, number, Case, Int};
use crate::{flow_error, report_dict, value_error, Interrupts};

/// The exact times in (t_start, t_end] at which the event functions `names` cross zero along the
/// motion of `case` (default: `Case.default()`): a dict with the keys of `rsts events --format
/// json` — case, events: [{name, t, direction, state: {omega, alpha, beta}}]. Names as in the
/// CLI: "omega1".."beta3", "gamma1".."gamma3", "s1", "s2", each optionally with ":up", ":down"
/// or ":both", each function once. t_start and t_end are numbers as in `Case`: a str is the
/// decimal it holds, a float its exact binary value. With `digits` (16 to 10000), times and
/// states are decimal strings of that many digits; without, floats correctly rounded. Bad input
/// (an unknown name, an empty window, a motion that does not exist) raises ValueError. See
/// docs/events.md. The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt (seen
/// between events).
#[pyfunction]
#[pyo3(signature = (names, case = None, t_start = None, t_end = None, digits = None))]
pub fn events<'py>(
    py: Python<'py>,
    names: Vec<String>,
    case: Option<Case>,
    t_start: Option<&Bound<'py, PyAny>>,
    t_end: Option<&Bound<'py, PyAny>>,
    digits: Option<Int>,
) -> PyResult<Bound<'py, PyAny>> {
    let digits = int("digits", digits)?;
    let case = Case::or_default(case)?;
    let events = event_specs(&names).map_err(|e| value_error(&["names"], e.message))?;
    let end = |name, x: Option<&Bound<'py, PyAny>>, default: i64| match x {
        Some(x) => number(name, x),
        None => Ok(Decimal::from_integer(default)),
    };
    let digits = digits_arg(digits, rsts_flows::events::DIGITS)?;
    let request = EventsRequest {
        motion: case.motion.clone(),
        events,
        t_start: end("t_start", t_start, 0)?,
        t_end: end("t_end", t_end, 10)?,
        digits,
    };
    let found = py.detach(move || {
        let mut sink = Found {
            interrupts: Interrupts::new(),
            events: Vec::new(),
        };
        events_flow(&request, &mut sink).map(|outcome| EventsReport {
            case: outcome.case,
            events: sink.events,
        })
    });
    let report = match found {
        Ok(report) => report,
        Err(Stop::Flow(e)) => return Err(flow_error(e)),
        Err(Stop::Interrupted(e)) => return Err(e),
    };
    report_dict(py, &report)
}

/// The events as they are found; Ctrl-C stops the search.
struct Found {
    interrupts: Interrupts,
    events: Vec<EventRecord>,
}

/// Why the events could not be found.
enum Stop {
    Flow(FlowError),
    Interrupted(PyErr),
}

impl From<FlowError> for Stop {
    fn from(e: FlowError) -> Self {
        Stop::Flow(e)
    }
}

impl Sink<EventCase, EventRecord> for Found {
    type Error = Stop;
    fn head(&mut self, _: &EventCase) -> Result<(), Stop> {
        Ok(())
    }
    fn row(&mut self, event: EventRecord) -> Result<(), Stop> {
        if self.interrupts.stopped() {
            if let Some(e) = self.interrupts.take() {
                return Err(Stop::Interrupted(e));
            }
        }
        self.events.push(event);
        Ok(())
    }
}
