//! Events an integrator detected, read from a file (`rsts check --events`): CSV with the
//! columns `name` and `t` (any order, others ignored: the CSV of `rsts events` is read as it is)
//! or JSON `{"events": [{"name", "t"}]}`.
//!
//! Bounded before and while reading: at most [`MAX_DETECTED_BYTES`] of input (a larger file is
//! refused from its size, a device or FIFO where it passes the bound), lines of at most
//! [`MAX_DETECTED_LINE_BYTES`], at most [`MAX_DETECTED_EVENTS`] events. The input is read as a
//! stream (CSV line by line, JSON by a parser that keeps only each event's name and time), so
//! memory is that of the events kept, 16 bytes each.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use rsts_io::cut;

use rsts_closed_form::events::{EventName, EVENT_NAMES};
use serde::de::{self, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

use crate::events::DetectedEvent;

/// Largest events file (bytes): what `rsts events` may write (2 GiB, one output file), read as
/// it is. Memory does not grow with it (the file is streamed), only with the events kept.
pub const MAX_DETECTED_BYTES: u64 = 2 << 30;
/// Longest line of an events CSV (a line of `rsts events --digits 10000` takes 100 kB).
pub const MAX_DETECTED_LINE_BYTES: u64 = 1 << 20;
/// Most events one file may list.
pub const MAX_DETECTED_EVENTS: usize = 1_000_000;

/// The events found so far, each checked as it comes: a known name, a finite time, not more
/// than [`MAX_DETECTED_EVENTS`]. Any order: [`Found::sorted`] puts them in time order (scipy's
/// `t_events` comes grouped by event).
#[derive(Default)]
struct Found(Vec<DetectedEvent>);

impl Found {
    fn push(&mut self, place: &str, name: &str, t: Option<f64>) -> Result<(), String> {
        let name = EventName::parse(name.trim()).ok_or_else(|| {
            format!(
                "{place}: unknown event '{}' (known: {})",
                cut(name.trim()),
                EVENT_NAMES.join(", ")
            )
        })?;
        let t = t.ok_or_else(|| format!("{place}: no \"t\" number"))?;
        if !t.is_finite() {
            return Err(format!("{place}: the time is not a finite number"));
        }
        if self.0.len() >= MAX_DETECTED_EVENTS {
            return Err(format!(
                "{place}: more than {MAX_DETECTED_EVENTS} events, the most one file may list"
            ));
        }
        self.0.push(DetectedEvent { name, t });
        Ok(())
    }

    /// The events in time order (a stable sort: events at the same time keep the file's order).
    fn sorted(mut self) -> Vec<DetectedEvent> {
        self.0.sort_by(|a, b| a.t.total_cmp(&b.t));
        self.0
    }
}

/// Detected events from a file's text ([`read_detected`] of text in memory). Errors name the
/// line (CSV) or the entry (JSON): unknown names, times that are not finite numbers. The events
/// may come in any order; they are returned in time order.
pub fn parse_detected(text: &str) -> Result<Vec<DetectedEvent>, String> {
    detected_from(text.as_bytes())
}

/// Detected events from the file `path`, read as a stream within the bounds of the module doc.
/// The error does not name the path.
pub fn read_detected(path: &Path) -> Result<Vec<DetectedEvent>, String> {
    let input = rsts_io::open_bounded(path, MAX_DETECTED_BYTES, "an events file")
        .map_err(|e| format!("cannot read: {e}"))?;
    detected_from(input)
}

/// [`read_detected`] from any input.
fn detected_from(input: impl Read) -> Result<Vec<DetectedEvent>, String> {
    let mut input = BufReader::new(input);
    // JSON when the first character that is not white space is `{`.
    let json = loop {
        let buf = input.fill_buf().map_err(|e| format!("cannot read: {e}"))?;
        if buf.is_empty() {
            break false;
        }
        match buf.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(k) => break buf[k] == b'{',
            None => {
                let n = buf.len();
                input.consume(n);
            }
        }
    };
    if json {
        read_json(input)
    } else {
        read_csv(input)
    }
}

