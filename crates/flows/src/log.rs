//! The MCAP log of a comparison or a check (`--mcap`; docs/mcap.md): every sample's exact and
//! integrated states and its errors, the events as marks. The file appears at its path only
//! when the log is finished ([`McapLog::finish`]); a failed run drops it and leaves any
//! previous file; a run stopped on purpose finishes it (a complete file of what was done).

use std::path::{Path, PathBuf};

use serde::Serialize;

use rsts_harness::events::EventMatchReport;
use rsts_harness::{Observer, SampleRecord, StateSnapshot};
use rsts_mcap::{BodyState, ErrorSample, EventMark, LogStats, Metadata, Sample, TrajectoryLog};

use crate::FlowError;

/// Bytes an MCAP log takes per sample (measured: 2000 samples of the default case, 2.44 MB).
pub const MCAP_BYTES_PER_SAMPLE: f64 = 1300.0;

/// Largest size of one output file (2 GiB): a run whose log would be larger is refused before
/// it starts.
pub const MAX_OUTPUT_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Where a flow logs to: the path, and what the face knows of the integrator beyond the
/// flow's request (an `--exec` command as the user wrote it).
#[derive(Clone, Debug, PartialEq)]
pub struct Mcap {
    pub path: PathBuf,
    /// The external integrator's command line, recorded in the log's metadata.
    pub command: Option<String>,
}

impl Mcap {
    /// A log at `path`.
    pub fn at(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            command: None,
        }
    }
}

/// An output error naming the path: `PATH: why`.
fn output_error(path: &Path, e: &(dyn std::error::Error + 'static)) -> FlowError {
    FlowError::Output {
        output: "mcap",
        message: format!("{}: {}", path.display(), rsts_io::error_text(e)),
    }
}

/// Refuse a log of `samples` samples larger than [`MAX_OUTPUT_BYTES`] (naming `option`, the
/// input that sets its size), a log that is or holds one of the `inputs` (named as the request
/// names them: writing it would destroy the input), and a path that cannot be written, before
/// any work.
pub(crate) fn check_log(
    path: &Path,
    samples: Option<usize>,
    option: &'static str,
    inputs: &[(&'static str, &Path)],
) -> Result<(), FlowError> {
    if let Some(n) = samples {
        let bytes = MCAP_BYTES_PER_SAMPLE * n as f64;
        if bytes > MAX_OUTPUT_BYTES {
            return Err(FlowError::input(
                &[option],
                format!(
                    "the MCAP log would take about {} bytes, more than the {} bytes (2 GiB) one output file may have; ask for less",
                    rsts_dynamics::short(bytes),
                    rsts_dynamics::short(MAX_OUTPUT_BYTES)
                ),
            ));
        }
    }
    if let Err(e) = rsts_io::check_outputs(inputs, &[rsts_io::Output::File("mcap", path)]) {
        let mut names = vec!["mcap"];
        names.extend(inputs.iter().map(|(name, _)| *name));
        names.dedup();
        return Err(FlowError::input(&names, rsts_io::error_text(&e)));
    }
    rsts_io::check_writable(path).map_err(|e| output_error(path, &e))
}

/// An MCAP log being written.
pub struct McapLog {
    log: TrajectoryLog,
}

impl McapLog {
    /// Create the log `path` (its directory too) with the case and the integrator as metadata.
    pub fn create(
        path: &Path,
        case: &impl Serialize,
        integrator: &impl Serialize,
    ) -> Result<Self, FlowError> {
        let meta = Metadata::new(
            concat!("rsts ", env!("CARGO_PKG_VERSION")),
            case,
            integrator,
        )
        .map_err(|e| output_error(path, &e))?;
        let log = TrajectoryLog::create(path, &meta).map_err(|e| output_error(path, &e))?;
        Ok(Self { log })
    }

    /// Mark the events matched (exact and detected times) on the log's event channel.
    pub fn mark_events(&mut self, events: &EventMatchReport) -> Result<(), FlowError> {
        let marks: Vec<EventMark> = events
            .per_event
            .iter()
            .map(|p| EventMark {
                name: p.name.clone(),
                t_exact: p.t_exact,
                t_detected: p.t_detected,
                time_error: p.time_error,
            })
            .collect();
        let path = self.log.path().to_path_buf();
        self.log
            .log_events(&marks)
            .map_err(|e| output_error(&path, &e))
    }

    /// Write the index and move the file to its path.
    pub fn finish(self) -> Result<LogStats, FlowError> {
        let path = self.log.path().to_path_buf();
        self.log.finish().map_err(|e| output_error(&path, &e))
    }
}

/// A logged value, absent when not finite (no nearest point on N was found).
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

fn body(s: &StateSnapshot) -> BodyState {
    BodyState {
        q: s.q,
        omega: s.omega,
        omega_fixed: s.omega_fixed,
        h: s.h,
        k: s.k,
        g: s.g,
    }
}

/// An observer that logs every sample to an MCAP log (when there is one) and hands it on to
/// the face's observer (progress, Ctrl-C), which also decides when to stop.
pub(crate) struct Logged<'a, O: Observer + ?Sized> {
    pub(crate) log: Option<McapLog>,
    inner: &'a mut O,
}

impl<'a, O: Observer + ?Sized> Logged<'a, O> {
    pub(crate) fn new(log: Option<McapLog>, inner: &'a mut O) -> Self {
        Self { log, inner }
    }

    /// Finish the log (its file appears), if there is one.
    pub(crate) fn finish(&mut self) -> Result<Option<LogStats>, FlowError> {
        self.log.take().map(McapLog::finish).transpose()
    }
}

impl<O: Observer + ?Sized> Observer for Logged<'_, O> {
    fn wants_states(&self) -> bool {
        self.log.is_some() || self.inner.wants_states()
    }

    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        if let Some(McapLog { log }) = &mut self.log {
            let e = &r.errors;
            log.log_sample(&Sample {
                t: r.t,
                exact: Some(body(&r.exact)),
                integrated: Some(body(&r.integrated)),
                errors: Some(ErrorSample {
                    state_error: e.state_error,
                    orientation_error: e.orientation_error,
                    drift_h: e.drift_h,
                    drift_k: e.drift_k,
                    drift_g: e.drift_g,
                    constraint_drift: e.constraint_drift,
                    off_n: e.off_n,
                    distance_from_n: finite(e.distance_from_n),
                    x_phi: finite(e.x_phi),
                    along_n: finite(e.along_n),
                    phase_error_psi1: finite(e.phase_error[0]),
                    phase_error_psi2: finite(e.phase_error[1]),
                }),
            })
            .map_err(|e| format!("writing the MCAP file: {}", rsts_io::error_text(&e)))?;
        }
        self.inner.on_sample(r)
    }

    fn should_stop(&self) -> bool {
        self.inner.should_stop()
    }
}
