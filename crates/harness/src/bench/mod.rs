//! Work–precision measurement (issue 5): one integrator at one tolerance, its largest state
//! error against the closed form and what it cost.
//!
//! Unlike [`crate::compare()`], a measurement integrates the whole grid in ONE call of
//! [`Integrator::integrate`] (no pieces, no restarts: the cost is the integrator's alone),
//! repeats it `repeats` times and keeps the median of the integrator's own
//! `stats.integration_seconds`. The closed form is evaluated once per [`Reference`], at
//! [`reference_bits_for`] the integrator's precision (64 bits beyond it), and reused across
//! repeats, tolerances and integrators.

mod band_diagram;
pub mod diagrams;
mod flow;
pub mod merge;
mod request;

pub use flow::{
    bench, bench_ensemble, bench_with_dense, default_mp_digits, label_of, BenchReport, RowLabel,
    MAX_BENCH_SAMPLES, MAX_REPEATS, MAX_TOTAL_STEPS,
};
pub use merge::{
    bench_merge, merge_shards, read_shard, BenchMerge, BenchMergeRequest, EnsembleShard,
};
pub use request::{
    BenchIntegrator, BenchMethod, BenchObserver, BenchRequest, EnsemblePlan, OutsideMethod, Quiet,
};

use rsts_dynamics::integrators::{MethodConfig, OutputGrid, Problem, Tolerances};
use rsts_dynamics::{Fields, State};
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::case::Case;
use crate::compare::{reference_bits, reference_bits_for};
use crate::digits::{correct_digits, CorrectDigits};
use crate::integrator::{Integrator, Trajectory};
use crate::metrics::exact_state;
use crate::HarnessError;

/// One line of a work–precision table: the JSON row of `rsts bench`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchRow {
    /// The motion of an ensemble the row measures (its index in `ensemble.motions`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<usize>,
    pub method: String,
    /// min(rtol, atol); NaN (`null`) for an integrator without tolerances.
    #[serde(deserialize_with = "nan_if_null")]
    pub tolerance: f64,
    /// max over samples and the nine components (ω, α, β) of |x − x_exact|.
    pub max_error: f64,
    /// Correct digits of the run (`scd`, `mescd`, `scd_min`, `mescd_min`: [`crate::digits`]).
    #[serde(flatten)]
    pub correct_digits: CorrectDigits,
    /// Median over the repeats of the integrator's own time (an external integrator's
    /// `integration_seconds` when it reports one, else its wall time; an integrator that
    /// reports none is timed around its call).
    pub integration_seconds: f64,
    /// Smallest, median and largest of that time over the repeats.
    #[serde(default)]
    pub time_min: f64,
    #[serde(default)]
    pub time_median: f64,
    #[serde(default)]
    pub time_max: f64,
    /// What the first run cost (`null` when not known: an external integrator whose answer does
    /// not state it, a Python callable that cannot count its steps).
    pub steps: Option<u64>,
    pub rhs_evals: Option<u64>,
    /// Median over the repeats of the wall time measured around an external integrator
    /// (process start-up included); absent for in-process integrators.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_seconds: Option<f64>,
    /// Events located against the exact ones (`bench --event`; docs/events.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub events: Option<crate::events::EventCounts>,
    /// The dense-output check (`bench --dense K`; [`crate::dense`]).
    #[serde(default, flatten, skip_serializing_if = "Option::is_none")]
    pub dense: Option<crate::dense::DenseReport>,
}

/// A number written as `null` (NaN) read back as NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Option::<f64>::deserialize(d).map(|x| x.unwrap_or(f64::NAN))
}

/// The closed-form motion of a case at its sample times, at a given precision.
#[derive(Clone, Debug)]
pub struct Reference {
    bits: u32,
    grid: OutputGrid,
    times: Vec<f64>,
    fields: Fields<Float>,
    states: Vec<State<Float>>,
}

impl Reference {
    /// Evaluate the closed form of `case` at its N sample times k·T/(N−1) (the f64 times of
    /// [`OutputGrid::time`], taken exactly) in `bits` bits.
    pub fn new(case: &Case, bits: u32) -> Result<Self, HarnessError> {
        let f = |x: f64| Float::with_val(bits, x);
        let (motion, fields) = case.reference_motion(bits)?;
        let grid = case.grid()?;
        let times = grid.times();
        let states = times
            .iter()
            .map(|&t| exact_state(&motion.at(&f(t))))
            .collect();
        Ok(Self {
            bits,
            grid,
            times,
            fields,
            states,
        })
    }

