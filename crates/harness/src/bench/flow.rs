//! The flow of a benchmark (`rsts bench`, `rsts.bench`): a [`BenchRequest`] → [`bench`] → the
//! [`BenchReport`] that `rsts bench --format json` prints. The job list (methods × tolerances,
//! a tolerance below a method's round-off skipped with a note), the step estimate of the whole
//! benchmark, one closed-form [`Reference`] per precision, the runs and the tolerance fits.
//!
//! A method is a built-in ([`BenchMethod::BuiltIn`]) or an integrator from outside made for
//! each tolerance ([`OutsideMethod`](super::OutsideMethod): an `--exec` process, a Python callable); the library
//! measures each the same way ([`measure_integrator`]).

use std::collections::btree_map::{BTreeMap, Entry};

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances, MAX_MP_DIGITS};
use serde::{Deserialize, Serialize};

use super::merge::{request_digest, EnsembleShard};
use super::request::{BenchIntegrator, BenchMethod, BenchObserver, BenchRequest, EnsemblePlan};
use super::{measure_against, measure_integrator, run_once, BenchRow, Reference};
use crate::compare::{preflight, reference_bits, reference_bits_for};
use crate::ensemble::{bands, draw_ensemble, Band, Ensemble};
use crate::environment::Environment;
use crate::events::events_of_run;
use crate::proportionality::{fit_tolerances, ToleranceFit};
use crate::{Case, HarnessError, MAX_SAMPLES};

/// Most samples of a benchmark: the closed-form reference keeps every sample in high precision
/// (about 1 kB each).
pub const MAX_BENCH_SAMPLES: usize = 1_000_000;
/// Most repeats of each run.
pub const MAX_REPEATS: usize = 1000;
/// Most steps of a whole benchmark (every method, tolerance and repeat), as estimated up front.
pub const MAX_TOTAL_STEPS: f64 = 2e9;

/// How a row is labelled and drawn (serialised only in a shard of an ensemble, for its merge:
/// the rows carry the method's name).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RowLabel {
    /// taylor-mp with its digits (`taylor-mp-40d`), else the method's name.
    pub label: String,
    /// An integrator from outside (drawn dashed).
    pub external: bool,
}

/// The report of a benchmark: the JSON of `rsts bench` (the case, the settings, the rows of the
/// built-in methods then those from outside, the fits, the environment). Read back (a shard of
/// an ensemble, for [`merge_shards`](super::merge_shards)) it is the same report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchReport {
    pub case: Case,
    pub repeats: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub taylor_mp_digits: Option<u32>,
    /// The motions of an ensemble (`rsts bench --ensemble N`); the case then gives a, b, T and
    /// the samples, each motion its point, torus and phases.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<Ensemble>,
    /// Every run; in an ensemble, each row names its motion.
    pub rows: Vec<BenchRow>,
    /// Tolerance proportionality per method (two tolerances or more).
    pub fits: Vec<ToleranceFit>,
    /// Per method and tolerance of an ensemble, the median and 5–95 % band of the error and
    /// the time over the motions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bands: Vec<Band>,
    pub environment: Environment,
    /// A shard of an ensemble (`--shard K/N`): which, of what request, and its rows' labels;
    /// its rows, fits and bands are those of its motions alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<EnsembleShard>,
    /// One per row.
    #[serde(skip)]
    pub labels: Vec<RowLabel>,
}

impl BenchReport {
    /// The label of the row of `method` (its first row), else the name itself.
    pub fn label_of_method<'s>(&'s self, method: &'s str) -> &'s str {
        self.rows
            .iter()
            .zip(&self.labels)
            .find(|(r, _)| r.method == method)
            .map_or(method, |(_, l)| l.label.as_str())
    }
}

/// Default digits of taylor-mp for the smallest tolerance `tol`.
pub fn default_mp_digits(tol: f64) -> u32 {
    let d = (-tol.log10()).ceil().max(0.0) as u32 + 10;
    d.clamp(10, MAX_MP_DIGITS)
}

fn setting(names: &[&str], message: String) -> HarnessError {
    HarnessError::Setting(names.iter().map(|n| n.to_string()).collect(), message)
}

/// A planned run.
enum Job {
    BuiltIn(MethodConfig),
    Outside(Box<dyn BenchIntegrator>, String),
}

/// Run a benchmark: check the request whole (every job's point and step budget) before any run,
/// then measure each method at each tolerance against the closed form.
pub fn bench(
    request: BenchRequest<'_>,
    observer: &mut dyn BenchObserver,
) -> Result<BenchReport, HarnessError> {
    run(request, None, None, observer)
}

