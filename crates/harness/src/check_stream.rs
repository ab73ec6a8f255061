//! A check fed in chunks (`rsts check` streams its input): the samples of each chunk are
//! analysed in parallel and folded into the running summaries of [`crate::Analysis`], then
//! dropped, so memory does not grow with the number of samples. What the summaries keep is
//! bounded whatever the length (docs/output.md, "What a check keeps"): maxima and last values,
//! the correct-digit extremes, the drifts' running maxima at log-spaced times, the geometry's
//! series decimated to at most 2¹⁶ points, the first sample's error and the time span.

use rug::Float;

use rsts_dynamics::state::DIM;
use rsts_dynamics::State;

use crate::analysis::{Analysis, Observer};
use crate::check::{Check, CheckReport, CheckedCase};
use crate::metrics::SampleErrors;
use crate::HarnessError;

/// A check under way, fed its samples chunk after chunk ([`CheckStream::feed`]).
pub struct CheckStream {
    check: Check,
    start_error: Option<f64>,
    /// The first sample (time, state), for the start-offset verdict.
    first: Option<(Float, State<Float>)>,
    span: (f64, f64),
    given: usize,
    stopped: bool,
}

impl CheckStream {
    /// The samples of `check` come next.
    pub fn new(check: Check) -> Self {
        Self {
            check,
            start_error: None,
            first: None,
            span: (f64::NAN, f64::NAN),
            given: 0,
            stopped: false,
        }
    }

    /// The motion the trajectory is checked against.
    pub fn case(&self) -> &CheckedCase {
        &self.check.case
    }

    /// Samples fed so far.
    pub fn samples_given(&self) -> usize {
        self.given
    }

    /// Analyse the next samples (time order, after those fed before), evaluated in parallel
    /// on the current rayon pool and recorded in order. False when the observer asked to stop:
    /// nothing more is analysed (the report says `complete: false`).
    pub fn feed(
        &mut self,
        times: &[Float],
        states: &[State<Float>],
        observer: &mut dyn Observer,
    ) -> Result<bool, HarnessError> {
        // f64 data given as MPFR numbers (the Python face, a library caller) takes the path of
        // f64 data: the report is the CLI's, bit for bit.
        if self.check.analysis.measures_in_dd() {
            if let Some((t, s)) = exactly_f64(times, states) {
                return self.feed_f64(&t, &s, observer);
            }
        }
        if self.first.is_none() {
            let bits = self.check.analysis.bits();
            self.first = times.first().zip(states.first()).map(|(t, x)| {
                (
                    Float::with_val(bits, t),
                    x.map(|v| Float::with_val(bits, v)),
                )
            });
        }
        let span = times.first().zip(times.last());
        let span = span.map(|(a, b)| (a.to_f64(), b.to_f64()));
        let reach = times.iter().fold(0.0, |m: f64, t| m.max(t.to_f64().abs()));
        self.feed_with(span, times.len(), states.len(), reach, |analysis| {
            analysis.sample_all(times, states, observer)
        })
    }

    /// [`CheckStream::feed`] of f64 samples (times, states ω, α, β), analysed in double-double
    /// without MPFR numbers ([`crate::Analysis::sample_all_f64`]).
    pub fn feed_f64(
        &mut self,
        times: &[f64],
        states: &[[f64; DIM]],
        observer: &mut dyn Observer,
    ) -> Result<bool, HarnessError> {
        if self.first.is_none() {
            self.first = times.first().zip(states.first()).map(|(t, x)| {
                let bits = self.check.analysis.bits();
                (
                    Float::with_val(bits, t),
                    State::from_slice(x).map(|v| Float::with_val(bits, v)),
                )
            });
        }
        let span = times.first().zip(times.last()).map(|(a, b)| (*a, *b));
        let reach = times.iter().fold(0.0, |m: f64, t| m.max(t.abs()));
        self.feed_with(span, times.len(), states.len(), reach, |analysis| {
            analysis.sample_all_f64(times, states, observer)
        })
    }

    /// Feed `n` samples spanning `span` (`None`: none), |t| ≤ `reach`, analysed by `run`.
    fn feed_with(
        &mut self,
        span: Option<(f64, f64)>,
        n: usize,
        n_states: usize,
        reach: f64,
        run: impl FnOnce(&mut Analysis) -> Result<Option<SampleErrors>, HarnessError>,
    ) -> Result<bool, HarnessError> {
        if n != n_states {
            return Err(HarnessError::Data(format!(
                "{n} times and {n_states} states"
            )));
        }
        let Some((first, last)) = span else {
            return Ok(!self.stopped);
        };
        let first_feed = self.given == 0;
        if first_feed {
            self.span.0 = first;
        }
        self.span.1 = last;
        self.given += n;
        if self.stopped {
            return Ok(false);
        }
        let Check {
            analysis,
            reference,
            ..
        } = &mut self.check;
        analysis.reach(reference, reach)?;
        let errors = run(analysis)?;
        if first_feed {
            self.start_error = errors.map(|e| e.state_error);
        }
        self.stopped = !analysis.report().complete;
        Ok(!self.stopped)
    }

    /// The report of the samples fed.
    pub fn finish(self) -> CheckReport {
        let Check {
            file,
            case,
            distance,
            analysis,
            ..
        } = self.check;
        let start_state_error = self.start_error.unwrap_or(f64::NAN);
        let start_offset = self.first.as_ref().and_then(|(t0, x0)| {
            crate::check::StartOffset::judge(&case, start_state_error, t0, x0)
        });
        CheckReport {
            file,
            case,
            start_state_error,
            start_offset,
            start_distance_from_n: distance,
            report: analysis.finish(),
            span: self.span,
            samples_given: self.given,
        }
    }
}

/// The samples as f64 values when every time and state value is exactly an f64 (`None`
/// otherwise: wider data, NaN).
fn exactly_f64(times: &[Float], states: &[State<Float>]) -> Option<(Vec<f64>, Vec<[f64; DIM]>)> {
    let exact = |x: &Float| {
        let v = x.to_f64();
        (*x == v).then_some(v)
    };
    let t = times.iter().map(exact).collect::<Option<Vec<f64>>>()?;
    let s = states
        .iter()
        .map(|s| {
            let a = s.to_array();
            let mut out = [0.0; DIM];
            for (o, x) in out.iter_mut().zip(a.iter()) {
                *o = exact(x)?;
            }
            Some(out)
        })
        .collect::<Option<Vec<_>>>()?;
    Some((t, s))
}
