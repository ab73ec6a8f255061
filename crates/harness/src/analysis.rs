//! Analysing a trajectory: samples (time, state) of any spacing against the closed-form motion,
//! whoever produced them (a built-in method, a user's integrator, an external process, a file).
//!
//! [`Analysis`] takes the samples one at a time (so a long run reports progress as it goes):
//! the per-sample errors are computed in one place ([`crate::metrics::sample_errors`]) and
//! summarised in one place ([`Report::absorb`]); every sample is handed to an [`Observer`] as a
//! [`SampleRecord`] (MCAP log, progress bar, series for fits). [`analyse`] runs it over a whole
//! trajectory.

use rayon::prelude::*;
use rsts_closed_form::ExplicitMotion;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::integrators::Stats;
use rsts_dynamics::scalar::digits_for_bits;
use rsts_dynamics::{Fields, State};
use rug::Float;

use crate::case::Case;
use crate::digits::{CorrectDigits, DigitsTracker};
use crate::drift_growth::DriftSeries;
use crate::geometry::Geometry;
use crate::metrics::{
    exact_state, sample_errors, Drift, ManifoldN, Report, SampleErrors, StateSnapshot,
};
use crate::rounded_reference::DdReference;
use crate::{HarnessError, SampleRecord};
use rsts_dynamics::scalar::DoubleDouble;

mod f64_errors;
mod f64_samples;

/// Receives the samples of an analysis as they are computed.
pub trait Observer {
    /// Called once per sample, in time order.
    fn on_sample(&mut self, _record: &SampleRecord) -> Result<(), String> {
        Ok(())
    }
    /// False when the records' `exact` and `integrated` states are not looked at: they are then
    /// not computed (NaN, [`StateSnapshot::NAN`]), only the errors are.
    fn wants_states(&self) -> bool {
        true
    }
    /// Checked between pieces of an integration and between samples of an analysis: true stops
    /// the run (the report then has `complete: false`).
    fn should_stop(&self) -> bool {
        false
    }
}

/// An observer that does nothing.
pub struct NoObserver;
impl Observer for NoObserver {
    fn wants_states(&self) -> bool {
        false
    }
}

/// Who produced the trajectory, as the report shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct RunInfo {
    pub method: String,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// Decimal digits of the integrator's scalar (f64: 15) or of the data.
    pub digits: u32,
}

/// The closed-form motion a trajectory is measured against, and the report so far.
pub struct Analysis {
    motion: ExplicitMotion<Float>,
    fields: Fields<Float>,
    n: ManifoldN,
    /// H, K, G of the exact motion (at t = 0): the drifts are measured from them.
    initial_integrals: [Float; 3],
    bits: u32,
    report: Report,
    digits: DigitsTracker,
    drifts: DriftSeries,
    geometry: Option<Geometry>,
    /// The closed form in double-double, the reference of f64 data (digits ≤ 16).
    dd: Option<DdReference>,
    /// The constants of the measurement in double-double (with `dd`).
    dd_measure: Option<DdMeasure>,
    /// The record of the last sample, handed to the observer: kept from sample to sample, so
    /// that only what changes is written (no copy of NaN states per sample).
    last: SampleRecord,
    /// Whether `last` holds states (else they are NaN).
    last_has_states: bool,
}

/// Samples evaluated in parallel between two rounds of recording (memory: ~2 kB each).
const BATCH: usize = 4096;

/// f64 samples of a batch evaluated one after another by one thread: the samples of a chunk
/// may share work (a warm start from the sample before, several samples at once). The chunks
/// are fixed by the samples' places in the batch (and the batches by their places in the run),
/// so the report does not depend on the number of threads. (MPFR samples: chunks of one.)
pub(crate) const CHUNK: usize = 64;

