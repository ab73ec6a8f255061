//! Reading a log back: summary and series extraction for `rsts inspect`.
//!
//! Both entry points do one linear scan of the whole file, which works on complete,
//! truncated and partly damaged files alike: a chunk that fails to decompress or whose CRC
//! does not match is skipped whole (its messages are not trusted), and the scan stops at
//! the first top-level record it cannot frame (for a truncated file: the cut). When the
//! file has a summary section, its statistics are checked against the scan. Whatever went
//! wrong is described in the `notes` and flagged by `recovered: true`; a file that is not
//! MCAP at all, or cannot be read, is an [`InspectError`]. No input makes these panic.

use std::collections::BTreeMap;
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use mcap::records::Record;
use serde::Serialize;
use serde_json::Value;

use crate::topics;

/// Errors of the reader. A damaged file with anything readable is *not* an error: it gives
/// a result with `recovered: true` and notes.
#[derive(Debug, thiserror::Error)]
pub enum InspectError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path} is not an MCAP file: {reason}")]
    NotMcap { path: PathBuf, reason: String },
    #[error("no channel `{topic}` in the file; channels: {}", available.join(", "))]
    UnknownTopic {
        topic: String,
        available: Vec<String>,
    },
    #[error("channel `{topic}` has message encoding `{encoding}`, only `json` can be extracted")]
    NotJson { topic: String, encoding: String },
    #[error("internal error while reading {path} (the MCAP reader panicked): {message}")]
    ReaderPanicked { path: PathBuf, message: String },
}

/// One channel of the file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelInfo {
    pub topic: String,
    /// Schema name, e.g. `foxglove.FrameTransform` (None for a schemaless channel).
    pub schema_name: Option<String>,
    pub schema_encoding: Option<String>,
    pub message_encoding: String,
    /// Messages read (for a complete file: equal to the summary statistics).
    pub message_count: u64,
}

/// An MCAP Metadata record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetadataRecord {
    pub name: String,
    pub metadata: BTreeMap<String, String>,
}

/// The largest absolute value of one numeric field of the `/errors` channel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldMax {
    /// Flattened field path (`state_error`, or `a.0` for nested arrays/objects).
    pub field: String,
    /// max |value| over the finite values (NaN if none was finite).
    pub max_abs: f64,
    /// Motion time (s, from the log time) at which the maximum occurs.
    pub at_t: f64,
    /// Number of non-finite values (logged as JSON `null`).
    pub non_finite: u64,
}

/// What `rsts inspect FILE` prints.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub path: PathBuf,
    pub file_size: u64,
    /// Writer library from the MCAP header.
    pub library: Option<String>,
    pub channels: Vec<ChannelInfo>,
    /// Messages read.
    pub message_count: u64,
    /// Log times of the first and last message, in ns (None without messages).
    pub start_time_ns: Option<u64>,
    pub end_time_ns: Option<u64>,
    pub metadata: Vec<MetadataRecord>,
    /// Maxima of the numeric fields of `/errors`, in the order the fields first appear.
    pub error_maxima: Vec<FieldMax>,
    /// Whether a valid summary section was found (and agreed with the data).
    pub has_summary_section: bool,
    /// True when the file was damaged or incomplete and this is what could be recovered.
    pub recovered: bool,
    /// What was wrong, in plain words (empty for a healthy file).
    pub notes: Vec<String>,
}

/// One message of an extracted series.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeriesPoint {
    pub log_time_ns: u64,
    /// Motion time in seconds: `log_time_ns / 1e9`.
    pub t: f64,
    pub value: Value,
}

/// The messages of one JSON channel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    pub topic: String,
    pub points: Vec<SeriesPoint>,
    pub recovered: bool,
    pub notes: Vec<String>,
}

#[derive(Default)]
struct ScanChannel {
    topic: String,
    schema_id: u16,
    message_encoding: String,
    count: u64,
}

#[derive(Default)]
struct Scan {
    library: Option<String>,
    schemas: BTreeMap<u16, (String, String)>,
    channels: BTreeMap<u16, ScanChannel>,
    metadata: Vec<MetadataRecord>,
    message_count: u64,
    time_range: Option<(u64, u64)>,
    notes: Vec<String>,
    saw_data_end: bool,
    /// The summary section and footer are whole and their CRC matches.
    summary_sound: bool,
    /// Messages whose channel definition was not read (it was in a lost chunk); skipped.
    orphans: u64,
}

