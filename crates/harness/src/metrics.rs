//! What is measured at each sample and over a run.

use rsts_closed_form::ExplicitState;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::integrators::Stats;
use rsts_dynamics::vec3::{mat_vec, mul_bt, rotation_angle, Mat3, Vec3};
use rsts_dynamics::{Fields, Real, State};
use rug::Float;
use serde::Serialize;

use crate::digits::CorrectDigits;
use crate::drift_growth::DriftGrowth;
use crate::geometry::{ErrorSplit, NormalSummary, PhaseErrorSummary};

/// A state as plotted and logged (f64): orientation rows α, β, γ, ω, Ω = Qω and H, K, G.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StateSnapshot {
    pub q: [[f64; 3]; 3],
    pub omega: [f64; 3],
    pub omega_fixed: [f64; 3],
    pub h: f64,
    pub k: f64,
    pub g: f64,
}

impl StateSnapshot {
    /// The snapshot not computed (an observer that does not want states,
    /// [`crate::Observer::wants_states`]): NaN throughout.
    pub const NAN: Self = Self {
        q: [[f64::NAN; 3]; 3],
        omega: [f64::NAN; 3],
        omega_fixed: [f64::NAN; 3],
        h: f64::NAN,
        k: f64::NAN,
        g: f64::NAN,
    };
}

/// Errors of the integrated motion at one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SampleErrors {
    /// max |x_int − x_exact| over the nine components (ω, α, β).
    pub state_error: f64,
    /// Rotation angle of Q_int Q_exactᵀ (radians).
    pub orientation_error: f64,
    /// |H(t) − H(0)|, |K(t) − K(0)|, |G(t) − G(0)| of the integrated motion.
    pub drift_h: f64,
    pub drift_k: f64,
    pub drift_g: f64,
    /// max(||α|² − 1|, ||β|² − 1|, |α·β|).
    pub constraint_drift: f64,
    /// Drift of the on-N integral relations: max(|K − r⁴m²|, |2G − p²H − r⁴m|). Not a
    /// distance from N: a departure from N within the level set of H, K, G leaves it at 0.
    pub off_n: f64,
    /// Distance of the integrated state from its nearest point on N (state units, max-norm).
    pub distance_from_n: f64,
    /// |X_Φ| at the integrated state, Φ = r⁴K − (2G − p²H)²: the regular measure of the
    /// departure from N, derived from the integrals.
    pub x_phi: f64,
    /// Distance of that nearest point from the exact state: the drift along N.
    pub along_n: f64,
    /// ψᵢ − ψᵢ(exact) of the nearest point, in (−π, π] (NaN when no nearest point was found).
    pub phase_error: [f64; 2],
}

/// One sample of a comparison.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SampleRecord {
    pub index: usize,
    pub t: f64,
    pub exact: StateSnapshot,
    pub integrated: StateSnapshot,
    pub errors: SampleErrors,
}

/// Drift summary of a run: the largest value over the samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Drift {
    #[serde(rename = "H")]
    pub h: f64,
    #[serde(rename = "K")]
    pub k: f64,
    #[serde(rename = "G")]
    pub g: f64,
    pub constraints: f64,
    #[serde(rename = "off_N")]
    pub off_n: f64,
    /// Growth laws of the drifts of H, K, G and the constraints (null until the run is done).
    pub growth: Option<DriftGrowth>,
}

/// The result of a comparison (the JSON of `rsts compare`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub method: String,
    /// Tolerances of the integrator (`null` when it has none, e.g. a trajectory from a file).
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// Digits of the integrator's scalar (f64: 15).
    pub digits: u32,
    /// Digits of the closed-form reference.
    pub reference_digits: u32,
    pub camera: String,
    pub samples_compared: usize,
    /// False when the run was stopped (Ctrl-C) before the last sample.
    pub complete: bool,
    pub max_state_error: f64,
    pub final_state_error: f64,
    pub max_orientation_error: f64,
    /// Correct digits (Bari test set): `scd`, `mescd`, `scd_min`, `mescd_min`.
    #[serde(flatten)]
    pub correct_digits: CorrectDigits,
    pub drift: Drift,
    /// What the run cost (`null` when not known: a trajectory from a file that does not state
    /// it, a callable that cannot count its steps).
    pub steps: Option<u64>,
    pub rejected_steps: Option<u64>,
    pub rhs_evals: Option<u64>,
    pub integration_seconds: Option<f64>,
    /// Wall time measured around an external integrator (process start, request and answer
    /// included); absent for in-process integrators.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_seconds: Option<f64>,
    /// The departure from N: normal type, distance (max, final), its growth (null when the
    /// geometry could not be computed in the integrator's precision).
    pub normal: Option<NormalSummary>,
    /// The phase error of the nearest point on N and its growth.
    pub phase_error: Option<PhaseErrorSummary>,
    /// What dominates the state error (null: the error saturated from the first sample).
    pub error_split: Option<ErrorSplit>,
}

impl Report {
    /// Add the errors of one sample (the one place where samples are summarised).
    pub(crate) fn absorb(&mut self, e: &SampleErrors) {
        self.max_state_error = self.max_state_error.max(e.state_error);
        self.final_state_error = e.state_error;
        self.max_orientation_error = self.max_orientation_error.max(e.orientation_error);
        let d = &mut self.drift;
        d.h = d.h.max(e.drift_h);
        d.k = d.k.max(e.drift_k);
        d.g = d.g.max(e.drift_g);
        d.constraints = d.constraints.max(e.constraint_drift);
        d.off_n = d.off_n.max(e.off_n);
        self.samples_compared += 1;
    }