/// [`bench`] with the dense-output check of every row (`bench --dense K`, [`crate::dense`]):
/// one more, untimed run per row that reports its steps and K samples inside each.
pub fn bench_with_dense(
    request: BenchRequest<'_>,
    dense: Option<usize>,
    observer: &mut dyn BenchObserver,
) -> Result<BenchReport, HarnessError> {
    run(request, None, dense, observer)
}

/// Run a benchmark over an ensemble of motions ([`EnsemblePlan`]): the request's case gives a,
/// b, T and the samples; every method runs at every tolerance on every motion as in [`bench`]
/// (each run the trajectory of `rsts compare … --pieces 1`), and the report adds the motions
/// and the bands. Events are not located in an ensemble.
pub fn bench_ensemble(
    request: BenchRequest<'_>,
    plan: &EnsemblePlan,
    observer: &mut dyn BenchObserver,
) -> Result<BenchReport, HarnessError> {
    run(request, Some(plan), None, observer)
}

fn run(
    request: BenchRequest<'_>,
    plan: Option<&EnsemblePlan>,
    dense: Option<usize>,
    observer: &mut dyn BenchObserver,
) -> Result<BenchReport, HarnessError> {
    const { assert!(MAX_BENCH_SAMPLES <= MAX_SAMPLES) };
    let BenchRequest {
        case,
        methods,
        tolerances,
        repeats,
        digits,
        events: specs,
    } = request;
    if case.samples > MAX_BENCH_SAMPLES {
        return Err(setting(&["samples"], format!(
            "at most {MAX_BENCH_SAMPLES} samples are supported by bench (the reference keeps them all in high precision), got {}",
            case.samples
        )));
    }
    case.validate()?;
    let has_builtins = methods.iter().any(|m| matches!(m, BenchMethod::BuiltIn(_)));
    if has_builtins && !specs.iter().all(|s| s.name.index() < 12) {
        return Err(setting(&["event"], "the built-in methods locate events of functions of the state (omega, alpha, beta, gamma), not the turning points s1, s2".into()));
    }
    if let Some(k) = dense {
        crate::dense::check_dense(k).map_err(|e| setting(&["dense"], e.to_string()))?;
    }
    if case.t_end_f64() <= 0.0 || case.samples < 2 {
        return Err(setting(
            &["t-end", "samples"],
            "a benchmark needs T > 0 and at least 2 samples".into(),
        ));
    }
    if !(1..=MAX_REPEATS).contains(&repeats) {
        return Err(setting(
            &["repeats"],
            format!(
                "need 1 to {MAX_REPEATS} repeats (the time is their median), got {}",
                rsts_dynamics::short(repeats as f64)
            ),
        ));
    }
    if tolerances.is_empty() {
        return Err(setting(
            &["tolerances"],
            "give at least one tolerance".into(),
        ));
    }
    for &tol in &tolerances {
        Tolerances::new(tol, tol).map_err(|e| setting(&["tolerances"], e.to_string()))?;
    }
    if methods.is_empty() {
        return Err(setting(
            &["methods"],
            "give at least one method (or an --exec integrator)".into(),
        ));
    }
    // A shard's request, for its merge (before the methods are taken apart).
    let shard = plan.and_then(|p| Some((p.shard?, p)));
    let digest =
        shard.map(|(_, p)| request_digest(&case, &methods, &tolerances, repeats, digits, p));
    let ensemble = match plan {
        Some(plan) => {
            if !specs.is_empty() {
                return Err(setting(
                    &["event", "ensemble"],
                    "events are not located in an ensemble; leave out one of them".into(),
                ));
            }
            let [a, b, _, _] = case.motion.parameters_f64();
            let e = draw_ensemble(a, b, &plan.cameras, plan.n, plan.seed)
                .map_err(|e| setting(e.parameters(), e.to_string()))?;
            Some(e)
        }
        None => None,
    };
    // The motions run (with their index in the ensemble): the case itself, or each motion of
    // the ensemble (of the shard's slice).
    let cases: Vec<(usize, Case)> = match &ensemble {
        Some(e) => (0..e.n)
            .filter(|&k| shard.is_none_or(|(sh, _)| sh.holds(k)))
            .map(|k| (k, e.case(&case, k)))
            .collect(),
        None => vec![(0, case.clone())],
    };
    let motion_of = |k: usize, e: HarnessError| match &ensemble {
        Some(en) => {
            let mo = &en.motions[k];
            HarnessError::Integrator(format!(
                "ensemble motion {k} (camera {}, --m {} --h {} --torus {} --phase1 {} --phase2 {}): {e}",
                mo.camera, mo.m, mo.h, mo.torus, mo.phase1, mo.phase2
            ))
        }
        None => e,
    };
    let smallest = tolerances.iter().copied().fold(f64::INFINITY, f64::min);
    if let Some(d) = digits {
        if !(10..=MAX_MP_DIGITS).contains(&d) {
            return Err(setting(
                &["digits"],
                format!("must be between 10 and {MAX_MP_DIGITS}, got {d}"),
            ));
        }
    }
    let mp_digits = digits.unwrap_or_else(|| default_mp_digits(smallest));
    let with_mp = |config: MethodConfig| -> Result<MethodConfig, HarnessError> {
        match config.method {
            MethodName::TaylorMp => config
                .with_digits(mp_digits)
                .map_err(|e| setting(&["digits"], e.to_string())),
            _ => Ok(config),
        }
    };

    // Which runs to do; unreachable tolerances are noted and skipped. Built-in methods first
    // (each once), then those from outside, in the order given.
    let mut seen: Vec<MethodName> = Vec::new();
    let mut builtins = Vec::new();
    let mut outside = Vec::new();
    for m in methods {
        match m {
            BenchMethod::BuiltIn(name) if !seen.contains(&name) => {
                seen.push(name);
                builtins.push(name);
            }
            BenchMethod::BuiltIn(_) => {}
            BenchMethod::Outside(o) => outside.push(o),
        }
    }
    let mut jobs: Vec<Job> = Vec::new();
    for &method in &builtins {
        for &tol in &tolerances {
            // The method's round-off, asked of a config at a tolerance it accepts (it refuses
            // one below its round-off, which bench skips instead).
            let probe = MethodConfig::new(method, Tolerances::new(1.0, 1.0)?, None);
            let probe = with_mp(probe.map_err(|e| plain(e.into()))?)?;
            let unit = probe.min_tolerance();
            if tol < unit {
                observer.note(&format!(
                    "note: skipping {} at tolerance {tol:e}: below its unit round-off {unit:.2e}",
                    label_of(method, mp_digits)
                ));
                continue;
            }
            let config = MethodConfig::new(method, Tolerances::new(tol, tol)?, None);
            jobs.push(Job::BuiltIn(with_mp(config.map_err(|e| plain(e.into()))?)?));
        }
    }
    let built_in_jobs = jobs.len();
    // Integrators from outside: one per method and tolerance, requests at `mp_digits` digits.
    for o in outside {
        let what = o.what();
        for &tol in &tolerances {
            jobs.push(Job::Outside(
                o.at(Tolerances::new(tol, tol)?, mp_digits)?,
                what.clone(),
            ));
        }
    }
    if jobs.is_empty() {
        return Err(setting(
            &["tolerances"],
            "no method can reach any of the tolerances given (all below round-off)".into(),
        ));
    }
    // Every job is checked (the point, the step budget) before any runs, the whole bench too.
    let mut total_steps = 0.0;
    for (k, case) in &cases {
        let k = *k;
        for job in &jobs {
            if let Job::BuiltIn(config) = job {
                preflight(case, config).map_err(|e| motion_of(k, e))?;
                total_steps +=
                    estimate_steps(case, config).map_err(|e| motion_of(k, e))? * repeats as f64;
            }
        }
    }
    if total_steps > MAX_TOTAL_STEPS {
        return Err(setting(&["repeats", "tolerances", "t-end"], format!(
            "the benchmark needs at least about {} steps in all ({} runs of {} repeats), more than the limit of {}; ask for fewer",
            rsts_dynamics::short(total_steps),
            built_in_jobs * cases.len(),
            repeats,
            rsts_dynamics::short(MAX_TOTAL_STEPS)
        )));
    }

    observer.start(jobs.len() * cases.len());
    let asked: Vec<(String, String)> = specs
        .iter()
        .map(|s| {
            (
                s.name.as_str().to_string(),
                s.direction.as_str().to_string(),
            )
        })
        .collect();
    let mut rows: Vec<BenchRow> = Vec::new();
    let mut labels: Vec<RowLabel> = Vec::new();
    let mut environment = Environment::detect();
    for (k, case) in &cases {
        let k = *k;
        // One reference per precision and motion.
        let mut references: BTreeMap<u32, Reference> = BTreeMap::new();
        let mut reference_at = |bits: u32| -> Result<Reference, HarnessError> {
            Ok(match references.entry(bits) {
                Entry::Occupied(e) => e.get().clone(),
                Entry::Vacant(e) => e
                    .insert(Reference::new(case, bits).map_err(|e| motion_of(k, plain(e)))?)
                    .clone(),
            })
        };
        let motion = ensemble.as_ref().map(|_| k);
        let what_motion = motion.map_or(String::new(), |k| format!(" (motion {k})"));
        for job in jobs.iter_mut() {
            match job {
                Job::BuiltIn(config) => {
                    let label = label_of(config.method, mp_digits);
                    let tol = config.tolerances.rtol;
                    observer.running(&format!("{label} at {tol:e}{what_motion}"))?;
                    let reference = reference_at(reference_bits(config))?;
                    let mut row = measure_against(&reference, config, repeats).map_err(|e| {
                        motion_of(
                            k,
                            HarnessError::Integrator(format!("{label} at tolerance {tol:e}: {e}")),
                        )
                    })?;
                    if !specs.is_empty() {
                        let mut once = *config;
                        let (times, states) = run_once(&reference, &mut once).map_err(plain)?;
                        let ev = events_of_run(case, &specs, None, &times, &states)?;
                        row.events = Some(ev.counts());
                    }
                    if let Some(k) = dense {
                        row.dense = Some(crate::dense::dense_of_method(case, config, k)?);
                    }
                    row.motion = motion;
                    rows.push(row);
                    labels.push(RowLabel {
                        label,
                        external: false,
                    });
                }
                Job::Outside(integrator, what) => {
                    integrator.ask_events(&asked);
                    let tol = integrator.tolerances().map_or(f64::NAN, |t| t.rtol);
                    observer.running(&format!("{} at {tol:e}{what_motion}", integrator.name()))?;
                    let reference = reference_at(reference_bits_for(integrator.working_bits()))?;
                    let mut row = measure_integrator(&reference, integrator.as_mut(), repeats)
                        .map_err(|e| {
                            motion_of(
                                k,
                                HarnessError::Integrator(format!(
                                    "{what} at tolerance {tol:e}: {e}"
                                )),
                            )
                        })?;
                    if !specs.is_empty() {
                        let answered = integrator.answered_events();
                        let (mut times, states) = match answered {
                            Some(_) => (Vec::new(), Vec::new()),
                            None => run_once(&reference, integrator.as_mut()).map_err(plain)?,
                        };
                        if times.is_empty() {
                            times.push(case.t_end_f64());
                        }
                        let ev = events_of_run(case, &specs, answered.as_deref(), &times, &states)?;
                        row.events = Some(ev.counts());
                    }
                    if let Some(k) = dense {
                        integrator.ask_dense(Some(k));
                        let once = run_once(&reference, integrator.as_mut());
                        integrator.ask_dense(None);
                        once.map_err(plain)?;
                        let samples = integrator.answered_dense().ok_or_else(|| {
                            HarnessError::Integrator(format!(
                                "{what}: --dense needs an integrator that reports its step times and its samples inside them; {} does not",
                                integrator.name()
                            ))
                        })?;
                        row.dense = Some(crate::dense::dense_of_samples(case, k, &samples)?);
                    }
                    row.motion = motion;
                    environment.record(integrator.as_ref());
                    labels.push(RowLabel {
                        label: row.method.clone(),
                        external: true,
                    });
                    rows.push(row);
                }
            }
            observer.done();
        }
    }

    for (r, l) in rows.iter().zip(&labels) {
        if !(r.max_error.is_finite() && r.integration_seconds.is_finite()) {
            return Err(HarnessError::Integrator(format!(
                "{} at tolerance {}{}: the maximum error is not finite (the integrated motion left f64's range)",
                l.label,
                rsts_dynamics::short(r.tolerance),
                r.motion.map_or(String::new(), |k| format!(" (motion {k})"))
            )));
        }
    }
    let fits = fit_tolerances(&rows);
    let shard = shard
        .zip(digest)
        .map(|((sh, _), d)| EnsembleShard::new(sh, d, &rows, &labels));
    Ok(BenchReport {
        case,
        repeats,
        taylor_mp_digits: builtins
            .contains(&MethodName::TaylorMp)
            .then_some(mp_digits),
        bands: if ensemble.is_some() {
            bands(&rows)
        } else {
            Vec::new()
        },
        ensemble,
        rows,
        fits,
        environment,
        shard,
        labels,
    })
}