/// A message as seen by the scan callback.
struct Msg<'a> {
    topic: &'a str,
    encoding: &'a str,
    log_time: u64,
    data: &'a [u8],
}

impl Scan {
    fn record(&mut self, rec: Record<'_>, on_msg: &mut dyn FnMut(Msg<'_>)) {
        match rec {
            Record::Header(h) => self.library = Some(h.library),
            Record::Schema { header, .. } => {
                self.schemas
                    .insert(header.id, (header.name, header.encoding));
            }
            Record::Channel(c) => {
                self.channels.entry(c.id).or_insert(ScanChannel {
                    topic: c.topic,
                    schema_id: c.schema_id,
                    message_encoding: c.message_encoding,
                    count: 0,
                });
            }
            Record::Message { header, data } => match self.channels.get_mut(&header.channel_id) {
                Some(ch) => {
                    ch.count += 1;
                    self.message_count += 1;
                    self.time_range = Some(match self.time_range {
                        None => (header.log_time, header.log_time),
                        Some((a, b)) => (a.min(header.log_time), b.max(header.log_time)),
                    });
                    on_msg(Msg {
                        topic: &ch.topic,
                        encoding: &ch.message_encoding,
                        log_time: header.log_time,
                        data: &data,
                    });
                }
                None => self.orphans += 1,
            },
            Record::Metadata(m) => self.metadata.push(MetadataRecord {
                name: m.name,
                metadata: m.metadata,
            }),
            _ => {}
        }
    }
}

/// Largest log read (it is read whole): 2 GiB, the most one output file of rsts may hold.
pub const MAX_LOG_BYTES: u64 = 2 << 30;

fn read_file(path: &Path) -> Result<Vec<u8>, InspectError> {
    let io = |source| InspectError::Io {
        path: path.to_path_buf(),
        source,
    };
    // The magic first: a file (or a device) that is not MCAP is refused before the rest is read.
    let mut input = rsts_io::open_bounded(path, MAX_LOG_BYTES, "an MCAP log").map_err(io)?;
    let mut buf = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(&mut input, mcap::MAGIC.len() as u64),
        &mut buf,
    )
    .map_err(io)?;
    if buf.len() == mcap::MAGIC.len() && buf.starts_with(mcap::MAGIC) {
        let size = std::fs::metadata(path)
            .ok()
            .filter(|m| m.is_file())
            .map(|m| m.len());
        input.read_all(&mut buf, size).map_err(io)?;
    }
    if buf.len() < mcap::MAGIC.len() {
        let n = buf.len();
        let reason = if n > 0 && mcap::MAGIC.starts_with(&buf) {
            format!("truncated at byte {n}, inside the MCAP magic: nothing can be recovered")
        } else {
            format!("only {n} bytes, shorter than the MCAP magic")
        };
        return Err(InspectError::NotMcap {
            path: path.to_path_buf(),
            reason,
        });
    }
    if !buf.starts_with(mcap::MAGIC) {
        return Err(InspectError::NotMcap {
            path: path.to_path_buf(),
            reason: "it does not start with the MCAP magic bytes".into(),
        });
    }
    Ok(buf)
}

