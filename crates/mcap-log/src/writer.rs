//! Writing one comparison to an MCAP file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rsts_io::AtomicFile;

use mcap::records::MessageHeader;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::quat::Quaternion;
use crate::schemas;
use crate::topics;

/// Errors of [`TrajectoryLog`].
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    #[error("cannot create MCAP file {path}: {source}")]
    Create {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("I/O error while writing the MCAP file: {0}")]
    Io(#[from] std::io::Error),
    #[error("MCAP writer error: {0}")]
    Mcap(#[from] mcap::McapError),
    #[error("JSON encoding error: {0}")]
    Json(#[from] serde_json::Error),
    #[error("motion time t = {0} cannot be logged: it must be finite, >= 0 and < 1.8e10 s")]
    BadTime(f64),
    #[error("motion time went backwards: t = {t} after t = {previous}")]
    TimeNotMonotonic { t: f64, previous: f64 },
    #[error("the log was already finished")]
    Finished,
    /// A write failed before; the first error is kept (the OS error, e.g. "No space left on
    /// device"), not the writer's later "attempted another write after a write method failed".
    #[error("{0}")]
    Failed(String),
}

/// Metadata of one comparison, written once as an MCAP Metadata record (name `rsts`) and as
/// a JSON message on `/metadata` at t = 0.
///
/// `case` and `integrator` are free-form JSON objects so the harness can pass its own
/// serde types through [`serde_json::to_value`]; the expected keys are
/// case: `a, b, m, h, torus, phases, t_end, samples`; integrator: `method, rtol, atol, digits`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Metadata {
    pub software_version: String,
    pub case: Value,
    pub integrator: Value,
}

impl Metadata {
    /// Builds the metadata from any serialisable case and integrator description.
    pub fn new(
        software_version: impl Into<String>,
        case: &impl Serialize,
        integrator: &impl Serialize,
    ) -> Result<Metadata, serde_json::Error> {
        Ok(Metadata {
            software_version: software_version.into(),
            case: serde_json::to_value(case)?,
            integrator: serde_json::to_value(integrator)?,
        })
    }

    /// The string map of the MCAP Metadata record: `software_version`, and one key
    /// `case.<field>` / `integrator.<field>` per top-level field (strings verbatim, other
    /// values as JSON), plus `case` and `integrator` holding the whole JSON.
    pub fn to_record_map(&self) -> BTreeMap<String, String> {
        let mut m = BTreeMap::new();
        m.insert("software_version".into(), self.software_version.clone());
        for (prefix, v) in [("case", &self.case), ("integrator", &self.integrator)] {
            m.insert(prefix.into(), v.to_string());
            if let Value::Object(fields) = v {
                for (k, fv) in fields {
                    let s = match fv {
                        Value::String(s) => s.clone(),
                        other => other.to_string(),
                    };
                    m.insert(format!("{prefix}.{k}"), s);
                }
            }
        }
        m
    }
}

/// State of the body at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    /// Orientation matrix, rows α, β, γ: the fixed axes in body components (Ω = Q ω).
    pub q: [[f64; 3]; 3],
    /// Angular velocity in the body frame.
    pub omega: [f64; 3],
    /// Angular velocity in the fixed frame, Q ω.
    pub omega_fixed: [f64; 3],
    /// First integrals.
    pub h: f64,
    pub k: f64,
    pub g: f64,
}

/// Errors of the integrated motion against the exact one, as computed by the harness. Each
/// field is logged on `/errors` with a companion `log10_<field>` = log10 |value| (left out
/// where the value is 0 or not finite); the fields are listed in [`schemas::ERROR_FIELDS`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ErrorSample {
    pub state_error: f64,
    pub orientation_error: f64,
    pub drift_h: f64,
    pub drift_k: f64,
    pub drift_g: f64,
    pub constraint_drift: f64,
    pub off_n: f64,
    /// Distance of the integrated state from its nearest point on N (issue 11).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance_from_n: Option<f64>,
    /// |X_Φ| at the integrated state (the regular, integral-derived departure from N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_phi: Option<f64>,
    /// Distance of that nearest point from the exact state (drift along N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub along_n: Option<f64>,
    /// Phase errors ψ₁, ψ₂ of the nearest point against the exact angles (radians).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_error_psi1: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_error_psi2: Option<f64>,
}