fn read_csv(mut input: impl BufRead) -> Result<Vec<DetectedEvent>, String> {
    let missing = "expected a header with the columns name and t";
    let mut found = Found::default();
    let mut columns: Option<(usize, usize)> = None;
    let mut buf = Vec::new();
    let mut k = 0;
    loop {
        buf.clear();
        let n = input
            .by_ref()
            .take(MAX_DETECTED_LINE_BYTES + 1)
            .read_until(b'\n', &mut buf)
            .map_err(|e| format!("cannot read: {e}"))?;
        if n == 0 {
            break;
        }
        k += 1;
        if n as u64 > MAX_DETECTED_LINE_BYTES {
            return Err(format!(
                "line {k}: longer than {MAX_DETECTED_LINE_BYTES} bytes (1 MiB), the longest line \
                 an events file may have"
            ));
        }
        let line = std::str::from_utf8(&buf)
            .map_err(|e| format!("line {k}: not UTF-8 text (byte {})", e.valid_up_to() + 1))?;
        if line.trim().is_empty() {
            continue;
        }
        let Some((ni, ti)) = columns else {
            // The columns `name` and `t`, in any order.
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            let at = |c: &str| cols.iter().position(|x| *x == c);
            match (at("name"), at("t")) {
                (Some(n), Some(t)) => columns = Some((n, t)),
                _ => return Err(format!("line {k}: {missing}")),
            }
            continue;
        };
        let place = format!("line {k}");
        let line = line.trim_end_matches(['\n', '\r']);
        let cols: Vec<&str> = line.split(',').collect();
        let (Some(name), Some(t)) = (cols.get(ni), cols.get(ti)) else {
            return Err(format!("{place}: expected the columns name and t"));
        };
        let t: f64 = t
            .trim()
            .parse()
            .map_err(|_| format!("{place}: '{}' is not a number", cut(t.trim())))?;
        found.push(&place, name, Some(t))?;
    }
    if columns.is_none() {
        return Err(format!("empty file: {missing}"));
    }
    Ok(found.sorted())
}

/// The JSON document, parsed as a stream: only `events` is read, each entry's `name` and `t`
/// kept; everything else is skipped without being held.
fn read_json(input: impl Read) -> Result<Vec<DetectedEvent>, String> {
    let mut found = Found::default();
    let mut ours: Option<String> = None;
    let mut de = serde_json::Deserializer::from_reader(input);
    let seen = de.deserialize_map(DocVisitor {
        found: &mut found,
        ours: &mut ours,
    });
    let seen = match (seen, ours) {
        (_, Some(message)) => return Err(message),
        (Err(e), None) => return Err(format!("invalid JSON: {e}")),
        (Ok(seen), None) => seen,
    };
    de.end().map_err(|e| format!("invalid JSON: {e}"))?;
    if !seen {
        return Err("JSON without an \"events\" array".into());
    }
    Ok(found.sorted())
}

/// The top-level object: true when it had an `events` array.
struct DocVisitor<'a> {
    found: &'a mut Found,
    /// A message of ours (the parser's error only stops the parse).
    ours: &'a mut Option<String>,
}

impl<'de> Visitor<'de> for DocVisitor<'_> {
    type Value = bool;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an object with an \"events\" array")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<bool, A::Error> {
        let mut seen = false;
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            if key == "events" {
                if seen {
                    // A second list replaces the first, as a JSON object's last key does.
                    *self.found = Found::default();
                }
                seen = map.next_value_seed(ListSeed {
                    found: self.found,
                    ours: self.ours,
                })?;
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(seen)
    }
}

/// The `events` value: true when it is an array (its entries pushed one by one).
struct ListSeed<'a> {
    found: &'a mut Found,
    ours: &'a mut Option<String>,
}

