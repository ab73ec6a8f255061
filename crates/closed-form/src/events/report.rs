//! The serialisable report of `rsts events` (and of the Python package): the case and every
//! exact event with its state, numbers as f64 or, at `digits`, as decimal strings.

use rug::Float;
use serde::Serialize;

use super::{exact_events, working_bits, Crossing, EventSpec, ExactEvent};
use crate::error::ClosedFormError;
use crate::motion::Motion;
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
    mut case: EventCase,
    specs: &[EventSpec],
) -> Result<EventsReport, ClosedFormError> {
    let bits = working_bits(case.digits);
    let t_max = case.t_start.to_f64().abs().max(case.t_end.to_f64().abs());
    let motion = case.motion.explicit::<Float>(bits, t_max)?;
    case.camera = motion.camera.label().to_string();
    let (t0, t1) = (case.t_start.to_float(bits), case.t_end.to_float(bits));
    let events = exact_events(&motion, specs, &t0, &t1)?;
    Ok(EventsReport {
        events: events
            .iter()
            .map(|e| EventRecord::new(e, case.digits))
            .collect(),
        case,
    })
}