/// One sample of a comparison. `t` is the motion time in seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub t: f64,
    pub exact: Option<BodyState>,
    pub integrated: Option<BodyState>,
    pub errors: Option<ErrorSample>,
}

/// Writer options.
#[derive(Debug, Clone)]
pub struct LogOptions {
    /// Target uncompressed chunk size in bytes. Small chunks lose little when a run is
    /// killed (only the open chunk is lost); default 64 KiB ≈ 20 samples.
    pub chunk_size: u64,
    /// zstd level (0 = zstd default).
    pub compression_level: u32,
}

impl Default for LogOptions {
    fn default() -> Self {
        LogOptions {
            chunk_size: 64 * 1024,
            compression_level: 0,
        }
    }
}

/// Converts motion time in seconds to MCAP nanoseconds: round(t · 10⁹).
pub fn time_to_ns(t: f64) -> Result<u64, LogError> {
    // 1.8e10 s · 1e9 < u64::MAX ≈ 1.8447e19.
    if !(t.is_finite() && (0.0..1.8e10).contains(&t)) {
        return Err(LogError::BadTime(t));
    }
    Ok((t * 1e9).round() as u64)
}

pub(crate) fn stamp(ns: u64) -> Value {
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

/// Which motion a track belongs to.
#[derive(Debug, Clone, Copy)]
enum Motion {
    Exact,
    Integrated,
}

impl Motion {
    fn body_frame(self) -> &'static str {
        match self {
            Motion::Exact => topics::FRAME_BODY_EXACT,
            Motion::Integrated => topics::FRAME_BODY_INTEGRATED,
        }
    }
    fn color(self) -> Value {
        match self {
            Motion::Exact => json!({"r": 0.2, "g": 0.55, "b": 1.0, "a": 1.0}),
            Motion::Integrated => json!({"r": 1.0, "g": 0.45, "b": 0.1, "a": 1.0}),
        }
    }
}

/// One incremental hodograph curve (one topic).
struct Hodograph {
    channel: u16,
    frame_id: &'static str,
    motion: Motion,
    /// Frame-locked: the moving hodograph is drawn in the body frame and moves with it.
    frame_locked: bool,
    last: Option<[f64; 3]>,
    segments: u64,
}

