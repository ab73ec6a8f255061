//! The serialisable report of `rsts events` (and of the Python package): the case and every
//! exact event with its state, numbers as f64 or, at `digits`, as decimal strings.

use rug::Float;
use serde::Serialize;

use super::{working_bits, Crossing, EventSearch, EventSpec, ExactEvent};
use crate::error::ClosedFormError;
use crate::motion::{ExplicitMotion, Motion};
use rsts_dynamics::number::Decimal;
use rsts_dynamics::Real;

/// A number of the report: f64 (correctly rounded from the working precision) or a decimal
/// string of `digits` significant digits.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[serde(untagged)]
pub enum Number {
    F64(f64),
    Decimal(String),
}

impl Number {
    /// `x` correctly rounded to f64 (`digits` `None`) or written to `digits` significant digits.
    pub fn of(x: &Float, digits: Option<u32>) -> Self {
        match digits {
            None => Number::F64(x.to_f64()),
            Some(d) => Number::Decimal(x.to_decimal(d)),
        }
    }
    /// The value as f64 (for tables and matching).
    pub fn to_f64(&self) -> f64 {
        match self {
            Number::F64(x) => *x,
            Number::Decimal(s) => s.parse().unwrap_or(f64::NAN),
        }
    }
}

/// The motion and the window (its ends decimals as written, exact at every precision; in the
/// report their nearest f64).
#[derive(Clone, Debug, Serialize)]
pub struct EventCase {
    #[serde(flatten)]
    pub motion: Motion,
    pub t_start: Decimal,
    pub t_end: Decimal,
    /// Decimal digits of the times and states (`None`: f64).
    pub digits: Option<u32>,
    /// The camera of (m, h) (filled in by [`events_report`]).
    pub camera: String,
}

/// (ω, α, β) at an event.
#[derive(Clone, Debug, Serialize)]
pub struct EventState {
    pub omega: [Number; 3],
    pub alpha: [Number; 3],
    pub beta: [Number; 3],
}

/// One event of the report.
#[derive(Clone, Debug, Serialize)]
pub struct EventRecord {
    pub name: String,
    pub t: Number,
    pub direction: Crossing,
    pub state: EventState,
}

/// `{"case", "events": [...]}`.
#[derive(Clone, Debug, Serialize)]
pub struct EventsReport {
    pub case: EventCase,
    pub events: Vec<EventRecord>,
}

impl EventRecord {
    /// The record of an exact event: its time and state rounded to f64 (`digits` `None`) or
    /// written to `digits` digits.
    pub fn new(e: &ExactEvent, digits: Option<u32>) -> Self {
        let v = |o: usize| std::array::from_fn(|i| Number::of(&e.state[o + i], digits));
        EventRecord {
            name: e.name.as_str().to_string(),
            t: Number::of(&e.t, digits),
            direction: e.direction,
            state: EventState {
                omega: v(0),
                alpha: v(3),
                beta: v(6),
            },
        }
    }
}

/// The exact events of `specs` along the motion of `case` in (t_start, t_end], at `case.digits`
/// digits (plus guard bits) or correctly rounded to f64.
pub fn events_report(
    case: EventCase,
    specs: &[EventSpec],
) -> Result<EventsReport, ClosedFormError> {
    let run = EventsRun::new(case, specs)?;
    let mut events = Vec::new();
    run.for_each(|e| {
        events.push(e);
        Ok::<(), ClosedFormError>(())
    })?;
    Ok(EventsReport {
        case: run.case,
        events,
    })
}

/// Bytes one event takes in any output of `rsts events` (CSV, JSON, table) at `digits` (`None`:
/// f64): ten numbers of the digits and up to 24 characters of sign, point, exponent, key and
/// separator each, and 200 of name, direction and layout. An honest bound, a little generous.
pub fn bytes_per_event(digits: Option<u32>) -> u64 {
    10 * (u64::from(digits.unwrap_or(17)) + 24) + 200
}

/// The events of one case, ready to be found piece by piece ([`EventSearch`]): the motion is
/// built and the window checked by [`EventsRun::new`]; [`EventsRun::most_events`] says how many
/// events there may be before any is computed; [`EventsRun::for_each`] hands them on in time
/// order as they are found (memory does not grow with the window).
pub struct EventsRun {
    case: EventCase,
    motion: ExplicitMotion<Float>,
    search: EventSearch,
}

impl EventsRun {
    /// The motion of `case` at its digits and the search of `specs` in its window, checked.
    pub fn new(mut case: EventCase, specs: &[EventSpec]) -> Result<Self, ClosedFormError> {
        let bits = working_bits(case.digits);
        let t_max = case.t_start.to_f64().abs().max(case.t_end.to_f64().abs());
        let motion = case.motion.explicit::<Float>(bits, t_max)?;
        case.camera = motion.camera.label().to_string();
        let (t0, t1) = (case.t_start.to_float(bits), case.t_end.to_float(bits));
        let search = EventSearch::new(&motion, specs, &t0, &t1)?;
        Ok(Self {
            case,
            motion,
            search,
        })
    }

    /// The case, its camera filled in.
    pub fn case(&self) -> &EventCase {
        &self.case
    }

    /// The most events the run may find ([`EventSearch::most_events`]; it stops past it).
    pub fn most_events(&self) -> f64 {
        self.search.most_events()
    }

    /// The most bytes the events take in an output: [`EventsRun::most_events`] ×
    /// [`bytes_per_event`].
    pub fn most_bytes(&self) -> f64 {
        self.most_events() * bytes_per_event(self.case.digits) as f64
    }

    /// Every event in time order, handed to `sink` as found.
    pub fn for_each<E: From<ClosedFormError>>(
        &self,
        mut sink: impl FnMut(EventRecord) -> Result<(), E>,
    ) -> Result<(), E> {
        let digits = self.case.digits;
        self.search
            .for_each(&self.motion, |e| sink(EventRecord::new(&e, digits)))
    }
}
