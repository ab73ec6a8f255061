//! `check`: a trajectory computed elsewhere — a file (CSV, JSON, npy, the integrated channel of
//! an rsts MCAP log), a stream (standard input) or arrays — against the closed-form motion on
//! N, given or identified from the first sample, with the report of `compare`; the events the
//! integrator detected matched with the exact ones; logged to MCAP when asked (`rsts check`,
//! `rsts.check`).
//!
//! The samples are read and analysed a chunk at a time ([`CHUNK_ROWS`]), so memory does not
//! grow with their number, whatever the face: f64 data are read as f64 numbers and measured in
//! double-double, longer values exactly at their precision. A file is read in one pass as f64
//! data, and again, surveyed, when a value turns out to have more than 17 digits (nothing is
//! reported before the analysis ends). The chunks, the threads (`jobs`) and the passes do not
//! change a digit of the report.

use std::io::Read;
use std::path::{Path, PathBuf};

use rug::Float;
use serde::Serialize;

use rsts_closed_form::events::{EventName, EventSpec};
use rsts_dynamics::State;
use rsts_external::stream::CHUNK_ROWS;
use rsts_external::{F64Chunk, FileFormat, RawTrajectory, RestF64, Survey, TrajectoryReader};
use rsts_harness::events::{exact_event_times, match_events, DetectedEvent, EventMatchReport};
use rsts_harness::{check_finite_report, Check, CheckMotion, CheckReport, CheckStream, Observer};
use rsts_mcap::LogStats;

use crate::log::{check_log, Logged, Mcap, McapLog};
use crate::{FlowError, Limits, Verdict};

/// Where the trajectory comes from.
pub enum Source {
    /// A file, its format by its extension: `.csv`, `.json`, `.npy`, `.mcap`.
    File(PathBuf),
    /// A stream of one format (standard input), read once.
    Stream {
        input: Box<dyn Read + Send>,
        format: FileFormat,
    },
    /// Samples in memory: times (strictly increasing) and the states (ω, α, β) at them, as
    /// f64 values (their exact binary values), read a chunk at a time where they are (a face's
    /// arrays are not copied whole); `name` is the report's `method`.
    Arrays {
        times: Vec<f64>,
        states: Box<dyn StateRows>,
        name: String,
    },
}

/// Rows of f64 states (ω, α, β) handed to the flow a chunk at a time: a `Vec`, or a face's
/// arrays read where they are (Python's numpy array).
pub trait StateRows: Send {
    /// Rows in all.
    fn rows(&self) -> usize;
    /// Rows `start..start + out.len()` into `out`.
    fn read(&mut self, start: usize, out: &mut [[f64; 9]]) -> Result<(), FlowError>;
}

impl StateRows for Vec<[f64; 9]> {
    fn rows(&self) -> usize {
        self.len()
    }
    fn read(&mut self, start: usize, out: &mut [[f64; 9]]) -> Result<(), FlowError> {
        out.copy_from_slice(&self[start..start + out.len()]);
        Ok(())
    }
}

/// Events an integrator detected, to be matched with the exact ones.
pub enum DetectedEvents {
    /// A file: CSV with columns `name` and `t`, or JSON `{"events": [{"name", "t"}]}`.
    File(PathBuf),
    /// Events in memory (time order).
    List(Vec<DetectedEvent>),
}

/// What to check.
pub struct CheckRequest {
    /// The motion given, or identified from the first sample on N of fields (a, b).
    pub motion: CheckMotion,
    pub source: Source,
    /// Decimal digits the data carry (default: 15 for f64 data, else those of the longest
    /// value); the reference is evaluated 64 bits beyond (at least 30 digits).
    pub digits: Option<u32>,
    /// The events the integrator detected, matched with the exact ones of the same names in
    /// (t_first, t_last] of the trajectory.
    pub events: Option<DetectedEvents>,
    /// Events also expected (names in the detected list are expected anyway).
    pub expect: Vec<EventSpec>,
    pub mcap: Option<Mcap>,
    /// Threads the samples are analysed on (`None`: those of the current rayon pool).
    pub jobs: Option<usize>,
    pub limits: Limits,
}