/// An error shown as its text alone (no setting named).
fn plain(e: HarnessError) -> HarnessError {
    HarnessError::Integrator(e.to_string())
}

/// The optimistic step estimate of one run of `config` on `case` (its initial state from the
/// closed form in f64).
fn estimate_steps(case: &Case, config: &MethodConfig) -> Result<f64, HarnessError> {
    use rsts_dynamics::integrators::Problem;
    let motion = case.motion.explicit::<f64>(53, 0.0)?;
    let s = motion.at(&0.0);
    let problem = Problem {
        fields: case.motion.fields(53).map_err(|e| plain(e.into()))?,
        initial: rsts_dynamics::State {
            omega: [s.omega[0], s.omega[1], s.omega[2]],
            alpha: [s.alpha[0], s.alpha[1], s.alpha[2]],
            beta: [s.beta[0], s.beta[1], s.beta[2]],
        },
    };
    let grid = case.grid().map_err(plain)?;
    Ok(config.estimate_steps(&problem, &grid))
}

/// taylor-mp carries its digits in tables and legends.
pub fn label_of(method: MethodName, mp_digits: u32) -> String {
    match method {
        MethodName::TaylorMp => format!("taylor-mp-{mp_digits}d"),
        m => m.as_str().to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::OutsideMethod;
    use crate::Propagated;
    use rsts_dynamics::integrators::Rk4;

    /// RK4 with a step from the tolerance (tol^(1/4), at least 0.01), as a user's integrator object.
    struct MyRk4;

    impl OutsideMethod for MyRk4 {
        fn what(&self) -> String {
            "my-rk4".into()
        }

        fn at(
            &mut self,
            tolerances: Tolerances,
            _digits: u32,
        ) -> Result<Box<dyn BenchIntegrator>, HarnessError> {
            let step = tolerances.rtol.powf(0.25).max(0.01);
            Ok(Box::new(
                Propagated::new(Rk4::new(step))
                    .named("my-rk4")
                    .with_tolerances(tolerances),
            ))
        }
    }

    #[derive(Default)]
    struct Notes(Vec<String>, usize);

    impl BenchObserver for Notes {
        fn note(&mut self, text: &str) {
            self.0.push(text.into());
        }
        fn done(&mut self) {
            self.1 += 1;
        }
    }

    /// Built-ins first (each once), then the methods from outside made at each tolerance; a
    /// tolerance below a built-in's round-off is a note, not a row.
    #[test]
    fn a_user_integrator_is_a_method_beside_the_builtins() {
        let mut mine = MyRk4;
        let request = BenchRequest {
            case: Case::default_i_plus()
                .with_grid(rsts_closed_form::Decimal::parse("5").unwrap(), 6),
            methods: vec![
                BenchMethod::Outside(&mut mine),
                BenchMethod::BuiltIn(MethodName::Dop853),
                BenchMethod::BuiltIn(MethodName::Dop853),
            ],
            tolerances: vec![1e-4, 1e-8, 1e-30],
            repeats: 1,
            digits: None,
            events: Vec::new(),
        };
        let mut notes = Notes::default();
        let report = bench(request, &mut notes).unwrap();
        let methods: Vec<&str> = report.rows.iter().map(|r| r.method.as_str()).collect();
        assert_eq!(methods, ["dop853", "dop853", "my-rk4", "my-rk4", "my-rk4"]);
        assert_eq!(notes.1, 5, "one done per run");
        assert_eq!(notes.0.len(), 1, "{:?}", notes.0);
        assert!(notes.0[0].starts_with("note: skipping dop853 at tolerance 1e-30"));
        assert!(report.labels[2].external && !report.labels[1].external);
        let rk4: Vec<f64> = report.rows[2..].iter().map(|r| r.max_error).collect();
        assert!(rk4[1] < 1e-3 * rk4[0], "{rk4:?}");
        assert_eq!(report.rows[2].steps, Some(50), "step 0.1 over T = 5");
        assert_eq!(report.rows[2].rhs_evals, Some(200), "4 evaluations a step");
        assert_eq!(report.fits.len(), 2);
        assert_eq!(report.taylor_mp_digits, None);
    }

    #[test]
    fn default_digits_cover_the_smallest_tolerance() {
        assert_eq!(default_mp_digits(1e-70), 80);
        assert_eq!(default_mp_digits(1e-8), 18);
        assert_eq!(default_mp_digits(0.5), 11);
    }
}