impl<'de> de::DeserializeSeed<'de> for ListSeed<'_> {
    type Value = bool;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<bool, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for ListSeed<'_> {
    type Value = bool;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an array of events")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<bool, A::Error> {
        let mut i = 0usize;
        while let Some(entry) = seq.next_element::<Entry>()? {
            let place = format!("events[{i}]");
            let result = match &entry.name {
                Some(name) => self.found.push(&place, name, entry.t),
                None => Err(format!("{place}: no \"name\" string")),
            };
            if let Err(e) = result {
                *self.ours = Some(e);
                return Err(de::Error::custom("stopped"));
            }
            i += 1;
        }
        Ok(true)
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<bool, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(false)
    }
    fn visit_bool<E>(self, _: bool) -> Result<bool, E> {
        Ok(false)
    }
    fn visit_i64<E>(self, _: i64) -> Result<bool, E> {
        Ok(false)
    }
    fn visit_u64<E>(self, _: u64) -> Result<bool, E> {
        Ok(false)
    }
    fn visit_f64<E>(self, _: f64) -> Result<bool, E> {
        Ok(false)
    }
    fn visit_str<E>(self, _: &str) -> Result<bool, E> {
        Ok(false)
    }
    fn visit_unit<E>(self) -> Result<bool, E> {
        Ok(false)
    }
}

/// One entry: its `name` when a string, its `t` when a number or a decimal string; anything
/// else in it is skipped.
#[derive(Default)]
struct Entry {
    name: Option<String>,
    t: Option<f64>,
}

impl<'de> de::Deserialize<'de> for Entry {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(EntryVisitor)
    }
}

struct EntryVisitor;

impl<'de> Visitor<'de> for EntryVisitor {
    type Value = Entry;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an event {\"name\", \"t\"}")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Entry, A::Error> {
        let mut e = Entry::default();
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            match key.as_ref() {
                "name" => e.name = map.next_value::<Scalar>()?.text,
                "t" => {
                    let s = map.next_value::<Scalar>()?;
                    e.t = s
                        .number
                        .or_else(|| s.text.and_then(|t| t.trim().parse().ok()));
                }
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(e)
    }
    // Not an object: an entry without name or time.
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Entry, A::Error> {
        while seq.next_element::<IgnoredAny>()?.is_some() {}
        Ok(Entry::default())
    }
    fn visit_bool<E>(self, _: bool) -> Result<Entry, E> {
        Ok(Entry::default())
    }
    fn visit_i64<E>(self, _: i64) -> Result<Entry, E> {
        Ok(Entry::default())
    }
    fn visit_u64<E>(self, _: u64) -> Result<Entry, E> {
        Ok(Entry::default())
    }
    fn visit_f64<E>(self, _: f64) -> Result<Entry, E> {
        Ok(Entry::default())
    }
    fn visit_str<E>(self, _: &str) -> Result<Entry, E> {
        Ok(Entry::default())
    }
    fn visit_unit<E>(self) -> Result<Entry, E> {
        Ok(Entry::default())
    }
}

/// A JSON value kept only when it is a string (its first 10 kB) or a number; arrays and
/// objects are skipped.
#[derive(Default)]
struct Scalar {
    text: Option<String>,
    number: Option<f64>,
}

impl<'de> de::Deserialize<'de> for Scalar {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ScalarVisitor)
    }
}

struct ScalarVisitor;