/// What a check found: the document of `rsts check --format json` and the verdict.
#[derive(Clone, Debug, Serialize)]
pub struct CheckOutcome {
    #[serde(flatten)]
    pub report: CheckReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mcap: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub events: Option<EventMatchReport>,
    #[serde(skip)]
    pub verdict: Verdict,
    #[serde(skip)]
    pub log: Option<LogStats>,
    /// Samples in the source when known before the end (`None`: a CSV stream).
    #[serde(skip)]
    pub rows: Option<usize>,
}

impl CheckOutcome {
    /// Why the check is not complete (it was stopped), if it is not.
    pub fn stopped(&self) -> Option<String> {
        (!self.report.report.complete).then(|| {
            let of = self.rows.map_or(String::new(), |n| format!(" of {n}"));
            format!(
                "checked {}{of} samples",
                self.report.report.samples_compared
            )
        })
    }
}

/// A face's observer of a check: an [`Observer`] (progress, Ctrl-C) told how many samples a
/// pass over the data has before it starts.
pub trait Progress: Observer {
    /// A pass over `samples` samples starts (`None`: not known before its end).
    fn start_pass(&mut self, samples: Option<usize>) {
        let _ = samples;
    }
}

/// The input and its first chunk, as f64 numbers (f64 data, analysed in double-double) or as
/// read (high-precision data).
enum First {
    F64(F64Chunk),
    Read(RawTrajectory),
}

/// How one pass over the input ended.
enum Pass {
    Done(Box<CheckOutcome>),
    /// A file read in one pass as f64 data has a longer value: read it again, surveyed.
    Again,
}

/// Refuse what can be refused before the data are read: limits, digits, the fields and the
/// motion given, the log's path, the detected events.
fn validate(request: &CheckRequest) -> Result<(), FlowError> {
    for (name, limit) in [
        ("max-error", request.limits.max_error),
        ("max-event-error", request.limits.max_event_error),
    ] {
        if let Some(e) = limit.filter(|e| *e < 0.0) {
            return Err(FlowError::input(
                &[name],
                format!("must be non-negative, got {e}"),
            ));
        }
    }
    if let Some(d) = request.digits {
        if !(1..=10_000).contains(&d) {
            return Err(FlowError::input(
                &["digits"],
                format!("must be between 1 and 10000, got {d}"),
            ));
        }
    }
    let (a, b) = request.motion.fields();
    rsts_dynamics::Fields::new(a.to_f64(), b.to_f64())
        .map_err(|e| FlowError::input(&["a", "b"], e.to_string()))?;
    Ok(())
}

/// Check a trajectory: see the module. `observer` sees every sample (progress, Ctrl-C); a check
/// it stops reports the samples checked (`complete: false`, the log finished).
pub fn check(
    request: CheckRequest,
    observer: &mut (dyn Progress + Send),
) -> Result<CheckOutcome, FlowError> {
    validate(&request)?;
    let CheckRequest {
        motion,
        source,
        digits,
        events,
        expect,
        mcap,
        jobs,
        limits,
    } = request;
    let (file, name) = match &source {
        Source::File(path) => (
            path.display().to_string(),
            path.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| path.display().to_string()),
        ),
        Source::Stream { .. } => ("<stdin>".to_string(), "<stdin>".to_string()),
        Source::Arrays { name, .. } => ("<arrays>".to_string(), name.clone()),
    };
    let mut harness_request = rsts_harness::CheckRequest {
        file,
        name,
        motion,
        digits: 15,
    };
    // The motion given is checked before the data are read.
    harness_request.validate()?;
    if let Some(log) = &mcap {
        let mut inputs = Vec::new();
        if let Source::File(path) = &source {
            inputs.push(("file", path.as_path()));
        }
        if let Some(DetectedEvents::File(path)) = &events {
            inputs.push(("events", path.as_path()));
        }
        check_log(&log.path, None, "mcap", &inputs)?;
    }
    let detected = match events {
        None => None,
        Some(DetectedEvents::List(list)) => Some(list),
        Some(DetectedEvents::File(path)) => Some(read_detected(&path)?),
    };
    let pool = match jobs {
        None => None,
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| {
                    FlowError::input(&["jobs"], format!("cannot start the threads: {e}"))
                })?,
        ),
    };
    let settings = Settings {
        digits,
        detected: detected.as_deref(),
        expect: &expect,
        mcap: mcap.as_ref(),
        limits: &limits,
    };
    let pool = pool.as_ref();
    let done = match source {
        Source::File(path) => {
            let mut one_pass = true;
            loop {
                let again = on(pool, || {
                    let opened = open_file(&path, one_pass)?;
                    pass(&mut harness_request, opened, &settings, &mut *observer)
                })?;
                match again {
                    Pass::Done(outcome) => break outcome,
                    Pass::Again if one_pass => one_pass = false,
                    Pass::Again => unreachable!("a surveyed file is read at its precision"),
                }
            }
        }
        Source::Stream { input, format } => {
            let done = on(pool, || {
                pass(
                    &mut harness_request,
                    open_stream(input, format)?,
                    &settings,
                    observer,
                )
            })?;
            match done {
                Pass::Done(outcome) => outcome,
                Pass::Again => unreachable!("a stream is not read again"),
            }
        }
        Source::Arrays { times, states, .. } => {
            let mut states = states;
            let done = on(pool, || {
                arrays(
                    &mut harness_request,
                    &times,
                    &mut *states,
                    &settings,
                    observer,
                )
            })?;
            match done {
                Pass::Done(outcome) => outcome,
                Pass::Again => unreachable!("arrays are not read again"),
            }
        }
    };
    Ok(*done)
}

