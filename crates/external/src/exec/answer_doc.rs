//! A JSON answer read as a stream (no tree of the whole document): the samples go straight into
//! a [`RawTrajectory`] as they are parsed, the other keys rsts reads are kept as small values,
//! and everything else is skipped without being held. Memory is that of what is kept — the
//! samples asked for (and at most [`MAX_DENSE_ANSWER_SAMPLES`] dense ones) — not a multiple of
//! the answer: a `serde_json::Value` of `[0, 0, …]` takes 16 times its text.
//!
//! Errors of the values are recorded, not raised, so that they are reported in the order of the
//! reading of a whole document ([`super::Exec::parse_answer`]): JSON syntax first, then each
//! key; within a list, its first bad element.

use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value;

use crate::dense::MAX_DENSE_ANSWER_SAMPLES;
use crate::samples::{check_component, check_f64, check_text, Number, RawTrajectory};

/// Most events an answer may list.
pub const MAX_ANSWER_EVENTS: usize = 1_000_000;

/// A list of samples as read: the first `keep` kept, all counted, the first error recorded.
#[derive(Debug, Default)]
pub(crate) struct SampleList {
    pub raw: RawTrajectory,
    /// Elements in the list (also those not kept).
    pub count: usize,
    /// The first error: the list is not an array, or its first bad sample.
    pub error: Option<String>,
}

/// The keys of an answer rsts reads.
#[derive(Debug, Default)]
pub(crate) struct AnswerDoc {
    pub name: Option<Value>,
    pub digits: Option<Value>,
    pub version: Option<Value>,
    /// `stats` as an object of small values (not an object: an empty array); its `step_times`
    /// holds at most [`MAX_DENSE_ANSWER_SAMPLES`] + 2 times, `step_times_count` counts them all.
    pub stats: Option<Value>,
    pub step_times_count: usize,
    /// `events` as (name, t) pairs, or the first error.
    pub events: Option<Result<Vec<(String, f64)>, String>>,
    pub samples: Option<SampleList>,
    pub dense: Option<SampleList>,
}

impl AnswerDoc {
    /// Read a JSON answer (or a JSON trajectory file, which has the same `samples` and `stats`)
    /// whose `samples` keep at most `keep` samples. A document that is not an object has none of
    /// the keys.
    pub fn read(bytes: &[u8], keep: usize) -> Result<Self, serde_json::Error> {
        let mut de = serde_json::Deserializer::from_slice(bytes);
        let doc = de.deserialize_any(DocVisitor { keep })?;
        de.end()?;
        Ok(doc)
    }
}

struct DocVisitor {
    keep: usize,
}

impl<'de> Visitor<'de> for DocVisitor {
    type Value = AnswerDoc;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an rsts-integrator/1 answer (a JSON object)")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<AnswerDoc, A::Error> {
        let mut doc = AnswerDoc::default();
        // A key given twice: the last one counts, as in a JSON object read whole.
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            match key.as_ref() {
                "name" => doc.name = Some(map.next_value::<Small>()?.0),
                "digits" => doc.digits = Some(map.next_value::<Small>()?.0),
                "version" => doc.version = Some(map.next_value::<Small>()?.0),
                "stats" => {
                    let (stats, count) = map.next_value_seed(StatsSeed)?;
                    doc.stats = Some(stats);
                    doc.step_times_count = count;
                }
                "events" => doc.events = Some(map.next_value_seed(EventsSeed)?),
                "samples" => {
                    doc.samples = Some(map.next_value_seed(ListSeed {
                        keep: self.keep,
                        what: "samples",
                    })?)
                }
                "dense" => {
                    doc.dense = Some(map.next_value_seed(ListSeed {
                        keep: MAX_DENSE_ANSWER_SAMPLES,
                        what: "samples",
                    })?)
                }
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(doc)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<AnswerDoc, A::Error> {
        skip_seq(&mut seq)?;
        Ok(AnswerDoc::default())
    }
    fn visit_bool<E>(self, _: bool) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
    fn visit_i64<E>(self, _: i64) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
    fn visit_u64<E>(self, _: u64) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
    fn visit_f64<E>(self, _: f64) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
    fn visit_str<E>(self, _: &str) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
    fn visit_unit<E>(self) -> Result<AnswerDoc, E> {
        Ok(AnswerDoc::default())
    }
}

/// Skip the rest of a sequence or map (nothing kept).
fn skip_seq<'de, A: SeqAccess<'de>>(seq: &mut A) -> Result<usize, A::Error> {
    let mut n = 0;
    while seq.next_element::<IgnoredAny>()?.is_some() {
        n += 1;
    }
    Ok(n)
}

fn skip_map<'de, A: MapAccess<'de>>(map: &mut A) -> Result<(), A::Error> {
    while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
    Ok(())
}

/// A scalar JSON value kept as a `Value`; an array or object is skipped and kept as an empty
/// array (every check of a scalar key refuses it, as it refuses the whole).
struct Small(Value);

impl<'de> de::Deserialize<'de> for Small {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SmallVisitor)
    }
}

