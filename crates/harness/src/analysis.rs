//! Analysing a trajectory: samples (time, state) of any spacing against the closed-form motion,
//! whoever produced them (a built-in method, a user's integrator, an external process, a file).
//!
//! [`Analysis`] takes the samples one at a time (so a long run reports progress as it goes):
//! the per-sample errors are computed in one place ([`crate::metrics::sample_errors`]) and
//! summarised in one place ([`Report::absorb`]); every sample is handed to an [`Observer`] as a
//! [`SampleRecord`] (MCAP log, progress bar, series for fits). [`analyse`] runs it over a whole
//! trajectory.

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
use crate::metrics::{exact_state, sample_errors, Drift, ManifoldN, Report, SampleErrors};
use crate::{HarnessError, SampleRecord};

/// Receives the samples of an analysis as they are computed.
pub trait Observer {
    /// Called once per sample, in time order.
    fn on_sample(&mut self, _record: &SampleRecord) -> Result<(), String> {
        Ok(())
    }
    /// Checked between pieces of an integration and between samples of an analysis: true stops
    /// the run (the report then has `complete: false`).
    fn should_stop(&self) -> bool {
        false
    }
}

/// An observer that does nothing.
pub struct NoObserver;
impl Observer for NoObserver {}

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
            steps: 0,
            rejected_steps: 0,
            rhs_evals: 0,
            integration_seconds: 0.0,
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
        }
    }

    /// The motion of `case` (its a, b, m, h, torus and phases; not its grid) at `bits` bits.
    pub fn for_case(case: &Case, bits: u32, info: RunInfo) -> Result<Self, HarnessError> {
        let (motion, fields) = case.reference_motion(bits)?;
        Ok(Self::new(motion, fields, info))
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
        let exact = self.exact_state(t);
        let (mut errors, ex, int) = sample_errors(
            &self.fields,
            &self.n,
            &self.initial_integrals,
            &exact,
            state,
        );
        if let Some(g) = self
            .geometry
            .as_mut()
            .and_then(|geometry| geometry.sample(t, state, &exact, errors.state_error))
        {
            errors.distance_from_n = g.distance_from_n;
            errors.x_phi = g.x_phi;
            errors.along_n = g.along_n;
            errors.phase_error = g.phase_error.unwrap_or([f64::NAN; 2]);
        }
        let index = self.report.samples_compared;
        self.report.absorb(&errors);
        self.digits.sample(&exact, state);
        self.report.correct_digits = self.digits.summary();
        self.drifts.push(
            t.to_f64(),
            [
                errors.drift_h,
                errors.drift_k,
                errors.drift_g,
                errors.constraint_drift,
            ],
        );
        observer
            .on_sample(&SampleRecord {
                index,
                t: t.to_f64(),
                exact: ex,
                integrated: int,
                errors,
            })
            .map_err(HarnessError::Observer)?;
        Ok(errors)
    }

    /// Add the cost of (a piece of) the run.
    pub fn add_stats(&mut self, stats: &Stats) {
        self.report.add_stats(stats);
    }

    /// Add wall time measured around the integrator.
    pub fn add_wall_seconds(&mut self, seconds: f64) {
        *self.report.wall_seconds.get_or_insert(0.0) += seconds;
    }

    /// Report under another method name.
    pub fn rename(&mut self, method: String) {
        self.report.method = method;
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
}