/// `f` on the threads of `pool` (`None`: those of the current rayon pool).
fn on<R: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// What every pass needs besides its input.
struct Settings<'a> {
    digits: Option<u32>,
    detected: Option<&'a [DetectedEvent]>,
    expect: &'a [EventSpec],
    mcap: Option<&'a Mcap>,
    limits: &'a Limits,
}

/// The detected events of a file.
fn read_detected(path: &Path) -> Result<Vec<DetectedEvent>, FlowError> {
    let named = |e: &dyn std::fmt::Display| {
        FlowError::input(&["events"], format!("{}: {e}", path.display()))
    };
    rsts_harness::events::read_detected(path).map_err(|e| named(&e))
}

/// An input error of the reader (its message names the file and the place).
fn read_error(e: String) -> FlowError {
    FlowError::input(&[], e)
}

/// A file opened in one pass for f64 data ([`TrajectoryReader::open_f64`]) or surveyed first
/// ([`TrajectoryReader::open_surveyed`]), and its first chunk; `None`: a value of more than 17
/// digits in the first chunk of a file opened in one pass.
fn open_file(
    path: &Path,
    one_pass: bool,
) -> Result<Option<(TrajectoryReader, Survey, First)>, FlowError> {
    let open = match one_pass {
        true => TrajectoryReader::open_f64,
        false => TrajectoryReader::open_surveyed,
    };
    let (mut reader, mut survey) = open(path).map_err(read_error)?;
    if !survey.is_high_precision() {
        let mut first = F64Chunk::default();
        if !reader.next_chunk_f64(&mut first).map_err(read_error)? {
            return Err(FlowError::input(&[], "no samples"));
        }
        if first.long_at.is_some() && reader.reread_if_long() {
            return Ok(None);
        }
        survey.add_times(&first.times);
        return Ok(Some((reader, survey, First::F64(first))));
    }
    let first = reader
        .next_chunk()
        .map_err(read_error)?
        .ok_or_else(|| FlowError::input(&[], "no samples"))?;
    let first = First::Read(first);
    Ok(Some((reader, survey, first)))
}

/// A stream surveyed from its first chunk, and that chunk.
fn open_stream(
    input: Box<dyn Read + Send>,
    format: FileFormat,
) -> Result<Option<(TrajectoryReader, Survey, First)>, FlowError> {
    let mut reader = TrajectoryReader::from_reader(input, format, "<stdin>").map_err(read_error)?;
    let first = reader
        .next_chunk()
        .map_err(read_error)?
        .ok_or_else(|| FlowError::input(&[], "no samples"))?;
    let survey = reader.survey_of_first(&first);
    let first = if survey.is_high_precision() {
        First::Read(first)
    } else {
        First::F64(F64Chunk::of_raw(&first))
    };
    Ok(Some((reader, survey, first)))
}

/// The digits of the data: those asked, else those of the longest value (high-precision
/// data), else 15 (f64 data).
fn data_digits(asked: Option<u32>, survey: &Survey) -> u32 {
    match asked {
        Some(d) => d,
        None if survey.is_high_precision() => survey.digits as u32,
        None => 15,
    }
}