impl Hodograph {
    /// The SceneUpdate for a new point: a 2-point LINE_STRIP from the previous point (a new
    /// entity with a unique id and no lifetime, so the curve accumulates) and the arrow of
    /// the current vector (fixed id `current`, replaced every time).
    fn update(&mut self, ns: u64, p: [f64; 3]) -> Value {
        let color = self.motion.color();
        let identity = json!({"position": {"x": 0.0, "y": 0.0, "z": 0.0},
                              "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}});
        let mut entities = Vec::with_capacity(2);
        if let Some(prev) = self.last {
            self.segments += 1;
            entities.push(entity(
                ns,
                self.frame_id,
                &format!("seg{}", self.segments),
                self.frame_locked,
                vec![],
                vec![json!({
                    "type": 0,
                    "pose": identity,
                    "thickness": 2.0,
                    "scale_invariant": true,
                    "points": [point(prev), point(p)],
                    "color": color,
                    "colors": [],
                    "indices": []
                })],
            ));
        }
        self.last = Some(p);
        let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let len = if len.is_finite() { len } else { 0.0 };
        let head = 0.15 * len;
        entities.push(entity(
            ns,
            self.frame_id,
            "current",
            self.frame_locked,
            vec![json!({
                "pose": {"position": {"x": 0.0, "y": 0.0, "z": 0.0},
                         "orientation": Quaternion::x_axis_to(p)},
                "shaft_length": len - head,
                "shaft_diameter": 0.02 * len,
                "head_length": head,
                "head_diameter": 0.06 * len,
                "color": color
            })],
            vec![],
        ));
        json!({"deletions": [], "entities": entities})
    }
}

fn point(p: [f64; 3]) -> Value {
    json!({"x": p[0], "y": p[1], "z": p[2]})
}

fn entity(
    ns: u64,
    frame_id: &str,
    id: &str,
    frame_locked: bool,
    arrows: Vec<Value>,
    lines: Vec<Value>,
) -> Value {
    json!({
        "timestamp": stamp(ns),
        "frame_id": frame_id,
        "id": id,
        "lifetime": {"sec": 0, "nsec": 0},
        "frame_locked": frame_locked,
        "metadata": [],
        "arrows": arrows,
        "cubes": [],
        "spheres": [],
        "cylinders": [],
        "lines": lines,
        "triangles": [],
        "texts": [],
        "models": []
    })
}

struct Channels {
    tf: u16,
    exact_state: u16,
    integrated_state: u16,
    errors: u16,
    hodographs: [Hodograph; 4],
}

/// Size counters of a log.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct LogStats {
    /// Samples logged.
    pub samples: u64,
    /// Messages written (including the `/metadata` message).
    pub messages: u64,
    /// Sum of the uncompressed message payload sizes in bytes.
    pub payload_bytes: u64,
}

/// An MCAP log of one comparison. See `docs/mcap.md` for the channel layout.
///
/// The file is written whole or not at all ([`rsts_io::AtomicFile`]): everything goes to a
/// temporary beside the target, and [`finish`](Self::finish) renames it into place. Until then
/// an existing file at the path is untouched; dropping the log without `finish` (a failed run)
/// removes the temporary, and so does [`rsts_io::remove_temporaries`] (a second Ctrl-C). A run
/// stopped early on purpose (the first Ctrl-C caught by the CLI) calls `finish` and so leaves a
/// complete, indexed file of what it logged.
pub struct TrajectoryLog {
    pub(crate) writer: Option<mcap::Writer<AtomicFile>>,
    /// The first write error, repeated by every later call.
    failed: Option<String>,
    path: PathBuf,
    ch: Channels,
    sequence: BTreeMap<u16, u32>,
    last_t: Option<f64>,
    stats: LogStats,
}

impl TrajectoryLog {
    /// Starts writing `path` with the default [`LogOptions`] and writes the metadata (the file
    /// appears at `path` when [`finish`](Self::finish)ed).
    pub fn create(path: impl AsRef<Path>, metadata: &Metadata) -> Result<Self, LogError> {
        Self::create_with_options(path, metadata, &LogOptions::default())
    }