    /// Precision of the reference states.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    pub fn grid(&self) -> &OutputGrid {
        &self.grid
    }

    /// The sample times (the grid's, from 0).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    pub fn fields(&self) -> &Fields<Float> {
        &self.fields
    }

    /// The exact states at the grid times; `states()[0]` is where every run starts.
    pub fn states(&self) -> &[State<Float>] {
        &self.states
    }
}

/// Largest |x − y| over the samples and the nine components, computed at the precision of
/// the reference and rounded to f64. Errors when the lengths differ.
pub fn max_state_error(
    reference: &[State<Float>],
    states: &[State<Float>],
) -> Result<f64, HarnessError> {
    if reference.len() != states.len() {
        return Err(HarnessError::Case(format!(
            "{} states compared with {} reference states",
            states.len(),
            reference.len()
        )));
    }
    let mut worst = 0.0f64;
    for (x, y) in states.iter().zip(reference) {
        let (x, y) = (x.to_array(), y.to_array());
        for k in 0..x.len() {
            let d = Float::with_val(y[k].prec(), &x[k] - &y[k]).abs();
            worst = worst.max(d.to_f64());
        }
    }
    Ok(worst)
}

/// Median of a non-empty list (mean of the two middle values for an even count); NaN for an
/// empty one.
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Measure `config` on `case`: the closed form is evaluated at [`reference_bits`]`(config)`.
pub fn measure(
    case: &Case,
    config: &MethodConfig,
    repeats: usize,
) -> Result<BenchRow, HarnessError> {
    let reference = Reference::new(case, reference_bits(config))?;
    measure_against(&reference, config, repeats)
}

/// One more run of `integrator` over the reference's grid (untimed): its sample times and
/// states (ω, α, β) in f64, for locating events ([`crate::events::events_of_run`]).
pub fn run_once(
    reference: &Reference,
    integrator: &mut dyn Integrator,
) -> Result<(Vec<f64>, Vec<[f64; 9]>), HarnessError> {
    let problem = Problem {
        fields: reference.fields.clone(),
        initial: reference.states[0].clone(),
    };
    let traj = integrator.integrate(&problem, &reference.times)?;
    let states = traj
        .states
        .iter()
        .map(|s| {
            let v = [&s.omega, &s.alpha, &s.beta];
            std::array::from_fn(|k| v[k / 3][k % 3].to_f64())
        })
        .collect();
    Ok((traj.times, states))
}

/// Measure the built-in method `config` against an already evaluated reference (see
/// [`measure_integrator`]); the row's tolerance is min(rtol, atol).
pub fn measure_against(
    reference: &Reference,
    config: &MethodConfig,
    repeats: usize,
) -> Result<BenchRow, HarnessError> {
    let mut config = *config;
    measure_integrator(reference, &mut config, repeats)
}

/// Measure any integrator against an already evaluated reference (which must carry at least
/// [`reference_bits_for`] the integrator's bits): `repeats` (≥ 1) un-chunked runs over the
/// whole grid. The error, steps and evaluations are those of the first run (the runs are
/// deterministic); the times are medians over the runs. The row is named after the
/// integrator; its tolerance is min(rtol, atol) (NaN for an integrator without tolerances).
pub fn measure_integrator(
    reference: &Reference,
    integrator: &mut dyn Integrator,
    repeats: usize,
) -> Result<BenchRow, HarnessError> {
    if repeats == 0 {
        return Err(HarnessError::Case("repeats must be at least 1".into()));
    }
    let needed = reference_bits_for(integrator.working_bits());
    if reference.bits < needed {
        return Err(HarnessError::Case(format!(
            "the reference has {} bits, {} needs {needed}",
            reference.bits,
            integrator.name()
        )));
    }
    let problem = Problem {
        fields: reference.fields.clone(),
        initial: reference.states[0].clone(),
    };
    let tolerances = integrator.tolerances();
    // What the first run stated of its cost (an external integrator's answer may leave out
    // its steps or evaluations: not known, not 0).
    let mut stated = None;
    let mut row = summarize(reference, repeats, tolerances, || {
        let traj = integrator.integrate(&problem, &reference.times);
        if stated.is_none() {
            stated = Some(integrator.stated_stats());
        }
        traj
    })?;
    if let Some(Some(s)) = stated {
        row.steps = row.steps.filter(|_| s.steps.is_some());
        row.rhs_evals = row.rhs_evals.filter(|_| s.rhs_evals.is_some());
    }
    row.method = integrator.name();
    row.tolerance = integrator
        .tolerances()
        .map_or(f64::NAN, |t| t.rtol.min(t.atol));
    Ok(row)
}