/// Start the check from the first sample (identifying the motion when it is not given) and
/// open the log.
fn start(
    request: &rsts_harness::CheckRequest,
    t0: &Float,
    state0: &State<Float>,
    extent: f64,
    mcap: Option<&Mcap>,
) -> Result<(CheckStream, Option<McapLog>), FlowError> {
    let start = Check::start(request, t0, state0, extent).map_err(|e| match request.motion {
        CheckMotion::Given(_) => FlowError::from(e),
        CheckMotion::Identify { .. } => FlowError::input(&[], e.to_string()),
    })?;
    let log = match mcap {
        None => None,
        Some(m) => {
            let meta = serde_json::json!({"method": "check", "file": request.file});
            Some(McapLog::create(&m.path, start.case(), &meta)?)
        }
    };
    Ok((CheckStream::new(start), log))
}

/// One pass over an input: the first chunk starts the check, the rest follow chunk after
/// chunk (the reference of a chunk evaluated in parallel, its samples recorded in order).
fn pass(
    request: &mut rsts_harness::CheckRequest,
    opened: Option<(TrajectoryReader, Survey, First)>,
    settings: &Settings<'_>,
    observer: &mut (dyn Progress + Send),
) -> Result<Pass, FlowError> {
    let Some((mut reader, survey, first)) = opened else {
        return Ok(Pass::Again);
    };
    let high = survey.is_high_precision();
    request.digits = data_digits(settings.digits, &survey);
    let bits = request.reference_bits();
    let (t0, state0) = match &first {
        First::F64(c) => {
            let wide = |x: &f64| Float::with_val(bits, *x);
            (
                wide(&c.times[0]),
                State::from_slice(&c.states[0].each_ref().map(wide)),
            )
        }
        First::Read(raw) => {
            let s = raw.to_samples_at(bits, high);
            (s.times[0].clone(), s.states[0].clone())
        }
    };
    let (mut stream, log) = start(request, &t0, &state0, survey.extent, settings.mcap)?;
    observer.start_pass(survey.rows);
    let mut logged = Logged::new(log, observer);
    let analysed = (|| -> Result<Option<Pass>, FlowError> {
        match first {
            First::F64(chunk) => {
                let more = stream.feed_f64(&chunk.times, &chunk.states, &mut logged)?;
                drop(chunk);
                if more {
                    let rest = rsts_external::check_rest_f64(&mut reader, &mut stream, &mut logged)
                        .map_err(read_error)?;
                    if let RestF64::HighPrecision(_) = rest {
                        return Ok(Some(Pass::Again));
                    }
                }
            }
            First::Read(raw) => {
                let samples = raw.to_samples_at(bits, high);
                drop(raw);
                let more = stream.feed(&samples.times, &samples.states, &mut logged)?;
                drop(samples);
                if more {
                    rsts_external::check_rest(&mut reader, &mut stream, bits, high, &mut logged)
                        .map_err(read_error)?;
                }
            }
        }
        Ok(None)
    })();
    // A failed check (or one read again) discards its log: the temporary is removed, a
    // previous file stays.
    if let Some(again) = analysed? {
        return Ok(again);
    }
    let mut report = stream.finish();
    // What the run cost is known only where the file states it (JSON `stats`).
    report.report.set_stated_stats(&reader.stated_stats());
    finish(report, survey.rows, logged, settings).map(|o| Pass::Done(Box::new(o)))
}