    /// Starts writing `path` (a temporary beside it until [`finish`](Self::finish)) and writes
    /// the schemas, channels and metadata.
    pub fn create_with_options(
        path: impl AsRef<Path>,
        metadata: &Metadata,
        options: &LogOptions,
    ) -> Result<Self, LogError> {
        let path = path.as_ref().to_path_buf();
        let file = AtomicFile::create(&path).map_err(|source| LogError::Create {
            path: path.clone(),
            source,
        })?;
        let opts = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(options.compression_level)
            .compression_threads(0)
            .chunk_size(Some(options.chunk_size.max(1)))
            .profile("")
            .library(format!("rsts-mcap/{}", env!("CARGO_PKG_VERSION")));
        let mut w = opts.create(file)?;

        // The metadata record goes first, before any schema or channel: a Metadata record
        // closes the open chunk, and a chunk holding only schemas and channels has no message
        // index, which @mcap/core 2.1.0 (Foxglove Studio 1.x) rejects; today's 2.2.2 reads it.
        // Schemas and channels then share the first chunk with the first messages.
        w.write_metadata(&mcap::records::Metadata {
            name: topics::METADATA_RECORD_NAME.into(),
            metadata: metadata.to_record_map(),
        })?;
        let tf_s = w.add_schema(
            schemas::FRAME_TRANSFORM_NAME,
            "jsonschema",
            schemas::FRAME_TRANSFORM.as_bytes(),
        )?;
        let su_s = w.add_schema(
            schemas::SCENE_UPDATE_NAME,
            "jsonschema",
            schemas::SCENE_UPDATE.as_bytes(),
        )?;
        let st_s = w.add_schema(
            schemas::BODY_STATE_NAME,
            "jsonschema",
            schemas::BODY_STATE.as_bytes(),
        )?;
        let er_s = w.add_schema(
            schemas::ERRORS_NAME,
            "jsonschema",
            schemas::ERRORS.as_bytes(),
        )?;
        let md_s = w.add_schema(
            schemas::METADATA_NAME,
            "jsonschema",
            schemas::METADATA.as_bytes(),
        )?;
        let none = BTreeMap::new();
        let md_c = w.add_channel(md_s, topics::METADATA, "json", &none)?;
        let tf = w.add_channel(tf_s, topics::TF, "json", &none)?;
        let exact_state = w.add_channel(st_s, topics::EXACT_STATE, "json", &none)?;
        let integrated_state = w.add_channel(st_s, topics::INTEGRATED_STATE, "json", &none)?;
        let errors = w.add_channel(er_s, topics::ERRORS, "json", &none)?;
        let mut hodo = |topic: &str, frame_id: &'static str, motion, frame_locked| {
            w.add_channel(su_s, topic, "json", &none)
                .map(|channel| Hodograph {
                    channel,
                    frame_id,
                    motion,
                    frame_locked,
                    last: None,
                    segments: 0,
                })
        };
        let hodographs = [
            hodo(
                topics::EXACT_HODOGRAPH_MOVING,
                topics::FRAME_BODY_EXACT,
                Motion::Exact,
                true,
            )?,
            hodo(
                topics::EXACT_HODOGRAPH_FIXED,
                topics::FRAME_WORLD,
                Motion::Exact,
                false,
            )?,
            hodo(
                topics::INTEGRATED_HODOGRAPH_MOVING,
                topics::FRAME_BODY_INTEGRATED,
                Motion::Integrated,
                true,
            )?,
            hodo(
                topics::INTEGRATED_HODOGRAPH_FIXED,
                topics::FRAME_WORLD,
                Motion::Integrated,
                false,
            )?,
        ];
        let mut log = TrajectoryLog {
            writer: Some(w),
            failed: None,
            path,
            ch: Channels {
                tf,
                exact_state,
                integrated_state,
                errors,
                hodographs,
            },
            sequence: BTreeMap::new(),
            last_t: None,
            stats: LogStats::default(),
        };
        log.write_json(md_c, 0, &serde_json::to_value(metadata)?)?;
        Ok(log)
    }

    /// The path of the file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Counters of what was written so far.
    pub fn stats(&self) -> LogStats {
        self.stats
    }

    /// The first error again, if a write failed before.
    fn check_failed(&self) -> Result<(), LogError> {
        match &self.failed {
            Some(first) => Err(LogError::Failed(first.clone())),
            None => Ok(()),
        }
    }

    /// Remember the first error of a write.
    pub(crate) fn fail(&mut self, e: LogError) -> LogError {
        let text = rsts_io::error_text(&e);
        self.failed.get_or_insert(text.clone());
        LogError::Failed(text)
    }

    pub(crate) fn write_json(
        &mut self,
        channel: u16,
        ns: u64,
        value: &Value,
    ) -> Result<(), LogError> {
        self.check_failed()?;
        let data = serde_json::to_vec(value)?;
        let w = self.writer.as_mut().ok_or(LogError::Finished)?;
        let seq = self.sequence.entry(channel).or_insert(0);
        *seq += 1;
        let written = w.write_to_known_channel(
            &MessageHeader {
                channel_id: channel,
                sequence: *seq,
                log_time: ns,
                publish_time: ns,
            },
            &data,
        );
        if let Err(e) = written {
            return Err(self.fail(e.into()));
        }
        self.stats.messages += 1;
        self.stats.payload_bytes += data.len() as u64;
        Ok(())
    }