/// A sample evaluated apart from the samples before it (the parallel part of
/// [`Analysis::sample`]).
struct Evaluated {
    /// The exact state at the reference precision, for the MPFR geometry ([`Geometry::sample`]
    /// computes it in time order); `None` for the f64 samples of [`Analysis::sample_all_f64`].
    exact: Option<Box<State<Float>>>,
    errors: SampleErrors,
    /// The relative and the mixed error of the correct digits ([`crate::digits`]).
    digits: (f64, f64),
    /// The exact and the integrated state as logged (when the observer wants them).
    snapshots: Option<Box<[StateSnapshot; 2]>>,
    geometry: Option<crate::geometry::SampleGeometry>,
}

/// Fields, N and the initial integrals rounded to double-double: the errors of f64 data are
/// measured in double-double (106 bits, 53 beyond the data; docs/closed-form.md).
struct DdMeasure {
    fields: Fields<DoubleDouble>,
    n: ManifoldN<DoubleDouble>,
    initial_integrals: [DoubleDouble; 3],
}

impl Analysis {
    /// Measure against `motion` (evaluated at the precision of its constants) in `fields`.
    pub fn new(motion: ExplicitMotion<Float>, fields: Fields<Float>, info: RunInfo) -> Self {
        let info_digits = info.digits;
        let c = &motion.constants;
        let bits = c.m.prec();
        let r4 = c.r2.clone() * &c.r2;
        let n = ManifoldN {
            k: r4.clone() * &c.m * &c.m,
            p2: c.p2.clone(),
            r4m: r4 * &c.m,
        };
        let digits = DigitsTracker::new(info.rtol, info.atol);
        let start = exact_state(&motion.at(&Float::with_val(bits, 0)));
        let i0 = integrals(&fields, &start);
        let report = Report {
            method: info.method,
            rtol: info.rtol,
            atol: info.atol,
            digits: info.digits,
            reference_digits: digits_for_bits(bits),
            camera: motion.camera.label().to_string(),
            samples_compared: 0,
            complete: true,
            max_state_error: 0.0,
            final_state_error: 0.0,
            max_orientation_error: 0.0,
            correct_digits: CorrectDigits::default(),
            drift: Drift::default(),
            steps: None,
            rejected_steps: None,
            rhs_evals: None,
            integration_seconds: None,
            wall_seconds: None,
            normal: None,
            phase_error: None,
            error_split: None,
        };
        // The geometry of the error in the integrator's precision; a motion that exists only
        // at the reference precision (within rounding of Σ) goes without it.
        let geometry = Geometry::new(&motion, info_digits).ok();
        Self {
            motion,
            fields,
            n,
            initial_integrals: [i0.h, i0.k, i0.g],
            bits,
            report,
            digits,
            drifts: DriftSeries::new(),
            geometry,
            dd: None,
            dd_measure: None,
            last: SampleRecord {
                index: 0,
                t: f64::NAN,
                exact: StateSnapshot::NAN,
                integrated: StateSnapshot::NAN,
                errors: SampleErrors::default(),
            },
            last_has_states: false,
        }
    }

    /// The motion of `case` (its a, b, m, h, torus and phases; not its grid) at `bits` bits.
    /// For data of at most 16 digits (f64) the samples that are f64 exactly are measured in
    /// double-double against the closed form in double-double ([`DdReference`];
    /// docs/closed-form.md: why that is exact enough), the others in MPFR.
    pub fn for_case(case: &Case, bits: u32, info: RunInfo) -> Result<Self, HarnessError> {
        let (motion, fields) = case.reference_motion(bits)?;
        let f64_data = info.digits <= 16;
        let mut analysis = Self::new(motion, fields, info);
        if f64_data {
            analysis.dd = DdReference::new(case, case.t_end_f64(), |t| {
                analysis.exact_state(&Float::with_val(bits, t)).to_array()
            });
            let d = DoubleDouble::from_float;
            let n = &analysis.n;
            analysis.dd_measure = Some(DdMeasure {
                fields: Fields {
                    a: d(&analysis.fields.a),
                    b: d(&analysis.fields.b),
                },
                n: ManifoldN {
                    k: d(&n.k),
                    p2: d(&n.p2),
                    r4m: d(&n.r4m),
                },
                initial_integrals: analysis.initial_integrals.clone().map(|x| d(&x)),
            });
        }
        Ok(analysis)
    }