    /// Add the cost of (a piece of) a run.
    pub(crate) fn add_stats(&mut self, s: &Stats) {
        *self.steps.get_or_insert(0) += s.accepted_steps;
        *self.rejected_steps.get_or_insert(0) += s.rejected_steps;
        *self.rhs_evals.get_or_insert(0) += s.rhs_evals;
        *self.integration_seconds.get_or_insert(0.0) += s.integration_seconds;
    }

    /// The cost a trajectory states about itself (a file's `stats` block), each part only
    /// where stated.
    pub fn set_stated_stats(&mut self, s: &StatedStats) {
        self.steps = s.steps;
        self.rejected_steps = s.rejected_steps;
        self.rhs_evals = s.rhs_evals;
        self.integration_seconds = s.integration_seconds;
    }

    /// Forget the counts a run did not state (an external integrator's answer without
    /// `stats.steps` or `stats.rhs_evals`): null in JSON, empty in CSV, n/a in tables. The
    /// protocol has no rejected steps: they are counted with the steps.
    pub fn forget_unstated(&mut self, s: &StatedStats) {
        if s.steps.is_none() {
            self.steps = None;
            self.rejected_steps = None;
        }
        if s.rhs_evals.is_none() {
            self.rhs_evals = None;
        }
    }
}

/// The cost a trajectory computed elsewhere states about itself: the `stats` block of a JSON
/// file as `rsts integrate --format json` writes it. Each part may be absent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct StatedStats {
    pub steps: Option<u64>,
    pub rejected_steps: Option<u64>,
    pub rhs_evals: Option<u64>,
    pub integration_seconds: Option<f64>,
}

fn f3<T: Real>(v: &Vec3<T>) -> [f64; 3] {
    v.clone().map(|x| x.to_f64())
}

/// The snapshot of `s` whose orientation is `q` and whose H, K, G are `hkg` (both computed
/// once per sample by the caller).
fn snapshot<T: Real>(s: &State<T>, q: &Mat3<T>, hkg: [&T; 3]) -> StateSnapshot {
    StateSnapshot {
        q: q.clone().map(|r| f3(&r)),
        omega: f3(&s.omega),
        omega_fixed: f3(&mat_vec(q, &s.omega)),
        h: hkg[0].to_f64(),
        k: hkg[1].to_f64(),
        g: hkg[2].to_f64(),
    }
}

/// The closed-form state as a phase state.
pub(crate) fn exact_state(e: &ExplicitState<Float>) -> State<Float> {
    State {
        omega: e.omega.clone(),
        alpha: e.alpha.clone(),
        beta: e.beta.clone(),
    }
}

/// Constants of N the distance is measured against: r⁴m² (= K) and p²h + r⁴m (= 2G).
#[derive(Clone)]
pub(crate) struct ManifoldN<T = Float> {
    pub k: T,
    pub p2: T,
    pub r4m: T,
}

/// Errors at one sample, at the reference precision or in double-double for f64 data (the one
/// place where per-sample errors are computed; [`Report::absorb`] summarises them), and with
/// `snapshots` the exact and the integrated state as logged.
#[inline(always)]
pub(crate) fn sample_errors<T: Real>(
    fields: &Fields<T>,
    n: &ManifoldN<T>,
    initial_integrals: &[T; 3],
    exact: &State<T>,
    integrated: &State<T>,
    snapshots: bool,
) -> (SampleErrors, Option<[StateSnapshot; 2]>) {
    let x = integrated.to_array();
    let y = exact.to_array();
    let state_error = (0..9)
        .map(|k| (x[k].clone() - &y[k]).abs())
        .fold(x[0].zero_like(), |a, b| a.max_of(b));
    let (q_int, q_ex) = (integrated.orientation(), exact.orientation());
    let r: Mat3<T> = mul_bt(&q_int, &q_ex);
    let ints = integrals(fields, integrated);
    let two = x[0].lit(2.0);
    let off_k = (ints.k.clone() - &n.k).abs();
    let off_g = (two * &ints.g - n.p2.clone() * &ints.h - &n.r4m).abs();
    let errors = SampleErrors {
        state_error: state_error.to_f64(),
        orientation_error: rotation_angle(&r).to_f64(),
        drift_h: (ints.h.clone() - &initial_integrals[0]).abs().to_f64(),
        drift_k: (ints.k.clone() - &initial_integrals[1]).abs().to_f64(),
        drift_g: (ints.g.clone() - &initial_integrals[2]).abs().to_f64(),
        constraint_drift: integrated.constraint_error().to_f64(),
        off_n: off_k.max_of(off_g).to_f64(),
        // Filled in by the geometry of the error (crate::geometry).
        distance_from_n: f64::NAN,
        x_phi: f64::NAN,
        along_n: f64::NAN,
        phase_error: [f64::NAN; 2],
    };
    let snapshots = snapshots.then(|| {
        let i0 = initial_integrals;
        [
            // The exact motion's H, K, G are its constants: those at t = 0.
            snapshot(exact, &q_ex, [&i0[0], &i0[1], &i0[2]]),
            snapshot(integrated, &q_int, [&ints.h, &ints.k, &ints.g]),
        ]
    });
    (errors, snapshots)
}
