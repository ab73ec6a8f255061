//! The `/events` channels of a compare log (docs/events.md, docs/mcap.md): exact and detected
//! events as `foxglove.Log` lines (the Log panel lists them, the seek bar jumps to them) and as
//! `rsts.EventMarker` numbers on `/events/markers` (markers in a Plot panel).

use std::collections::BTreeMap;

use serde_json::{json, Value};

use crate::topics;
use crate::writer::{stamp, time_to_ns, LogError, TrajectoryLog};

/// One event of a comparison: matched (both times), missed (no detected time) or spurious (no
/// exact time).
#[derive(Clone, Debug, PartialEq)]
pub struct EventMark {
    pub name: String,
    pub t_exact: Option<f64>,
    pub t_detected: Option<f64>,
    pub time_error: Option<f64>,
}

/// JSON Schema of `foxglove.Log` (the fields of `@foxglove/schemas` Log).
const LOG_SCHEMA: &str = r#"{"title":"foxglove.Log","description":"A log message","type":"object","properties":{"timestamp":{"type":"object","title":"time","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}}},"level":{"title":"foxglove.LogLevel","description":"Log level","oneOf":[{"title":"UNKNOWN","const":0},{"title":"DEBUG","const":1},{"title":"INFO","const":2},{"title":"WARNING","const":3},{"title":"ERROR","const":4},{"title":"FATAL","const":5}]},"message":{"type":"string"},"name":{"type":"string"},"file":{"type":"string"},"line":{"type":"integer","minimum":0}},"required":["timestamp","level","message","name","file","line"]}"#;

/// JSON Schema of `rsts.EventMarker`.
const MARKER_SCHEMA: &str = r#"{"title":"rsts.EventMarker","type":"object","properties":{"name":{"type":"string"},"exact":{"type":"number","description":"1 at an exact event, 0 at a spurious detection"},"detected":{"type":"number","description":"1 when detected, 0 when missed"},"time_error":{"type":"number","description":"|t_detected - t_exact| of a matched event, else -1"},"log10_time_error":{"type":"number"}},"required":["name","exact","detected","time_error","log10_time_error"]}"#;

impl TrajectoryLog {
    /// Logs the events of a comparison (any order of times; each at its exact time, a spurious
    /// one at its detected time): `foxglove.Log` on `/events` (INFO matched, WARNING missed or
    /// spurious) and `rsts.EventMarker` on `/events/markers`.
    pub fn log_events(&mut self, events: &[EventMark]) -> Result<(), LogError> {
        let w = self.writer.as_mut().ok_or(LogError::Finished)?;
        let none = BTreeMap::new();
        let added = (|| {
            let log_s = w.add_schema("foxglove.Log", "jsonschema", LOG_SCHEMA.as_bytes())?;
            let mk_s = w.add_schema("rsts.EventMarker", "jsonschema", MARKER_SCHEMA.as_bytes())?;
            let log_c = w.add_channel(log_s, topics::EVENTS, "json", &none)?;
            let mk_c = w.add_channel(mk_s, topics::EVENT_MARKERS, "json", &none)?;
            Ok::<_, mcap::McapError>((log_c, mk_c))
        })();
        let (log_c, mk_c) = added.map_err(|e| self.fail(e.into()))?;
        let mut sorted: Vec<&EventMark> = events.iter().collect();
        let at = |e: &EventMark| e.t_exact.or(e.t_detected).unwrap_or(0.0);
        sorted.sort_by(|p, q| at(p).total_cmp(&at(q)));
        for e in sorted {
            let ns = time_to_ns(at(e))?;
            let (level, message) = match (e.t_exact, e.t_detected) {
                (Some(x), Some(d)) => (
                    2,
                    format!(
                        "{} at t = {x} (exact), detected at {d}: time error {:.3e}",
                        e.name,
                        e.time_error.unwrap_or(f64::NAN)
                    ),
                ),
                (Some(x), None) => (3, format!("{} at t = {x} (exact): MISSED", e.name)),
                (None, Some(d)) => (
                    3,
                    format!("{} detected at t = {d}: SPURIOUS (no exact event)", e.name),
                ),
                (None, None) => continue,
            };
            let log = json!({"timestamp": stamp(ns), "level": level, "message": message,
                             "name": e.name, "file": "", "line": 0});
            self.write_json(log_c, ns, &log)?;
            let err = e.time_error.unwrap_or(-1.0);
            let marker: Value = json!({
                "name": e.name,
                "exact": if e.t_exact.is_some() { 1.0 } else { 0.0 },
                "detected": if e.t_detected.is_some() { 1.0 } else { 0.0 },
                "time_error": err,
                "log10_time_error": if err > 0.0 { err.log10() } else { -20.0 },
            });
            self.write_json(mk_c, ns, &marker)?;
        }
        Ok(())
    }
}