    /// The exact state and the errors of an f64 sample (time and state f64 exactly) in
    /// double-double; `None` for other samples (or data of more than 16 digits).
    #[allow(clippy::type_complexity)]
    fn errors_dd(
        &self,
        t: &Float,
        state: &State<Float>,
        snapshots: bool,
    ) -> Option<(State<Float>, (SampleErrors, Option<[StateSnapshot; 2]>))> {
        let (dd, m) = (self.dd.as_ref()?, self.dd_measure.as_ref()?);
        let is_f64 = |x: &Float| x.to_f64() == *x;
        let mut all = state.omega.iter().chain(&state.alpha).chain(&state.beta);
        if !is_f64(t) || !all.all(is_f64) {
            return None;
        }
        let exact = dd.state(t.to_f64());
        let x = state.to_array().map(|v| v.to_f64());
        // The errors of `check`'s f64 path; the snapshots (when asked) from the general code.
        let [(errors, _)] = f64_errors::f64_sample_errors::<1>(
            &m.fields,
            &m.n,
            &m.initial_integrals,
            std::slice::from_ref(&exact),
            std::slice::from_ref(&x),
            self.digits.ratio(),
        );
        let snapshots = snapshots.then(|| {
            let x = State::from_slice(&x.map(DoubleDouble::from_f64_exact));
            let (_, s) = sample_errors(&m.fields, &m.n, &m.initial_integrals, &exact, &x, true);
            s.expect("asked for")
        });
        Some((exact.map(|v| v.to_float(self.bits)), (errors, snapshots)))
    }

    /// Keep the reference exact up to |t| = `t_max` (a stream's later times): when its phase
    /// clock is not valid that far, the motion of `case` is rebuilt with `t_end` twice `t_max`
    /// (the state at a time it was valid for does not change: the clock only gains bits).
    pub(crate) fn reach(&mut self, case: &mut Case, t_max: f64) -> Result<(), HarnessError> {
        let valid = |until: f64| until >= t_max;
        if t_max <= case.t_end_f64()
            || (valid(self.motion.valid_until())
                && self.dd.as_ref().is_none_or(|d| valid(d.valid_until())))
        {
            return Ok(());
        }
        case.t_end = rsts_closed_form::Decimal::from_f64((2.0 * t_max).min(f64::MAX))
            .map_err(|e| HarnessError::Case(format!("t: {e}")))?;
        let info = RunInfo {
            method: self.report.method.clone(),
            rtol: self.report.rtol,
            atol: self.report.atol,
            digits: self.report.digits,
        };
        let fresh = Self::for_case(case, self.bits, info)?;
        self.motion = fresh.motion;
        self.dd = fresh.dd;
        self.dd_measure = fresh.dd_measure;
        Ok(())
    }

