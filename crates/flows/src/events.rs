//! `EventsRequest → events → EventsOutcome`: the exact times in (t_start, t_end] at which event
//! functions cross zero along the closed-form motion (docs/events.md), the document of
//! `rsts events` and of the Python package's `rsts.events`.
//!
//! The motion's decimals and the window's ends are exact at the working precision ([`working_bits`](rsts_closed_form::events::working_bits):
//! the digits asked plus 64 guard bits, f64 plus 64 without); each event's time and state are
//! computed there and rounded once, to f64 or to the digits asked. The document is streamed:
//! its head ([`EventCase`], the camera filled in) and then every event in time order go to a
//! [`Sink`].

use rsts_closed_form::events::EventsReport;
use rsts_closed_form::events::{EventCase, EventRecord, EventSpec, EventsRun};
use rsts_closed_form::{Decimal, Motion};
use serde::Serialize;

use crate::log::MAX_OUTPUT_BYTES;
use crate::sink::{Collect, Sink};
use crate::FlowError;

/// Digits an event report may carry (without: f64, correctly rounded).
pub const DIGITS: std::ops::RangeInclusive<u32> = 16..=10_000;

/// The events asked for along one motion.
#[derive(Clone, Debug, PartialEq)]
pub struct EventsRequest {
    pub motion: Motion,
    /// The event functions and the crossings asked for ([`event_specs`]).
    pub events: Vec<EventSpec>,
    /// The window (t_start, t_end].
    pub t_start: Decimal,
    pub t_end: Decimal,
    /// Digits of the times and states (`None`: f64, correctly rounded).
    pub digits: Option<u32>,
}

/// What an events run found: its head and how many events (each went to the sink).
#[derive(Clone, Debug, Serialize)]
pub struct EventsOutcome {
    pub case: EventCase,
    pub found: usize,
}

/// An event spec that cannot be read (`NAME[:up|down|both]`), or one asked for twice.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("'{spec}': {message}")]
pub struct SpecError {
    /// The spec as given.
    pub spec: String,
    pub message: String,
}

/// The event specs of `names` (`omega1`, `gamma3:down`, `s2:up`, …), each function at most once.
pub fn event_specs<S: AsRef<str>>(names: &[S]) -> Result<Vec<EventSpec>, SpecError> {
    let mut specs: Vec<EventSpec> = Vec::new();
    for s in names {
        let s = s.as_ref();
        let error = |message: String| SpecError {
            spec: rsts_io::cut(s),
            message,
        };
        let spec: EventSpec = s.parse().map_err(error)?;
        if specs.iter().any(|p| p.name == spec.name) {
            return Err(error(format!("{} is asked for twice", spec.name)));
        }
        specs.push(spec);
    }
    Ok(specs)
}

/// Check a request before anything is computed: events asked, digits in [`DIGITS`], a window
/// that is not empty.
fn check(request: &EventsRequest) -> Result<(), FlowError> {
    if request.events.is_empty() {
        return Err(FlowError::input(&["event"], "give at least one event"));
    }
    if let Some(d) = request.digits {
        if !DIGITS.contains(&d) {
            return Err(FlowError::input(
                &["digits"],
                format!(
                    "must be between {} and {}, got {d}",
                    DIGITS.start(),
                    DIGITS.end()
                ),
            ));
        }
    }
    if crate::times::cmp(&request.t_end, &request.t_start) != std::cmp::Ordering::Greater {
        return Err(FlowError::input(
            &["t-start", "t-end"],
            format!(
                "the window (t_start, t_end] = ({}, {}] is empty: need t_end > t_start",
                shown(&request.t_start),
                shown(&request.t_end)
            ),
        ));
    }
    Ok(())
}

fn shown(d: &Decimal) -> String {
    rsts_dynamics::number::shorten(d.as_str())
}