    /// Logs one sample (log and publish time = round(t · 10⁹) ns). Samples must come in
    /// non-decreasing `t`. Writes, for each motion present: a `FrameTransform` on `/tf`, its
    /// state on `/exact/state` or `/integrated/state`, one new segment of each hodograph;
    /// and the errors with their `log10_…` companions on `/errors` when present.
    pub fn log_sample(&mut self, sample: &Sample) -> Result<(), LogError> {
        if self.writer.is_none() {
            return Err(LogError::Finished);
        }
        let ns = time_to_ns(sample.t)?;
        if let Some(previous) = self.last_t {
            if sample.t < previous {
                return Err(LogError::TimeNotMonotonic {
                    t: sample.t,
                    previous,
                });
            }
        }
        self.last_t = Some(sample.t);
        for (motion, state) in [
            (Motion::Exact, &sample.exact),
            (Motion::Integrated, &sample.integrated),
        ] {
            let Some(s) = state else { continue };
            let quat = Quaternion::from_orientation(&s.q);
            let tf = json!({
                "timestamp": stamp(ns),
                "parent_frame_id": topics::FRAME_WORLD,
                "child_frame_id": motion.body_frame(),
                "translation": {"x": 0.0, "y": 0.0, "z": 0.0},
                "rotation": quat
            });
            self.write_json(self.ch.tf, ns, &tf)?;
            let state_channel = match motion {
                Motion::Exact => self.ch.exact_state,
                Motion::Integrated => self.ch.integrated_state,
            };
            let st = json!({
                "t": sample.t,
                "alpha": s.q[0],
                "beta": s.q[1],
                "gamma": s.q[2],
                "quaternion": quat,
                "omega": s.omega,
                "omega_fixed": s.omega_fixed,
                "h": s.h,
                "k": s.k,
                "g": s.g
            });
            self.write_json(state_channel, ns, &st)?;
            let (moving, fixed) = match motion {
                Motion::Exact => (0, 1),
                Motion::Integrated => (2, 3),
            };
            for (i, p) in [(moving, s.omega), (fixed, s.omega_fixed)] {
                let msg = self.ch.hodographs[i].update(ns, p);
                let channel = self.ch.hodographs[i].channel;
                self.write_json(channel, ns, &msg)?;
            }
        }
        if let Some(e) = &sample.errors {
            let mut v = serde_json::to_value(e)?;
            if let Value::Object(m) = &mut v {
                // log10 |x| beside every error and drift, where it is defined.
                let logs: Vec<(String, Value)> = m
                    .iter()
                    .filter_map(|(name, x)| {
                        let a = x.as_f64()?.abs();
                        (a.is_finite() && a > 0.0)
                            .then(|| (schemas::log10_field(name), json!(a.log10())))
                    })
                    .collect();
                m.extend(logs);
                m.insert("t".into(), json!(sample.t));
            }
            self.write_json(self.ch.errors, ns, &v)?;
        }
        self.stats.samples += 1;
        Ok(())
    }

    /// Ends the open chunk and flushes it to the OS, so everything logged so far survives
    /// a killed process. Costs a little compression; call it e.g. every few seconds.
    pub fn flush(&mut self) -> Result<(), LogError> {
        self.check_failed()?;
        let w = self.writer.as_mut().ok_or(LogError::Finished)?;
        if let Err(e) = w.flush() {
            return Err(self.fail(e.into()));
        }
        Ok(())
    }

    /// Writes the summary section and footer and renames the file into place.
    pub fn finish(mut self) -> Result<LogStats, LogError> {
        self.check_failed()?;
        let mut w = self.writer.take().ok_or(LogError::Finished)?;
        w.finish()?;
        w.into_inner().commit()?;
        Ok(self.stats)
    }
}