    /// Precision of the reference.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    pub fn fields(&self) -> &Fields<Float> {
        &self.fields
    }

    pub fn motion(&self) -> &ExplicitMotion<Float> {
        &self.motion
    }

    /// The exact state at `t`.
    pub fn exact_state(&self, t: &Float) -> State<Float> {
        exact_state(&self.motion.at(t))
    }

    /// Compare one sample (the next in time order) with the closed form, add it to the report
    /// and hand it to `observer`.
    pub fn sample(
        &mut self,
        t: &Float,
        state: &State<Float>,
        observer: &mut dyn Observer,
    ) -> Result<SampleErrors, HarnessError> {
        let evaluated = self.evaluate(t, state, observer.wants_states());
        let recorded = self.record(t.to_f64(), Some((t, state)), &evaluated, observer);
        self.update_digits();
        recorded.map(|()| self.last.errors)
    }

    /// Analyse samples in time order as [`Analysis::sample`] does one by one, evaluating them
    /// in parallel batches on the current rayon pool (the report and the observer's records
    /// are the same). Stops (report `complete: false`) when the observer asks. Returns the
    /// errors of the first sample.
    pub fn sample_all(
        &mut self,
        times: &[Float],
        states: &[State<Float>],
        observer: &mut dyn Observer,
    ) -> Result<Option<SampleErrors>, HarnessError> {
        self.in_batches(
            times,
            states,
            observer,
            |me, ts, ss, wanted, out| {
                out.extend(ts.iter().zip(ss).map(|(t, s)| me.evaluate(t, s, wanted)));
            },
            |t, s| (t.to_f64(), Some((t, s))),
            1,
        )
    }

    /// Whether f64 data are measured in double-double ([`Analysis::sample_all_f64`] without
    /// widening them to MPFR): data of at most 16 digits.
    pub(crate) fn measures_in_dd(&self) -> bool {
        self.dd.is_some() && self.dd_measure.is_some()
    }

    /// The batch loop of [`Analysis::sample_all`] and [`Analysis::sample_all_f64`]: each batch
    /// evaluated in parallel, `chunk` samples at a time (`evaluate(self, times, states,
    /// snapshots, out)` appends one [`Evaluated`] per sample to `out`, in order), then recorded
    /// in time order (`place`: the sample's time in f64 and, for MPFR samples, the sample
    /// itself).
    fn in_batches<T: Sync, S: Sync>(
        &mut self,
        times: &[T],
        states: &[S],
        observer: &mut dyn Observer,
        evaluate: impl Fn(&Self, &[T], &[S], bool, &mut Vec<Evaluated>) + Sync,
        place: impl for<'a> Fn(&'a T, &'a S) -> (f64, Option<(&'a Float, &'a State<Float>)>),
        chunk: usize,
    ) -> Result<Option<SampleErrors>, HarnessError> {
        let mut first = None;
        // One buffer per chunk, kept for every batch (no allocation per batch).
        let mut evaluated: Vec<Vec<Evaluated>> = Vec::new();
        for (tc, sc) in times.chunks(BATCH).zip(states.chunks(BATCH)) {
            if observer.should_stop() {
                self.mark_incomplete();
                break;
            }
            let me = &*self;
            let wanted = observer.wants_states();
            let chunks = tc.len().div_ceil(chunk);
            evaluated.resize_with(chunks, Vec::new);
            evaluated[..chunks]
                .par_iter_mut()
                .zip(tc.par_chunks(chunk).zip(sc.par_chunks(chunk)))
                .for_each(|(out, (t, s))| {
                    out.clear();
                    evaluate(me, t, s, wanted, out);
                });
            // Recorded from where they were evaluated (not moved out).
            let all = evaluated[..chunks].iter().flatten();
            for ((t, s), ev) in tc.iter().zip(sc).zip(all) {
                if observer.should_stop() {
                    self.mark_incomplete();
                    self.update_digits();
                    return Ok(first);
                }
                let (time, sample) = place(t, s);
                self.record(time, sample, ev, observer)?;
                first.get_or_insert(self.last.errors);
            }
        }
        self.update_digits();
        Ok(first)
    }

    /// The report's correct digits from the samples recorded (after a call's last sample:
    /// not per sample, four logarithms each).
    pub(crate) fn update_digits(&mut self) {
        self.report.correct_digits = self.digits.summary();
    }

    /// What a sample's errors are, apart from the samples before it.
    fn evaluate(&self, t: &Float, state: &State<Float>, snapshots: bool) -> Evaluated {
        let (exact, (errors, snapshots)) = match self.errors_dd(t, state, snapshots) {
            Some(dd) => dd,
            None => {
                let exact = self.exact_state(t);
                let errors = sample_errors(
                    &self.fields,
                    &self.n,
                    &self.initial_integrals,
                    &exact,
                    state,
                    snapshots,
                );
                (exact, errors)
            }
        };
        let geometry = self
            .geometry
            .as_ref()
            .and_then(|g| g.evaluate(t, state, &exact));
        Evaluated {
            digits: crate::digits::sample_errors(&exact, state, self.digits.ratio()),
            exact: Some(Box::new(exact)),
            errors,
            snapshots: snapshots.map(Box::new),
            geometry,
        }
    }

    /// Add an evaluated sample (the next in time order, at time `t`; `mpfr`: its time and
    /// state at the reference precision, for the MPFR geometry) to the report and the observer
    /// (the record handed to it is kept in `last`).
    fn record(
        &mut self,
        t: f64,
        mpfr: Option<(&Float, &State<Float>)>,
        evaluated: &Evaluated,
        observer: &mut dyn Observer,
    ) -> Result<(), HarnessError> {
        let mut errors = evaluated.errors;
        let state_error = errors.state_error;
        let geometry = match (evaluated.geometry, self.geometry.as_mut()) {
            (Some(g), Some(geometry)) => {
                geometry.record(t, &g, state_error);
                Some(g)
            }
            (_, Some(geometry)) => match (mpfr, &evaluated.exact) {
                (Some((tm, state)), Some(exact)) => geometry.sample(tm, state, exact, state_error),
                // An f64 sample's geometry is always evaluated (it runs in f64).
                _ => None,
            },
            (_, None) => None,
        };
        if let Some(g) = geometry {
            errors.distance_from_n = g.distance_from_n;
            errors.x_phi = g.x_phi;
            errors.along_n = g.along_n;
            errors.phase_error = g.phase_error.unwrap_or([f64::NAN; 2]);
        }
        let index = self.report.samples_compared;
        self.report.absorb(&errors);
        self.digits.add(evaluated.digits);
        self.drifts.push(
            t,
            [
                errors.drift_h,
                errors.drift_k,
                errors.drift_g,
                errors.constraint_drift,
            ],
        );
        let record = &mut self.last;
        record.index = index;
        record.t = t;
        record.errors = errors;
        match &evaluated.snapshots {
            Some(s) => {
                [record.exact, record.integrated] = **s;
                self.last_has_states = true;
            }
            None if self.last_has_states => {
                [record.exact, record.integrated] = [StateSnapshot::NAN; 2];
                self.last_has_states = false;
            }
            None => {}
        }
        observer
            .on_sample(&self.last)
            .map_err(HarnessError::Observer)
    }

    /// Add the cost of (a piece of) the run.
    pub fn add_stats(&mut self, stats: &Stats) {
        self.report.add_stats(stats);
    }

    /// Forget the counts the run did not state ([`Report::forget_unstated`]).
    pub fn forget_unstated(&mut self, stated: &crate::StatedStats) {
        self.report.forget_unstated(stated);
    }

    /// Add wall time measured around the integrator.
    pub fn add_wall_seconds(&mut self, seconds: f64) {
        *self.report.wall_seconds.get_or_insert(0.0) += seconds;
    }

    /// Report under another method name.
    pub fn rename(&mut self, method: String) {
        self.report.method = method;
    }

    /// The digits the integrator states after its run (an external one's answer may say them).
    pub fn set_digits(&mut self, digits: u32) {
        self.report.digits = digits;
    }

    /// The run was stopped before its last sample.
    pub fn mark_incomplete(&mut self) {
        self.report.complete = false;
    }

    /// The report so far.
    pub fn report(&self) -> &Report {
        &self.report
    }

    /// The report with the growth fits and the split of the error (docs/stability.md).
    pub fn finish(self) -> Report {
        let mut report = self.report;
        report.drift.growth = Some(self.drifts.laws());
        if let Some(geometry) = self.geometry {
            let g = geometry.finish();
            report.normal = Some(g.normal);
            report.phase_error = Some(g.phase_error);
            report.error_split = g.error_split;
        }
        report
    }
}