/// Read the whole file: frame its records ([`crate::framing::walk`], which also checks the data
/// and summary CRCs, the footer and the closing magic), decompress and check every chunk (a
/// chunk whose CRC does not match is skipped whole), and hand every message to `on_msg`.
fn scan(buf: &[u8], on_msg: &mut dyn FnMut(Msg<'_>)) -> Scan {
    let mut s = Scan::default();
    let mut chunk_no = 0u64;
    let damaged = std::cell::Cell::new(false);
    let layout = crate::framing::walk(
        buf,
        &mut |opcode, offset, body| {
            let record = match mcap::parse_record(opcode, body) {
                Ok(r) => r,
                Err(e) => {
                    damaged.set(true);
                    s.notes.push(format!(
                        "the record at byte {offset} (opcode {opcode:#04x}) is damaged and was skipped: {e}"
                    ));
                    return;
                }
            };
            match record {
                Record::Chunk { header, data } => {
                    chunk_no += 1;
                    let (start, end) = (header.message_start_time, header.message_end_time);
                    match read_chunk(&header, &data) {
                        Ok(records) => {
                            for r in records {
                                s.record(r, on_msg);
                            }
                        }
                        Err(e) => {
                            damaged.set(true);
                            s.notes.push(format!(
                                "chunk {chunk_no} (bytes {offset} to {}, log times {} to {} s) is damaged and was skipped: {e}",
                                offset + 9 + body.len(),
                                ns_to_s(start),
                                ns_to_s(end)
                            ));
                        }
                    }
                }
                r => s.record(r, on_msg),
            }
        },
        &|| damaged.get(),
    );
    if s.orphans > 0 {
        s.notes.push(format!(
            "{} message(s) refer to channels whose definitions were lost with a damaged chunk; skipped",
            s.orphans
        ));
    }
    s.notes.extend(layout.notes);
    s.saw_data_end = layout.saw_data_end;
    s.summary_sound = layout.summary_sound;
    s
}

/// Largest uncompressed chunk accepted: 1 GiB, and at most 4096 times the compressed size
/// plus 1 MiB. A damaged size field must not make the reader allocate without bound.
fn chunk_size_plausible(uncompressed: u64, compressed: usize) -> bool {
    uncompressed <= 1 << 30 && uncompressed <= 4096 * compressed as u64 + (1 << 20)
}

/// Decompresses a chunk, checks its size and CRC, and parses its records. Any failure
/// rejects the whole chunk (its records are not trusted), as a plain message.
fn read_chunk(
    header: &mcap::records::ChunkHeader,
    data: &[u8],
) -> Result<Vec<Record<'static>>, String> {
    let size = header.uncompressed_size;
    if !chunk_size_plausible(size, data.len()) {
        return Err(format!(
            "implausible uncompressed size {size} for {} compressed bytes",
            data.len()
        ));
    }
    let raw: Vec<u8> = match header.compression.as_str() {
        "" => data.to_vec(),
        "zstd" => zstd::bulk::decompress(data, size as usize)
            .map_err(|e| format!("zstd decompression failed: {e}"))?,
        other => return Err(format!("unsupported chunk compression `{other}`")),
    };
    if raw.len() as u64 != size {
        return Err(format!(
            "decompressed to {} bytes, the chunk header says {size}",
            raw.len()
        ));
    }
    if header.uncompressed_crc != 0 {
        let crc = crc32fast::hash(&raw);
        if crc != header.uncompressed_crc {
            return Err(format!(
                "CRC mismatch (stored {:08x}, computed {crc:08x})",
                header.uncompressed_crc
            ));
        }
    }
    mcap::read::LinearReader::sans_magic(&raw)
        .map(|r| {
            r.map(|r| r.into_owned())
                .map_err(|e| format!("bad record in chunk: {e}"))
        })
        .collect()
}

/// Exact decimal seconds of a time in ns, e.g. `0.010010010`.
pub fn format_ns(ns: u64) -> String {
    format!("{}.{:09}", ns / 1_000_000_000, ns % 1_000_000_000)
}

fn ns_to_s(ns: u64) -> f64 {
    ns as f64 * 1e-9
}

fn guarded<T>(path: &Path, f: impl FnOnce() -> Result<T, InspectError>) -> Result<T, InspectError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => {
            let message = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(InspectError::ReaderPanicked {
                path: path.to_path_buf(),
                message,
            })
        }
    }
}

/// Flattens a JSON value into `(column, leaf)` pairs with the CSV column naming of every
/// `rsts` command (docs/output.md): array elements numbered from 1 after the name (`omega1`,
/// `gamma3`), object keys joined by `_` (`quaternion_w`, `rotation_x`); a scalar at the top has
/// the name `""`.
pub fn flatten(value: &Value) -> Vec<(String, Value)> {
    fn go(prefix: &str, v: &Value, out: &mut Vec<(String, Value)>) {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    let name = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}_{k}")
                    };
                    go(&name, x, out);
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    go(&format!("{prefix}{}", i + 1), x, out);
                }
            }
            leaf => out.push((prefix.to_string(), leaf.clone())),
        }
    }
    let mut out = Vec::new();
    go("", value, &mut out);
    out
}