impl<'de> Visitor<'de> for ScalarVisitor {
    type Value = Scalar;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_str<E>(self, s: &str) -> Result<Scalar, E> {
        let kept = match s.char_indices().nth(10_000) {
            Some((k, _)) => &s[..k],
            None => s,
        };
        Ok(Scalar {
            text: Some(kept.to_string()),
            number: None,
        })
    }
    fn visit_f64<E>(self, x: f64) -> Result<Scalar, E> {
        Ok(Scalar {
            text: None,
            number: Some(x),
        })
    }
    fn visit_i64<E: de::Error>(self, x: i64) -> Result<Scalar, E> {
        self.visit_f64(x as f64)
    }
    fn visit_u64<E: de::Error>(self, x: u64) -> Result<Scalar, E> {
        self.visit_f64(x as f64)
    }
    fn visit_bool<E>(self, _: bool) -> Result<Scalar, E> {
        Ok(Scalar::default())
    }
    fn visit_unit<E>(self) -> Result<Scalar, E> {
        Ok(Scalar::default())
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Scalar, A::Error> {
        while seq.next_element::<IgnoredAny>()?.is_some() {}
        Ok(Scalar::default())
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Scalar, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(Scalar::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(name: &str, t: f64) -> DetectedEvent {
        DetectedEvent {
            name: EventName::parse(name).unwrap(),
            t,
        }
    }

    /// The JSON reader keeps the old reading: last `events` key wins, other keys and an
    /// entry's other fields skipped, times as numbers or decimal strings.
    #[test]
    fn json_is_read_as_a_stream_with_the_same_meaning() {
        let doc = r#" {"x": [1, {"y": [2]}], "events": [{"name": "s1", "t": "0.5", "z": {}},
            {"t": 0.75, "name": "omega2"}], "after": null}"#;
        assert_eq!(
            parse_detected(doc).unwrap(),
            vec![ev("s1", 0.5), ev("omega2", 0.75)]
        );
        let e = parse_detected(r#"{"events": [{"t": 1}]}"#).unwrap_err();
        assert_eq!(e, "events[0]: no \"name\" string");
        let e = parse_detected(r#"{"events": [{"name": "s1"}]}"#).unwrap_err();
        assert_eq!(e, "events[0]: no \"t\" number");
        let e = parse_detected(r#"{"events": {"name": "s1"}}"#).unwrap_err();
        assert_eq!(e, "JSON without an \"events\" array");
        let e = parse_detected(r#"{"events": [] "#).unwrap_err();
        assert!(e.starts_with("invalid JSON"), "{e}");
        let e = parse_detected(r#"{"events": []} x"#).unwrap_err();
        assert!(e.starts_with("invalid JSON"), "{e}");
    }

    /// Events in any order (scipy's `t_events` grouped by event) are read and sorted by time
    /// (old: "line 3: t = 0.5 is before the previous event's t = 1e300; list events in time
    /// order"), in CSV and JSON alike.
    #[test]
    fn events_in_any_order_are_sorted() {
        let csv = parse_detected("name,t\nomega1,3\nomega1,7\nalpha3,1\nalpha3,5\n").unwrap();
        let json = parse_detected(
            r#"{"events": [{"name": "omega1", "t": 3}, {"name": "omega1", "t": 7},
                           {"name": "alpha3", "t": 1}, {"name": "alpha3", "t": 5}]}"#,
        )
        .unwrap();
        for found in [csv, json] {
            let order: Vec<(String, f64)> =
                found.iter().map(|e| (e.name.to_string(), e.t)).collect();
            assert_eq!(
                order,
                vec![
                    ("alpha3".to_string(), 1.0),
                    ("omega1".to_string(), 3.0),
                    ("alpha3".to_string(), 5.0),
                    ("omega1".to_string(), 7.0)
                ]
            );
        }
    }

    /// Long values are cut in messages and numbers printed short.
    #[test]
    fn messages_cut_long_values() {
        let long = "9".repeat(5000);
        let e = parse_detected(&format!("name,t\nomega1,{long}x\n")).unwrap_err();
        assert!(e.len() < 200 && e.contains("(5001 characters)"), "{e}");
        let e = parse_detected(&format!("name,t\n{long},1\n")).unwrap_err();
        assert!(e.len() < 400, "{e}");
    }

    /// Lines and counts are bounded; a longer input stops at its bound.
    #[test]
    fn lines_and_counts_are_bounded() {
        let line = "x".repeat(MAX_DETECTED_LINE_BYTES as usize + 10);
        let e = parse_detected(&format!("name,t\n{line}\n")).unwrap_err();
        assert!(e.starts_with("line 2: longer than"), "{e}");
        let zeros = std::io::repeat(0).take(10 << 20);
        let e = detected_from(rsts_io::Bounded::new(zeros, 1 << 20, "an events file")).unwrap_err();
        assert!(
            e.contains("longer than") || e.contains("larger than"),
            "{e}"
        );
    }
}