/// Analyse a whole trajectory: `times` (absolute, any spacing) and `states`, one per time.
/// Stops early (report `complete: false`) when the observer asks.
pub fn analyse(
    mut analysis: Analysis,
    times: &[Float],
    states: &[State<Float>],
    observer: &mut dyn Observer,
) -> Result<Report, HarnessError> {
    if times.len() != states.len() {
        return Err(HarnessError::Case(format!(
            "{} times and {} states",
            times.len(),
            states.len()
        )));
    }
    for (t, s) in times.iter().zip(states) {
        if observer.should_stop() {
            analysis.mark_incomplete();
            break;
        }
        analysis.sample(t, s, observer)?;
    }
    Ok(analysis.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> RunInfo {
        RunInfo {
            method: "test".into(),
            rtol: None,
            atol: None,
            digits: 15,
        }
    }

    /// The exact motion itself has no error; a perturbation of one component by 1e-9 at one
    /// sample is reported as that sample's state error and as the maximum.
    #[test]
    fn exact_samples_have_no_error_and_a_perturbation_is_found() {
        let case = Case::default_i_plus();
        let analysis = Analysis::for_case(&case, 200, info()).unwrap();
        let times: Vec<Float> = [0.0, 0.7, 3.0, 10.5]
            .iter()
            .map(|&t| Float::with_val(200, t))
            .collect();
        let mut states: Vec<State<Float>> = times.iter().map(|t| analysis.exact_state(t)).collect();
        let exact = analyse(
            Analysis::for_case(&case, 200, info()).unwrap(),
            &times,
            &states,
            &mut NoObserver,
        )
        .unwrap();
        assert!(exact.max_state_error < 1e-55, "{:e}", exact.max_state_error);
        assert!(exact.drift.off_n < 1e-55);
        assert_eq!(exact.samples_compared, 4);
        assert_eq!(exact.camera, "I+");
        states[2].beta[1] += 1e-9;
        let off = analyse(analysis, &times, &states, &mut NoObserver).unwrap();
        assert!(
            (off.max_state_error - 1e-9).abs() < 1e-20,
            "{:e}",
            off.max_state_error
        );
        assert!(off.final_state_error < 1e-55);
        assert!(off.drift.constraints > 1e-10);
    }

    /// f64 data are measured in double-double (for_case, 15 digits) with the report of the
    /// measurement in MPFR (Analysis::new has no double-double) to 12 digits and more: errors
    /// of 1e-9 to 1e-16, drifts, orientation.
    #[test]
    fn f64_data_measured_in_double_double_as_in_mpfr() {
        let case = {
            let mut c = Case::default_i_plus();
            c.motion.m = rsts_closed_form::Decimal::from_f64(-0.7092).unwrap();
            c.motion.h = rsts_closed_form::Decimal::from_f64(1.5643).unwrap();
            c.motion.torus = 2;
            c.t_end = rsts_closed_form::Decimal::from_f64(50.0_f64).unwrap();
            c
        };
        let bits = 172;
        let dd = Analysis::for_case(&case, bits, info()).unwrap();
        assert!(dd.dd.is_some());
        let (motion, fields) = case.reference_motion(bits).unwrap();
        let mp = Analysis::new(motion, fields, info());
        let times: Vec<Float> = (0..200)
            .map(|k| Float::with_val(bits, 0.25 * k as f64))
            .collect();
        let states: Vec<State<Float>> = times
            .iter()
            .enumerate()
            .map(|(k, t)| {
                let s = dd.exact_state(t);
                s.map(|x| {
                    let wobble = 1e-9 * ((k as f64) * 0.37).sin() * (k as f64 / 200.0).powi(3);
                    Float::with_val(bits, x.to_f64() + wobble)
                })
            })
            .collect();
        let a = analyse(dd, &times, &states, &mut NoObserver).unwrap();
        let b = analyse(mp, &times, &states, &mut NoObserver).unwrap();
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());
        for (what, x, y) in [
            ("max_state_error", a.max_state_error, b.max_state_error),
            (
                "final_state_error",
                a.final_state_error,
                b.final_state_error,
            ),
            (
                "orientation",
                a.max_orientation_error,
                b.max_orientation_error,
            ),
            ("H", a.drift.h, b.drift.h),
            ("K", a.drift.k, b.drift.k),
            ("G", a.drift.g, b.drift.g),
            ("constraints", a.drift.constraints, b.drift.constraints),
            ("off_N", a.drift.off_n, b.drift.off_n),
        ] {
            assert!(close(x, y), "{what}: {x:e} (double-double) vs {y:e} (MPFR)");
        }
        assert!(a.max_state_error > 1e-10 && a.max_state_error < 1e-8);
    }
}