/// Summarises the file at `path`: channels, schemas, message counts, time range, metadata
/// records and the maximum of each numeric field on `/errors`.
pub fn summarize(path: impl AsRef<Path>) -> Result<Summary, InspectError> {
    let path = path.as_ref();
    let buf = read_file(path)?;
    guarded(path, || Ok(summarize_bytes(path, &buf)))
}

fn summarize_bytes(path: &Path, buf: &[u8]) -> Summary {
    let mut maxima: Vec<FieldMax> = Vec::new();
    let mut bad_error_msgs = 0u64;
    let mut s = scan(buf, &mut |m| {
        if m.topic != topics::ERRORS {
            return;
        }
        let Ok(v) = serde_json::from_slice::<Value>(m.data) else {
            bad_error_msgs += 1;
            return;
        };
        let t = ns_to_s(m.log_time);
        for (field, leaf) in flatten(&v) {
            // log10_… fields are derived from the others (for plots): their |maximum| means nothing.
            if field == "t" || field.starts_with("log10_") {
                continue;
            }
            let idx = match maxima.iter().position(|f| f.field == field) {
                Some(i) => i,
                None => {
                    maxima.push(FieldMax {
                        field,
                        max_abs: f64::NAN,
                        at_t: f64::NAN,
                        non_finite: 0,
                    });
                    maxima.len() - 1
                }
            };
            let fm = &mut maxima[idx];
            match leaf.as_f64() {
                Some(x) if x.is_finite() => {
                    if fm.max_abs.is_nan() || x.abs() > fm.max_abs {
                        fm.max_abs = x.abs();
                        fm.at_t = t;
                    }
                }
                _ => fm.non_finite += 1,
            }
        }
    });
    if bad_error_msgs > 0 {
        s.notes.push(format!(
            "{bad_error_msgs} message(s) on {} are not valid JSON and were ignored",
            topics::ERRORS
        ));
    }

    let has_summary_section = check_summary(buf, &mut s);

    let channels = s
        .channels
        .values()
        .map(|c| {
            let schema = s.schemas.get(&c.schema_id);
            ChannelInfo {
                topic: c.topic.clone(),
                schema_name: schema.map(|x| x.0.clone()),
                schema_encoding: schema.map(|x| x.1.clone()),
                message_encoding: c.message_encoding.clone(),
                message_count: c.count,
            }
        })
        .collect();
    Summary {
        path: path.to_path_buf(),
        file_size: buf.len() as u64,
        library: s.library,
        channels,
        message_count: s.message_count,
        start_time_ns: s.time_range.map(|r| r.0),
        end_time_ns: s.time_range.map(|r| r.1),
        metadata: s.metadata,
        error_maxima: maxima,
        has_summary_section,
        recovered: !s.notes.is_empty(),
        notes: s.notes,
    }
}

/// Compare the summary section (when the framing found it whole and its CRC matching) with
/// what the scan read; add what disagrees to the notes. Returns whether a valid summary section
/// was found and agreed. Channels listed only in the summary (their records were in a lost
/// chunk) are added to the scan.
fn check_summary(buf: &[u8], s: &mut Scan) -> bool {
    let scan_ok = s.notes.is_empty();
    if !s.summary_sound {
        return false;
    }
    let sum = match mcap::Summary::read(buf) {
        Ok(Some(sum)) => sum,
        Ok(None) => {
            if scan_ok {
                s.notes.push("the file has no summary section".into());
            }
            return false;
        }
        Err(e) => {
            s.notes
                .push(format!("the summary section or footer is unreadable: {e}"));
            return false;
        }
    };
    let mut agrees = true;
    if let Some(stats) = &sum.stats {
        let mut disagreements = Vec::new();
        if stats.message_count != s.message_count {
            disagreements.push(format!(
                "the summary section counts {} messages, {} could be read",
                stats.message_count, s.message_count
            ));
        }
        for (id, n) in &stats.channel_message_counts {
            let got = s.channels.get(id).map_or(0, |c| c.count);
            if got != *n && stats.message_count == s.message_count {
                disagreements.push(format!(
                    "channel {id}: summary counts {n} messages, {got} read"
                ));
            }
        }
        if !disagreements.is_empty() {
            agrees = false;
            s.notes.extend(disagreements);
        }
    }
    for (id, ch) in &sum.channels {
        s.channels.entry(*id).or_insert_with(|| {
            if let Some(sc) = &ch.schema {
                s.schemas
                    .entry(sc.id)
                    .or_insert((sc.name.clone(), sc.encoding.clone()));
            }
            ScanChannel {
                topic: ch.topic.clone(),
                schema_id: ch.schema.as_ref().map_or(0, |sc| sc.id),
                message_encoding: ch.message_encoding.clone(),
                count: 0,
            }
        });
    }
    agrees
}