/// The exact events of the request: the head ([`EventCase`] with the camera) to `sink`, then
/// every event in time order (events at one time in the order asked). Bad input is refused
/// before anything goes to the sink.
pub fn events<S: Sink<EventCase, EventRecord>>(
    request: &EventsRequest,
    sink: &mut S,
) -> Result<EventsOutcome, S::Error> {
    check(request)?;
    let case = EventCase {
        motion: request.motion.clone(),
        t_start: request.t_start.clone(),
        t_end: request.t_end.clone(),
        digits: request.digits,
        camera: String::new(),
    };
    // The motion is built and the window checked; the output is sized before any event is
    // computed, then the events go to the sink as they are found (memory does not grow with
    // the window).
    let run = EventsRun::new(case, &request.events).map_err(search_error)?;
    let bytes = run.most_bytes();
    if bytes > MAX_OUTPUT_BYTES {
        return Err(FlowError::input(
            &["t-end", "event", "digits"],
            format!(
                "the events would take about {} bytes, more than the {} bytes (2 GiB) one output file may have; ask for less",
                rsts_dynamics::short(bytes),
                rsts_dynamics::short(MAX_OUTPUT_BYTES)
            ),
        )
        .into());
    }
    sink.head(run.case())?;
    let mut found = 0usize;
    run.for_each(|e| {
        found += 1;
        sink.row(e).map_err(Stop::Sink)
    })
    .map_err(|s| match s {
        Stop::Search(e) => search_error(e).into(),
        Stop::Sink(e) => e,
    })?;
    Ok(EventsOutcome {
        case: run.case().clone(),
        found,
    })
}

/// An error of the search (its option named by the harness's mapping).
fn search_error(e: rsts_closed_form::ClosedFormError) -> FlowError {
    FlowError::from(rsts_harness::HarnessError::from(e))
}

/// What stops the events being handed on: the search or the sink.
enum Stop<E> {
    Search(rsts_closed_form::ClosedFormError),
    Sink(E),
}

impl<E> From<rsts_closed_form::ClosedFormError> for Stop<E> {
    fn from(e: rsts_closed_form::ClosedFormError) -> Self {
        Stop::Search(e)
    }
}

/// The whole document of [`events`] in memory (`{"case", "events"}`): the Python face's dict.
pub fn events_report(request: &EventsRequest) -> Result<EventsReport, FlowError> {
    let mut all = Collect::default();
    let outcome = events(request, &mut all)?;
    Ok(EventsReport {
        case: outcome.case,
        events: all.rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(motion: Motion, names: &[&str], t_end: &str, digits: Option<u32>) -> EventsRequest {
        EventsRequest {
            motion,
            events: event_specs(names).unwrap(),
            t_start: Decimal::from_integer(0),
            t_end: Decimal::parse(t_end).unwrap(),
            digits,
        }
    }

    #[test]
    fn specs_are_read_once_each() {
        assert_eq!(event_specs(&["omega1", "s2:up"]).unwrap().len(), 2);
        let e = event_specs(&["s1", "s1:up"]).unwrap_err();
        assert_eq!(e.to_string(), "'s1:up': s1 is asked for twice");
        let e = event_specs(&["omega4"]).unwrap_err();
        assert!(e.message.starts_with("unknown event 'omega4'"), "{e}");
        assert!(event_specs(&["omega1:sideways"])
            .unwrap_err()
            .message
            .contains("unknown direction"));
    }

    #[test]
    fn bad_requests_name_their_inputs_and_write_nothing() {
        let m = Motion::default_i_plus();
        let mut sink = Collect::default();
        let names =
            |r: &EventsRequest, sink: &mut Collect<_, _>| events(r, sink).unwrap_err().names();
        assert_eq!(
            names(&request(m.clone(), &["s1"], "-1", None), &mut sink),
            ["t-start", "t-end"]
        );
        assert_eq!(
            names(&request(m.clone(), &["s1"], "1", Some(3)), &mut sink),
            ["digits"]
        );
        assert_eq!(
            names(&request(m.clone(), &[], "1", None), &mut sink),
            ["event"]
        );
        let mut off = m.clone();
        off.h = Decimal::parse("-5").unwrap();
        assert_eq!(
            names(&request(off, &["s1"], "1", None), &mut sink),
            ["m", "h"]
        );
        assert_eq!(
            names(&request(m, &["omega1"], "1e9", None), &mut sink),
            ["t-end"]
        );
        assert!(sink.head.is_none() && sink.rows.is_empty());
    }

    #[test]
    fn the_events_are_in_time_order_and_in_the_window() {
        let r = request(
            Motion::default_i_plus(),
            &["omega1", "s2", "gamma3"],
            "20",
            None,
        );
        let doc = events_report(&r).unwrap();
        assert_eq!(doc.case.camera, "I+");
        assert!(doc.events.len() >= 4, "{}", doc.events.len());
        let t: Vec<f64> = doc.events.iter().map(|e| e.t.to_f64()).collect();
        assert!(t.windows(2).all(|w| w[0] <= w[1]), "{t:?}");
        assert!(t[0] > 0.0 && *t.last().unwrap() <= 20.0);
    }
}