struct SmallVisitor;

impl<'de> Visitor<'de> for SmallVisitor {
    type Value = Small;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, b: bool) -> Result<Small, E> {
        Ok(Small(Value::Bool(b)))
    }
    fn visit_i64<E>(self, x: i64) -> Result<Small, E> {
        Ok(Small(Value::from(x)))
    }
    fn visit_u64<E>(self, x: u64) -> Result<Small, E> {
        Ok(Small(Value::from(x)))
    }
    fn visit_f64<E>(self, x: f64) -> Result<Small, E> {
        Ok(Small(Value::from(x)))
    }
    fn visit_str<E>(self, s: &str) -> Result<Small, E> {
        Ok(Small(Value::String(s.to_string())))
    }
    fn visit_unit<E>(self) -> Result<Small, E> {
        Ok(Small(Value::Null))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Small, A::Error> {
        skip_seq(&mut seq)?;
        Ok(Small(Value::Array(Vec::new())))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Small, A::Error> {
        skip_map(&mut map)?;
        Ok(Small(Value::Array(Vec::new())))
    }
}

/// `stats`: an object of small values whose `step_times` keeps at most
/// [`MAX_DENSE_ANSWER_SAMPLES`] + 2 times (and counts them all).
struct StatsSeed;

impl<'de> DeserializeSeed<'de> for StatsSeed {
    type Value = (Value, usize);
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(Value, usize), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for StatsSeed {
    type Value = (Value, usize);
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("\"stats\"")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(Value, usize), A::Error> {
        let mut out = serde_json::Map::new();
        let mut count = 0;
        while let Some(key) = map.next_key::<String>()? {
            if key == "step_times" {
                let (times, n) = map.next_value_seed(TimesSeed)?;
                out.insert(key, times);
                count = n;
            } else {
                out.insert(key, map.next_value::<Small>()?.0);
            }
        }
        Ok((Value::Object(out), count))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(Value, usize), A::Error> {
        skip_seq(&mut seq)?;
        Ok((Value::Array(Vec::new()), 0))
    }
    fn visit_bool<E>(self, b: bool) -> Result<(Value, usize), E> {
        Ok((Value::Bool(b), 0))
    }
    fn visit_i64<E>(self, x: i64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_u64<E>(self, x: u64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_f64<E>(self, x: f64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_str<E>(self, s: &str) -> Result<(Value, usize), E> {
        Ok((Value::String(s.to_string()), 0))
    }
    fn visit_unit<E>(self) -> Result<(Value, usize), E> {
        Ok((Value::Null, 0))
    }
}

/// `stats.step_times`: an array of small values (the first [`MAX_DENSE_ANSWER_SAMPLES`] + 2
/// kept) and its length.
struct TimesSeed;

impl<'de> DeserializeSeed<'de> for TimesSeed {
    type Value = (Value, usize);
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(Value, usize), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for TimesSeed {
    type Value = (Value, usize);
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("\"step_times\"")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(Value, usize), A::Error> {
        let mut kept = Vec::new();
        let mut n = 0;
        while let Some(x) = seq.next_element::<Small>()? {
            if kept.len() < MAX_DENSE_ANSWER_SAMPLES + 2 {
                kept.push(x.0);
            }
            n += 1;
        }
        Ok((Value::Array(kept), n))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(Value, usize), A::Error> {
        skip_map(&mut map)?;
        Ok((Value::Object(Default::default()), 0))
    }
    fn visit_bool<E>(self, b: bool) -> Result<(Value, usize), E> {
        Ok((Value::Bool(b), 0))
    }
    fn visit_i64<E>(self, x: i64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_u64<E>(self, x: u64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_f64<E>(self, x: f64) -> Result<(Value, usize), E> {
        Ok((Value::from(x), 0))
    }
    fn visit_str<E>(self, s: &str) -> Result<(Value, usize), E> {
        Ok((Value::String(s.to_string()), 0))
    }
    fn visit_unit<E>(self) -> Result<(Value, usize), E> {
        Ok((Value::Null, 0))
    }
}

/// `events`: `[{"name", "t"}]`, t a number or a decimal string; the first bad entry is the
/// error, at most [`MAX_ANSWER_EVENTS`] entries.
struct EventsSeed;

impl<'de> DeserializeSeed<'de> for EventsSeed {
    type Value = Result<Vec<(String, f64)>, String>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

/// The refusal of an events list that is not an array.
fn not_events<T>() -> Result<T, String> {
    Err("\"events\" must be an array".into())
}

impl<'de> Visitor<'de> for EventsSeed {
    type Value = Result<Vec<(String, f64)>, String>;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("\"events\"")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut out = Vec::new();
        let mut error = None;
        let mut i = 0usize;
        while let Some(entry) = seq.next_element::<EventEntry>()? {
            if error.is_none() {
                match entry {
                    _ if i >= MAX_ANSWER_EVENTS => {
                        error = Some(format!(
                            "\"events\" lists more than {MAX_ANSWER_EVENTS} events"
                        ))
                    }
                    EventEntry {
                        name: Some(n),
                        t: Some(t),
                    } if t.is_finite() => out.push((n, t)),
                    _ => {
                        error = Some(format!(
                            "events[{i}] needs a \"name\" string and a finite \"t\""
                        ))
                    }
                }
                if error.is_some() {
                    out = Vec::new();
                }
            }
            i += 1;
        }
        Ok(error.map_or(Ok(out), Err))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        skip_map(&mut map)?;
        Ok(not_events())
    }
    fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
        Ok(not_events())
    }
    fn visit_i64<E>(self, _: i64) -> Result<Self::Value, E> {
        Ok(not_events())
    }
    fn visit_u64<E>(self, _: u64) -> Result<Self::Value, E> {
        Ok(not_events())
    }
    fn visit_f64<E>(self, _: f64) -> Result<Self::Value, E> {
        Ok(not_events())
    }
    fn visit_str<E>(self, _: &str) -> Result<Self::Value, E> {
        Ok(not_events())
    }
    fn visit_unit<E>(self) -> Result<Self::Value, E> {
        Ok(not_events())
    }
}

/// One entry of `events`: its name when a string, its time when a number or a decimal string.
#[derive(Default)]
struct EventEntry {
    name: Option<String>,
    t: Option<f64>,
}

impl<'de> de::Deserialize<'de> for EventEntry {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(EventEntryVisitor)
    }
}

struct EventEntryVisitor;

impl<'de> Visitor<'de> for EventEntryVisitor {
    type Value = EventEntry;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an event")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<EventEntry, A::Error> {
        let mut e = EventEntry::default();
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            match key.as_ref() {
                "name" => e.name = map.next_value::<Small>()?.0.as_str().map(str::to_string),
                "t" => {
                    e.t = match map.next_value::<Small>()?.0 {
                        Value::Number(n) => n.as_f64(),
                        Value::String(s) => s.trim().parse().ok(),
                        _ => None,
                    }
                }
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(e)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<EventEntry, A::Error> {
        skip_seq(&mut seq)?;
        Ok(EventEntry::default())
    }
    fn visit_bool<E>(self, _: bool) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
    fn visit_i64<E>(self, _: i64) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
    fn visit_u64<E>(self, _: u64) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
    fn visit_f64<E>(self, _: f64) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
    fn visit_str<E>(self, _: &str) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
    fn visit_unit<E>(self) -> Result<EventEntry, E> {
        Ok(EventEntry::default())
    }
}

/// A list of samples (`samples`, `dense`): the first `keep` kept as read (checked as
/// [`crate::files::parse_json`] checks them, with its messages), the rest counted.
struct ListSeed {
    keep: usize,
    what: &'static str,
}

impl<'de> DeserializeSeed<'de> for ListSeed {
    type Value = SampleList;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<SampleList, D::Error> {
        d.deserialize_any(self)
    }
}

impl ListSeed {
    fn not_a_list(&self) -> SampleList {
        SampleList {
            error: Some(format!("\"{}\" must be an array", self.what)),
            ..SampleList::default()
        }
    }
}

impl<'de> Visitor<'de> for ListSeed {
    type Value = SampleList;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a list of samples")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SampleList, A::Error> {
        let mut list = SampleList::default();
        loop {
            let k = list.count;
            if list.error.is_some() || k >= self.keep {
                // Past the first error or the samples kept: counted, not read.
                if seq.next_element::<IgnoredAny>()?.is_none() {
                    break;
                }
                list.count += 1;
                continue;
            }
            let Some(sample) = seq.next_element::<SampleRead>()? else {
                break;
            };
            let place = format!("{}[{k}]", self.what);
            match sample.check(&place) {
                Ok((t, state)) => list.raw.push(t, state, place),
                Err(e) => list.error = Some(e),
            }
            list.count += 1;
        }
        Ok(list)
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SampleList, A::Error> {
        skip_map(&mut map)?;
        Ok(self.not_a_list())
    }
    fn visit_bool<E>(self, _: bool) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
    fn visit_i64<E>(self, _: i64) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
    fn visit_u64<E>(self, _: u64) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
    fn visit_f64<E>(self, _: f64) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
    fn visit_str<E>(self, _: &str) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
    fn visit_unit<E>(self) -> Result<SampleList, E> {
        Ok(self.not_a_list())
    }
}

/// One value as read: a checked number, or why not.
type Read1 = Result<Number, String>;

/// One sample as read: `t` and the three vectors (each `None` when absent, `Err` when not an
/// array of three); checked in the order of [`crate::files::parse_json`] by
/// [`SampleRead::check`].
#[derive(Default)]
struct SampleRead {
    t: Option<Read1>,
    vectors: [Option<Result<[Read1; 3], ()>>; 3],
}

const VECTORS: [&str; 3] = ["omega", "alpha", "beta"];

impl SampleRead {
    fn check(self, place: &str) -> Result<(Number, [Number; 9]), String> {
        let t = match self.t {
            None => return Err(format!("{place}: no \"t\"")),
            Some(t) => t.map_err(|e| format!("{place}.t: {e}"))?,
        };
        let mut state: [Number; 9] = std::array::from_fn(|_| Number::F64(0.0));
        for (v, read) in self.vectors.into_iter().enumerate() {
            let key = VECTORS[v];
            let Some(Ok(values)) = read else {
                return Err(format!("{place}: \"{key}\" must be an array of 3 numbers"));
            };
            for (i, x) in values.into_iter().enumerate() {
                state[3 * v + i] = x
                    .and_then(check_component)
                    .map_err(|e| format!("{place}.{key}[{i}]: {e}"))?;
            }
        }
        Ok((t, state))
    }
}

impl<'de> de::Deserialize<'de> for SampleRead {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SampleVisitor)
    }
}

struct SampleVisitor;

impl<'de> Visitor<'de> for SampleVisitor {
    type Value = SampleRead;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a sample")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SampleRead, A::Error> {
        let mut s = SampleRead::default();
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            match VECTORS.iter().position(|v| *v == key.as_ref()) {
                Some(v) => s.vectors[v] = Some(map.next_value::<Vector>()?.0),
                None if key == "t" => s.t = Some(map.next_value::<Value1>()?.0),
                None => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(s)
    }
    // Not an object: a sample without "t".
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SampleRead, A::Error> {
        skip_seq(&mut seq)?;
        Ok(SampleRead::default())
    }
    fn visit_bool<E>(self, _: bool) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
    fn visit_i64<E>(self, _: i64) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
    fn visit_u64<E>(self, _: u64) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
    fn visit_f64<E>(self, _: f64) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
    fn visit_str<E>(self, _: &str) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
    fn visit_unit<E>(self) -> Result<SampleRead, E> {
        Ok(SampleRead::default())
    }
}

/// An array of exactly three values (`Err(())` for anything else).
struct Vector(Result<[Read1; 3], ()>);

impl<'de> de::Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(VectorVisitor)
    }
}

struct VectorVisitor;

impl<'de> Visitor<'de> for VectorVisitor {
    type Value = Vector;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an array of 3 numbers")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vector, A::Error> {
        let mut got: Vec<Read1> = Vec::with_capacity(3);
        while got.len() < 3 {
            match seq.next_element::<Value1>()? {
                Some(x) => got.push(x.0),
                None => return Ok(Vector(Err(()))),
            }
        }
        if skip_seq(&mut seq)? > 0 {
            return Ok(Vector(Err(())));
        }
        let [a, b, c]: [Read1; 3] = got.try_into().map_err(|_| de::Error::custom("three"))?;
        Ok(Vector(Ok([a, b, c])))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Vector, A::Error> {
        skip_map(&mut map)?;
        Ok(Vector(Err(())))
    }
    fn visit_bool<E>(self, _: bool) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
    fn visit_i64<E>(self, _: i64) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
    fn visit_u64<E>(self, _: u64) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
    fn visit_f64<E>(self, _: f64) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
    fn visit_str<E>(self, _: &str) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
    fn visit_unit<E>(self) -> Result<Vector, E> {
        Ok(Vector(Err(())))
    }
}

/// One value of a sample: a number or a decimal string, checked ([`check_f64`],
/// [`check_text`]).
struct Value1(Read1);

impl<'de> de::Deserialize<'de> for Value1 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(Value1Visitor)
    }
}

struct Value1Visitor;

fn not_a_number(what: &str) -> Value1 {
    Value1(Err(format!(
        "expected a number or a decimal string, got {what}"
    )))
}

impl<'de> Visitor<'de> for Value1Visitor {
    type Value = Value1;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a number or a decimal string")
    }
    fn visit_f64<E>(self, x: f64) -> Result<Value1, E> {
        Ok(Value1(check_f64(x)))
    }
    fn visit_i64<E>(self, x: i64) -> Result<Value1, E> {
        Ok(Value1(check_f64(x as f64)))
    }
    fn visit_u64<E>(self, x: u64) -> Result<Value1, E> {
        Ok(Value1(check_f64(x as f64)))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value1, E> {
        Ok(Value1(check_text(s)))
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value1, E> {
        Ok(not_a_number(&b.to_string()))
    }
    fn visit_unit<E>(self) -> Result<Value1, E> {
        Ok(not_a_number("null"))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value1, A::Error> {
        skip_seq(&mut seq)?;
        Ok(not_a_number("an array"))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value1, A::Error> {
        skip_map(&mut map)?;
        Ok(not_a_number("an object"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stream reads what a whole document gives: samples, stats, events, the last of a
    /// repeated key; junk keys are skipped.
    #[test]
    fn an_answer_read_as_a_stream_keeps_what_rsts_reads() {
        let text = r#"{"junk": [[0, 0], {"a": [1]}], "name": "x", "name": "rk4",
            "samples": [{"t": 0, "omega": [0.1, "0.2", 0.3], "alpha": [1, 0, 0],
                         "beta": [0, 1, 0], "H": 3},
                        {"t": 1, "omega": [1, 2, 3], "alpha": [1, 0, 0], "beta": [0, 1, 0]}],
            "stats": {"steps": 4, "step_times": [0, 0.5, 1], "x": [9]},
            "events": [{"name": "omega1", "t": "0.5"}], "digits": 15}"#;
        let doc = AnswerDoc::read(text.as_bytes(), 10).unwrap();
        assert_eq!(doc.name, Some(Value::from("rk4")));
        assert_eq!(doc.digits, Some(Value::from(15)));
        let s = doc.samples.unwrap();
        assert_eq!((s.count, s.raw.len(), s.error), (2, 2, None));
        assert_eq!(s.raw.states[0][1], Number::Text("0.2".into()));
        assert_eq!(s.raw.places[1], "samples[1]");
        assert_eq!(doc.step_times_count, 3);
        assert_eq!(doc.stats.unwrap()["x"], Value::Array(vec![]));
        assert_eq!(doc.events.unwrap().unwrap(), vec![("omega1".into(), 0.5)]);
        // Kept up to `keep`, all counted; the first bad sample is the error.
        let doc = AnswerDoc::read(text.as_bytes(), 1).unwrap();
        let s = doc.samples.unwrap();
        assert_eq!((s.count, s.raw.len()), (2, 1));
        let bad = r#"{"samples": [{"t": 0, "omega": [0, 0], "alpha": [1, 0, 0], "beta": [0, 1, 0]},
            {"omega": [0, 0, 0]}]}"#;
        let s = AnswerDoc::read(bad.as_bytes(), 10)
            .unwrap()
            .samples
            .unwrap();
        assert_eq!(
            s.error.unwrap(),
            "samples[0]: \"omega\" must be an array of 3 numbers"
        );
        let bad = r#"{"samples": [{"t": [1], "omega": [0, 0, 0]}]}"#;
        let s = AnswerDoc::read(bad.as_bytes(), 10)
            .unwrap()
            .samples
            .unwrap();
        assert_eq!(
            s.error.unwrap(),
            "samples[0].t: expected a number or a decimal string, got an array"
        );
        assert!(AnswerDoc::read(b"{\"samples\": [} ", 10).is_err());
        assert!(AnswerDoc::read(b"{} x", 10).is_err());
        assert!(AnswerDoc::read(b"[1, 2]", 10).unwrap().samples.is_none());
    }
}