/// A check of arrays: f64 data, a chunk at a time, as a file's f64 data are checked (in
/// double-double at most 16 digits; at more, their exact values widened to the reference
/// precision a part at a time, [`rsts_harness::CheckStream::feed_f64`]).
fn arrays(
    request: &mut rsts_harness::CheckRequest,
    times: &[f64],
    states: &mut dyn StateRows,
    settings: &Settings<'_>,
    observer: &mut (dyn Progress + Send),
) -> Result<Pass, FlowError> {
    if times.len() != states.rows() {
        return Err(FlowError::input(
            &["times", "states"],
            format!("{} times and {} states", times.len(), states.rows()),
        ));
    }
    if times.is_empty() {
        return Err(FlowError::input(&["times"], "no samples to check"));
    }
    // Every value is checked before any is analysed (a pass of its own, a chunk at a time), as
    // a file's are while it is read.
    let mut chunk = vec![[0.0; 9]; CHUNK_ROWS.min(times.len())];
    for (k, t) in times.chunks(CHUNK_ROWS).enumerate() {
        let start = k * CHUNK_ROWS;
        let rows = &mut chunk[..t.len()];
        states.read(start, rows)?;
        if let Some(why) = array_states_error(start, t, rows) {
            return Err(FlowError::input(&["states"], why));
        }
    }
    states.read(0, &mut chunk[..1])?;
    let state0 = chunk[0];
    request.digits = settings.digits.unwrap_or(15);
    let bits = request.reference_bits();
    let wide = |x: &f64| Float::with_val(bits, *x);
    let extent = times.iter().fold(0.0, |m: f64, t| m.max(t.abs()));
    let state0 = State::from_slice(&state0.each_ref().map(wide));
    let (mut stream, log) = start(request, &wide(&times[0]), &state0, extent, settings.mcap)?;
    observer.start_pass(Some(times.len()));
    let mut logged = Logged::new(log, observer);
    // f64 data: the flow of a file's f64 rows, whatever the digits asked.
    for (k, t) in times.chunks(CHUNK_ROWS).enumerate() {
        let s = &mut chunk[..t.len()];
        states.read(k * CHUNK_ROWS, s)?;
        // Again as analysed (a face's arrays may have been changed since).
        if let Some(why) = array_states_error(k * CHUNK_ROWS, t, s) {
            return Err(FlowError::input(&["states"], why));
        }
        if !stream.feed_f64(t, s, &mut logged)? {
            break;
        }
    }
    let report = stream.finish();
    finish(report, Some(times.len()), logged, settings).map(|o| Pass::Done(Box::new(o)))
}

/// States given as arrays (by a face, a library caller, a Python integrator's answer), refused
/// as a file's values are ([`rsts_external::check_f64_states`]: not finite, or |x| > 10⁸): the
/// place of the first bad one — its row (0-based, as the arrays index it; `states` and `times`
/// start at row `first`) with the row's time, and its column — and why; `None` when every value
/// may be analysed.
pub fn array_states_error(first: usize, times: &[f64], states: &[[f64; 9]]) -> Option<String> {
    let bad = rsts_external::check_f64_states(states).err()?;
    let at = times
        .get(bad.row)
        .map_or(String::new(), |t| format!(" (t = {t})"));
    Some(format!(
        "row {}{at}, {}: {}",
        first + bad.row,
        rsts_external::COLUMNS[bad.column + 1],
        bad.why
    ))
}

/// The outcome of a check whose samples were all fed: the log finished, the report checked,
/// the events matched, the limits judged.
fn finish(
    report: CheckReport,
    rows: Option<usize>,
    mut logged: Logged<'_, impl Observer + ?Sized>,
    settings: &Settings<'_>,
) -> Result<CheckOutcome, FlowError> {
    let log = logged.finish()?;
    check_finite_report(&report.report)?;
    let events = match settings.detected {
        None => None,
        Some(found) => {
            let mut specs = settings.expect.to_vec();
            for d in found {
                if !specs.iter().any(|s| s.name == d.name) {
                    specs.push(EventSpec {
                        name: d.name,
                        direction: Default::default(),
                    });
                }
            }
            let exact =
                exact_event_times(&report.case.motion, &specs, report.span.0, report.span.1)
                    .map_err(|e| FlowError::input(&["events"], e.to_string()))?;
            Some(match_events(&exact, found))
        }
    };
    let mut reasons = Vec::new();
    if let Some(why) = events
        .as_ref()
        .zip(settings.limits.max_event_error)
        .and_then(|(ev, limit)| ev.counts.failure(limit))
    {
        reasons.push(format!("{}: {why}", report.file));
    }
    if let Some(limit) = settings.limits.max_error {
        let e = report.report.max_state_error;
        if e.is_nan() || e > limit {
            reasons.push(format!(
                "{}: max state error {e:.3e} exceeds --max-error {limit:e}",
                report.file
            ));
        }
    }
    if let (Some(offset), false) = (&report.start_offset, settings.limits.allow_start_offset) {
        reasons.push(format!(
            "{}: start offset {:.3e} (--allow-start-offset to report it without failing)",
            report.file, offset.error
        ));
    }
    Ok(CheckOutcome {
        report,
        mcap: settings.mcap.map(|m| m.path.display().to_string()),
        events,
        verdict: Verdict::from_reasons(reasons),
        log,
        rows,
    })
}

/// The names of the events detected, as specs to expect (for a face that lists them).
pub fn expected(names: &[EventName]) -> Vec<EventSpec> {
    names
        .iter()
        .map(|&name| EventSpec {
            name,
            direction: Default::default(),
        })
        .collect()
}