/// Extracts the JSON messages of `topic`, in file order, with their times. A damaged file
/// gives the recovered messages with `recovered: true` and notes.
pub fn extract(path: impl AsRef<Path>, topic: &str) -> Result<Series, InspectError> {
    let path = path.as_ref();
    let buf = read_file(path)?;
    guarded(path, || {
        let mut points = Vec::new();
        let mut encoding: Option<String> = None;
        let mut bad = 0u64;
        let mut s = scan(&buf, &mut |m| {
            if m.topic != topic {
                return;
            }
            if m.encoding != "json" {
                encoding = Some(m.encoding.to_string());
                return;
            }
            match serde_json::from_slice::<Value>(m.data) {
                Ok(value) => points.push(SeriesPoint {
                    log_time_ns: m.log_time,
                    t: ns_to_s(m.log_time),
                    value,
                }),
                Err(_) => bad += 1,
            }
        });
        check_summary(&buf, &mut s);
        let channel = s.channels.values().find(|c| c.topic == topic);
        if channel.is_none() && !s.notes.is_empty() {
            // A damaged file: the channel may be in the part that was lost.
            let mut notes = s.notes;
            notes.push(format!(
                "no channel `{topic}` in what could be read (it may be in the damaged part)"
            ));
            return Ok(Series {
                topic: topic.to_string(),
                points,
                recovered: true,
                notes,
            });
        }
        let Some(channel) = channel else {
            let mut available: Vec<String> = s.channels.values().map(|c| c.topic.clone()).collect();
            available.sort();
            return Err(InspectError::UnknownTopic {
                topic: topic.to_string(),
                available,
            });
        };
        if let Some(encoding) = encoding.or_else(|| {
            (channel.message_encoding != "json").then(|| channel.message_encoding.clone())
        }) {
            return Err(InspectError::NotJson {
                topic: topic.to_string(),
                encoding,
            });
        }
        let mut notes = s.notes;
        if bad > 0 {
            notes.push(format!(
                "{bad} message(s) are not valid JSON and were skipped"
            ));
        }
        Ok(Series {
            topic: topic.to_string(),
            points,
            recovered: !notes.is_empty(),
            notes,
        })
    })
}

fn csv_field(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => {
            if s.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.clone()
            }
        }
        other => other.to_string(),
    }
}

/// The state columns that come right after `t` when a channel has them.
const STATE_COLUMNS: [&str; 9] = [
    "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
];

impl Series {
    /// Column names of [`to_csv`](Self::to_csv): `t`, then `omega1 … beta3` when the messages
    /// have them, then the other flattened fields in order of first appearance, then
    /// `log_time`.
    pub fn columns(&self) -> Vec<String> {
        let mut seen: Vec<String> = Vec::new();
        for p in &self.points {
            for (k, _) in flatten(&p.value) {
                let k = if k.is_empty() { "value".to_string() } else { k };
                if !seen.contains(&k) {
                    seen.push(k);
                }
            }
        }
        let mut cols = vec!["t".to_string()];
        cols.extend(
            STATE_COLUMNS
                .iter()
                .filter(|c| seen.iter().any(|s| s == *c))
                .map(|c| c.to_string()),
        );
        for k in seen {
            if !cols.contains(&k) && k != "log_time" {
                cols.push(k);
            }
        }
        cols.push("log_time".to_string());
        cols
    }