/// Run `run` `repeats` times: error, digits (for `tolerances`), steps and evaluations of the
/// first run, median times (the integrator's own, else measured around `run`).
fn summarize(
    reference: &Reference,
    repeats: usize,
    tolerances: Option<Tolerances>,
    mut run: impl FnMut() -> Result<Trajectory, HarnessError>,
) -> Result<BenchRow, HarnessError> {
    let mut seconds = Vec::with_capacity(repeats);
    let mut walls = Vec::with_capacity(repeats);
    let mut first = None;
    for _ in 0..repeats {
        let started = std::time::Instant::now();
        let traj = run()?;
        let around = started.elapsed().as_secs_f64();
        // An integrator that does not time itself is timed around its call.
        seconds.push(match traj.stats.integration_seconds {
            t if t > 0.0 => t,
            _ => around,
        });
        walls.extend(traj.wall_seconds);
        if first.is_none() {
            first = Some(traj);
        }
    }
    let traj = first.ok_or_else(|| HarnessError::Case("repeats must be at least 1".into()))?;
    Ok(BenchRow {
        motion: None,
        method: String::new(),
        tolerance: f64::NAN,
        max_error: max_state_error(&reference.states, &traj.states)?,
        correct_digits: correct_digits(
            &reference.states,
            &traj.states,
            tolerances.map(|t| t.rtol),
            tolerances.map(|t| t.atol),
        ),
        integration_seconds: median(&seconds),
        time_min: seconds.iter().copied().fold(f64::INFINITY, f64::min),
        time_median: median(&seconds),
        time_max: seconds.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        steps: Some(traj.stats.accepted_steps),
        rhs_evals: Some(traj.stats.rhs_evals),
        wall_seconds: (!walls.is_empty()).then(|| median(&walls)),
        events: None,
        dense: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsts_closed_form::{ExplicitMotion, TorusChoice};
    use rsts_dynamics::integrators::{MethodName, Stats};

    fn case(t_end: f64, samples: usize) -> Case {
        {
            let mut c = Case::default_i_plus();
            c.t_end = rsts_closed_form::Decimal::from_f64(t_end).unwrap();
            c.samples = samples;
            c
        }
    }

    fn config(method: MethodName, tol: f64) -> MethodConfig {
        MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap()
    }

    #[test]
    fn median_of_odd_even_and_unsorted_lists() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&[7.0]), 7.0);
        assert_eq!(median(&[5.0, 1e-9, 1e9, 2.0, 3.0]), 3.0);
        assert!(median(&[]).is_nan());
    }

    /// The reported error equals one computed independently: our own run of the integrator
    /// (f64 API) against the closed form evaluated afresh at 300 bits, sample by sample.
    #[test]
    fn max_error_equals_an_independent_computation() {
        let c = case(10.0, 21);
        let cfg = config(MethodName::Dop853, 1e-9);
        let row = measure(&c, &cfg, 2).unwrap();

        let bits = 300;
        let f = |x: f64| Float::with_val(bits, x);
        let motion = ExplicitMotion::new(
            f(c.motion.a.to_f64()),
            f(c.motion.b.to_f64()),
            f(c.motion.m.to_f64()),
            f(c.motion.h.to_f64()),
            TorusChoice {
                torus: 0,
                phase1: 0.0,
                phase2: 0.0,
            },
        )
        .unwrap();
        let start = exact_state(&motion.at(&f(0.0)));
        let problem = Problem {
            fields: Fields::new(c.motion.a.to_f64(), c.motion.b.to_f64()).unwrap(),
            initial: start.map(|x| x.to_f64()),
        };
        let grid = c.grid().unwrap();
        let sol = cfg.propagate_f64(&problem, &grid).unwrap();
        let mut worst = 0.0f64;
        for (k, s) in sol.states.iter().enumerate() {
            let exact = exact_state(&motion.at(&f(grid.time(k)))).to_array();
            for (x, y) in s.to_array().iter().zip(exact.iter()) {
                worst = worst.max((f(*x) - y).abs().to_f64());
            }
        }
        assert!(worst > 1e-13 && worst < 1e-6, "independent error {worst:e}");
        assert!(
            (row.max_error - worst).abs() <= 1e-6 * worst,
            "reported {:e}, independent {worst:e}",
            row.max_error
        );
        assert_eq!(row.steps, Some(sol.stats.accepted_steps));
        assert_eq!(row.rhs_evals, Some(sol.stats.rhs_evals));
        assert_eq!(row.method, "dop853");
        assert_eq!(row.tolerance, 1e-9);
    }

    #[test]
    fn max_state_error_finds_the_largest_component_and_checks_lengths() {
        let bits = 200;
        let z = || Float::with_val(bits, 0);
        let zero = State {
            omega: [z(), z(), z()],
            alpha: [z(), z(), z()],
            beta: [z(), z(), z()],
        };
        let mut off = zero.clone();
        off.beta[2] = Float::with_val(bits, -3e-40);
        let mut small = zero.clone();
        small.omega[0] = Float::with_val(bits, 1e-41);
        let e = max_state_error(&[zero.clone(), zero.clone()], &[small, off]).unwrap();
        assert!((e - 3e-40).abs() < 1e-52, "{e:e}");
        assert!(
            max_state_error(std::slice::from_ref(&zero), &[zero.clone(), zero.clone()]).is_err()
        );
    }

    /// Tighter tolerances give smaller errors and more work; the time is a median of positive
    /// times; the reference must be precise enough for the method.
    #[test]
    fn errors_fall_with_tolerance_and_the_reference_is_checked() {
        let c = case(10.0, 11);
        let reference =
            Reference::new(&c, reference_bits(&config(MethodName::TaylorF64, 1e-6))).unwrap();
        assert_eq!(reference.states().len(), 11);
        let loose = measure_against(&reference, &config(MethodName::TaylorF64, 1e-6), 3).unwrap();
        let tight = measure_against(&reference, &config(MethodName::TaylorF64, 1e-13), 3).unwrap();
        assert!(
            tight.max_error < 1e-3 * loose.max_error,
            "loose {:e}, tight {:e}",
            loose.max_error,
            tight.max_error
        );
        // Jorba–Zou: the order grows with the tolerance, the step hardly changes.
        assert!(tight.rhs_evals > loose.rhs_evals);
        assert!(loose.integration_seconds > 0.0 && loose.integration_seconds.is_finite());
        let mp = config(MethodName::TaylorMp, 1e-40).with_digits(45).unwrap();
        assert!(measure_against(&reference, &mp, 1).is_err(), "too few bits");
        assert!(measure_against(&reference, &config(MethodName::Dop853, 1e-8), 0).is_err());
    }

    /// The time is the median of the repeats' own integration times (not the first, not the
    /// mean); the error is measured on the states the runs return.
    #[test]
    fn time_is_the_median_of_the_repeats() {
        let c = case(1.0, 3);
        let reference = Reference::new(&c, 200).unwrap();
        let times = [5.0, 0.5, 40.0, 1.5, 2.0];
        let mut k = 0;
        let row = summarize(&reference, times.len(), None, || {
            let seconds = times[k];
            k += 1;
            let mut states = reference.states().to_vec();
            states[2].alpha[1] += 1e-30 * k as f64;
            Ok(Trajectory {
                times: reference.times().to_vec(),
                states,
                stats: Stats {
                    accepted_steps: 10 * k as u64,
                    rejected_steps: 0,
                    rhs_evals: 100 * k as u64,
                    integration_seconds: seconds,
                },
                wall_seconds: Some(2.0 * seconds),
            })
        })
        .unwrap();
        assert_eq!(k, 5, "every repeat runs");
        assert_eq!(row.integration_seconds, 2.0);
        assert_eq!(
            (row.time_min, row.time_median, row.time_max),
            (0.5, 2.0, 40.0)
        );
        assert_eq!(row.wall_seconds, Some(4.0));
        assert_eq!(
            (row.steps, row.rhs_evals),
            (Some(10), Some(100)),
            "stats of the first run"
        );
        assert!((row.max_error - 1e-30).abs() < 1e-40, "{:e}", row.max_error);
    }

    /// An integrator that reports no time of its own is timed around its call.
    #[test]
    fn an_integrator_without_its_own_time_is_timed_around_its_call() {
        let c = case(1.0, 3);
        let reference = Reference::new(&c, 200).unwrap();
        let row = summarize(&reference, 3, None, || {
            std::thread::sleep(std::time::Duration::from_millis(3));
            Ok(Trajectory {
                times: reference.times().to_vec(),
                states: reference.states().to_vec(),
                stats: Stats::default(),
                wall_seconds: None,
            })
        })
        .unwrap();
        assert!(row.time_min >= 0.003, "{:e}", row.time_min);
        assert!(row.integration_seconds >= row.time_min);
    }

    /// Extended precision reaches what f64 cannot.
    #[test]
    fn double_double_beats_the_f64_floor() {
        let c = case(5.0, 6);
        let dd = measure(&c, &config(MethodName::TaylorDd, 1e-28), 1).unwrap();
        assert!(dd.max_error < 1e-25, "taylor-dd error {:e}", dd.max_error);
        assert_eq!(dd.method, "taylor-dd");
    }
}