    /// CSV: a header line ([`columns`](Self::columns)) then one line per message. `t` is the
    /// message's own `t` when it has one, else the log time in seconds; `log_time` is the exact
    /// decimal of the ns log time; nested fields are flattened ([`flatten`]: `omega1`,
    /// `quaternion_w`); missing or null values are empty.
    pub fn to_csv(&self) -> String {
        let cols = self.columns();
        let mut out = cols
            .iter()
            .map(|c| csv_field(&Value::String(c.clone())))
            .collect::<Vec<_>>()
            .join(",");
        out.push('\n');
        for p in &self.points {
            let mut flat: BTreeMap<String, Value> = flatten(&p.value)
                .into_iter()
                .map(|(k, v)| (if k.is_empty() { "value".into() } else { k }, v))
                .collect();
            let log_time = format_ns(p.log_time_ns);
            flat.entry("t".into())
                .or_insert_with(|| Value::String(log_time.clone()));
            flat.insert("log_time".into(), Value::String(log_time));
            let row: Vec<String> = cols
                .iter()
                .map(|c| flat.get(c).map(csv_field).unwrap_or_default())
                .collect();
            out.push_str(&row.join(","));
            out.push('\n');
        }
        out
    }

    /// JSON: an array of `{"log_time": seconds, "log_time_ns": n, "message": {...}}`, one
    /// element per line.
    pub fn to_json(&self) -> String {
        let mut out = String::from("[\n");
        for (i, p) in self.points.iter().enumerate() {
            let v = serde_json::json!({"log_time": p.t, "log_time_ns": p.log_time_ns, "message": p.value});
            out.push_str(&v.to_string());
            if i + 1 < self.points.len() {
                out.push(',');
            }
            out.push('\n');
        }
        out.push_str("]\n");
        out
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "file: {} ({} bytes)",
            self.path.display(),
            self.file_size
        )?;
        if let Some(lib) = &self.library {
            writeln!(f, "written by: {lib}")?;
        }
        if self.recovered {
            writeln!(
                f,
                "status: DAMAGED OR INCOMPLETE — showing what could be recovered"
            )?;
            for n in &self.notes {
                writeln!(f, "  - {n}")?;
            }
        } else {
            writeln!(f, "status: complete")?;
        }
        match (self.start_time_ns, self.end_time_ns) {
            (Some(a), Some(b)) => writeln!(
                f,
                "time range: t = {} .. {} s ({} messages)",
                format_ns(a),
                format_ns(b),
                self.message_count
            )?,
            _ => writeln!(f, "time range: none (no message recovered)")?,
        }
        writeln!(f, "channels:")?;
        let w = self
            .channels
            .iter()
            .map(|c| c.topic.len())
            .max()
            .unwrap_or(0);
        for c in &self.channels {
            writeln!(
                f,
                "  {:w$}  {:>8} msgs  {} ({}), {}",
                c.topic,
                c.message_count,
                c.schema_name.as_deref().unwrap_or("<no schema>"),
                c.schema_encoding.as_deref().unwrap_or("-"),
                c.message_encoding,
            )?;
        }
        for m in &self.metadata {
            writeln!(f, "metadata `{}`:", m.name)?;
            for (k, v) in &m.metadata {
                if k == "case" || k == "integrator" {
                    continue; // the whole-object JSON duplicates the per-field keys
                }
                writeln!(f, "  {k} = {v}")?;
            }
        }
        if !self.error_maxima.is_empty() {
            writeln!(f, "max |value| on {}:", topics::ERRORS)?;
            let w = self
                .error_maxima
                .iter()
                .map(|m| m.field.len())
                .max()
                .unwrap_or(0);
            for m in &self.error_maxima {
                write!(
                    f,
                    "  {:w$}  {:.6e}  at t = {:.6}",
                    m.field, m.max_abs, m.at_t
                )?;
                if m.non_finite > 0 {
                    write!(f, "  ({} non-finite values)", m.non_finite)?;
                }
                writeln!(f)?;
            }
        }
        Ok(())
    }
}
