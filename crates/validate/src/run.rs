//! Running the runs of a suite in parallel (rayon) and judging each against its thresholds.

use std::time::Instant;

use rayon::prelude::*;
use rsts_closed_form::TorusChoice;
use rsts_dynamics::integrators::Tolerances;
use rsts_external::Exec;
use rsts_harness::geometry::{ErrorSplit, NormalSummary, PhaseErrorSummary};
use rsts_harness::{
    compare_integrator, CompareOptions, Integrator, Observer, OrderFit, SampleRecord,
};
use serde::{Deserialize, Serialize};

use crate::closed_form_check::{self, ClosedFormCheck};
use crate::growth::{self, Growth};
use crate::suite::{Run, RunKind, Thresholds};
use crate::ValidateError;

/// At most this many points of each error series are kept in the report (for the plots).
pub const SERIES_POINTS: usize = 400;

/// Outcome of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    Pass,
    Fail,
    /// The run could not be done (the integrator or the closed form gave an error).
    Error,
}

/// Errors and cost of an integrator run (deterministic for a machine).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    pub max_state_error: f64,
    pub final_state_error: f64,
    pub max_orientation_error: f64,
    #[serde(rename = "drift_H")]
    pub drift_h: f64,
    #[serde(rename = "drift_K")]
    pub drift_k: f64,
    #[serde(rename = "drift_G")]
    pub drift_g: f64,
    pub drift_constraints: f64,
    #[serde(rename = "off_N")]
    pub off_n: f64,
    /// What the run cost (null when the integrator does not say).
    pub steps: Option<u64>,
    pub rejected_steps: Option<u64>,
    pub rhs_evals: Option<u64>,
    pub samples_compared: usize,
    /// Correct digits of the worst sample (Bari mescd; absent: no error at all).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub mescd_min: Option<f64>,
}

impl Figures {
    /// The largest drift of H, K, G and the constraints.
    pub fn max_drift(&self) -> f64 {
        [
            self.drift_h,
            self.drift_k,
            self.drift_g,
            self.drift_constraints,
        ]
        .into_iter()
        .fold(0.0, nan_max)
    }
}

/// max that keeps NaN (a NaN error must fail, not vanish).
pub fn nan_max(x: f64, y: f64) -> f64 {
    if x.is_nan() || y.is_nan() {
        f64::NAN
    } else {
        x.max(y)
    }
}

/// Growth fits of the state error and of the distance from N.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GrowthFits {
    pub state_error: Option<Growth>,
    #[serde(rename = "off_N")]
    pub off_n: Option<Growth>,
}

/// Error series, downsampled to at most [`SERIES_POINTS`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Series {
    pub t: Vec<f64>,
    pub state_error: Vec<f64>,
    #[serde(rename = "off_N")]
    pub off_n: Vec<f64>,
    /// The distance of the integrated state from N (NaN where its geometry could not be
    /// computed); empty in reports written before it was kept.
    #[serde(rename = "distance_from_N", default)]
    pub distance_from_n: Vec<f64>,
}

/// Wall-clock figures: the only part of a result that changes from run to run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// The integrator alone (harness measurement); 0 for the closed-form check.
    pub integration_seconds: f64,
    /// The whole run, comparison included.
    pub wall_seconds: f64,
}

/// The result of one run, as stored in report.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    pub id: String,
    pub case: String,
    pub camera: String,
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    pub torus: usize,
    pub t_end: f64,
    pub samples: usize,
    /// `closed-form` or the integrator's name.
    pub method: String,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub rtol: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub digits: Option<u32>,
    pub thresholds: Thresholds,
    pub status: Status,
    /// The thresholds missed, each naming the figure, its value and the threshold.
    pub failures: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub figures: Option<Figures>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub closed_form: Option<ClosedFormCheck>,
    #[serde(default)]
    pub growth: GrowthFits,
    #[serde(default)]
    pub series: Series,
    /// The geometry of the error, as in compare's JSON (docs/stability.md): departure from N,
    /// phase error, what dominates.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub normal: Option<NormalSummary>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub phase_error: Option<PhaseErrorSummary>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error_split: Option<ErrorSplit>,
    /// A convergence run: the observed order, its window and excluded steps.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub convergence: Option<OrderFit>,
    pub timing: Timing,
}

/// Collects every sample's errors.
#[derive(Default)]
struct Collector {
    t: Vec<f64>,
    state_error: Vec<f64>,
    off_n: Vec<f64>,
    distance_from_n: Vec<f64>,
}

impl Observer for Collector {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        self.t.push(r.t);
        self.state_error.push(r.errors.state_error);
        self.off_n.push(r.errors.off_n);
        self.distance_from_n.push(r.errors.distance_from_n);
        Ok(())
    }
}

/// Evenly spread indices, at most `n`, first and last included.
pub fn downsample_indices(len: usize, n: usize) -> Vec<usize> {
    if len <= n {
        return (0..len).collect();
    }
    let mut v: Vec<usize> = (0..n).map(|k| k * (len - 1) / (n - 1)).collect();
    v.dedup();
    v
}

fn judge(r: &mut RunResult) {
    let th = r.thresholds;
    let mut fails = Vec::new();
    let mut over = |name: &str, value: f64, limit: Option<f64>, note: String| {
        if let Some(limit) = limit {
            // NaN fails.
            if value.is_nan() || value > limit {
                fails.push(format!("{name} {value:.3e} > {limit:.3e}{note}"));
            }
        }
    };
    if let Some(f) = &r.figures {
        let growth = r
            .growth
            .state_error
            .map(|g| format!(" (grows {})", g.describe()))
            .unwrap_or_default();
        let off_growth = r
            .growth
            .off_n
            .map(|g| format!(" (grows {})", g.describe()))
            .unwrap_or_default();
        over(
            "max_state_error",
            f.max_state_error,
            th.max_state_error,
            growth.clone(),
        );
        if let (Some(k), Some(rtol)) = (th.max_state_error_over_tol, r.rtol) {
            over(
                "max_state_error",
                f.max_state_error,
                Some(k * rtol),
                format!(" = {k:e} × rtol{growth}"),
            );
        }
        over("max_drift", f.max_drift(), th.max_drift, String::new());
        over("off_N", f.off_n, th.max_off_n, off_growth);
    }
    if let Some(c) = &r.closed_form {
        over(
            "closed_form_f64",
            c.f64_error,
            th.closed_form_f64,
            String::new(),
        );
        over(
            "closed_form_residual",
            c.residual,
            th.closed_form_residual,
            String::new(),
        );
    }
    if let (Some(min), Some(f)) = (th.min_mescd, &r.figures) {
        let digits = f.mescd_min.unwrap_or(f64::INFINITY);
        // NaN fails.
        if digits.is_nan() || digits < min {
            fails.push(format!("mescd_min {digits:.2} < {min:.2} correct digits"));
        }
    }
    if let (Some(min), Some(fit)) = (th.min_order, &r.convergence) {
        // NaN fails.
        if fit.order.is_nan() || fit.order < min {
            fails.push(format!(
                "observed order {:.3} ± {:.3} < min_order {min}",
                fit.order, fit.order_stderr
            ));
        }
    }
    if let (Some(_), Some(fit)) = (th.floor, &r.convergence) {
        fails.extend(fit.doubts());
    }
    r.status = if r.error.is_some() {
        Status::Error
    } else if fails.is_empty() {
        Status::Pass
    } else {
        Status::Fail
    };
    r.failures = fails;
}

/// Do one run.
pub fn execute(run: &Run) -> RunResult {
    let started = Instant::now();
    let (method, rtol, digits) = match &run.kind {
        RunKind::ClosedForm => ("closed-form".to_string(), None, None),
        RunKind::Convergence {
            method,
            order,
            digits,
            ..
        } => (
            order.map_or(method.clone(), |p| format!("{method}-p{p}")),
            None,
            *digits,
        ),
        RunKind::External {
            method,
            rtol,
            digits,
            ..
        } => (method.clone(), Some(*rtol), *digits),
        RunKind::Integrator {
            method,
            rtol,
            digits,
            ..
        } => (method.clone(), Some(*rtol), *digits),
    };
    let mut r = RunResult {
        id: run.id.clone(),
        case: run.case.clone(),
        camera: run.camera.clone(),
        a: run.a,
        b: run.b,
        m: run.m,
        h: run.h,
        torus: run.torus,
        t_end: run.t_end,
        samples: run.samples,
        method,
        rtol,
        digits,
        thresholds: run.thresholds,
        status: Status::Pass,
        failures: Vec::new(),
        error: None,
        figures: None,
        closed_form: None,
        growth: GrowthFits::default(),
        series: Series::default(),
        normal: None,
        phase_error: None,
        error_split: None,
        convergence: None,
        timing: Timing::default(),
    };
    if let RunKind::Convergence {
        method,
        steps,
        order,
        ..
    } = &run.kind
    {
        crate::convergence::execute(run, method, steps, *order, &mut r);
        judge(&mut r);
        r.timing.wall_seconds = started.elapsed().as_secs_f64();
        return r;
    }
    let external = match &run.kind {
        RunKind::External {
            method,
            command,
            rtol,
            atol,
            digits,
            timeout,
        } => Some(external(method, command, *rtol, *atol, *digits, *timeout)),
        _ => None,
    };
    match run.method_config() {
        Err(e) => r.error = Some(e.to_string()),
        Ok(None) if external.is_some() => match external.expect("checked") {
            Err(e) => r.error = Some(e),
            Ok(mut exec) => integrate_run(run, &mut exec, &mut r),
        },
        Ok(None) => {
            let choice = TorusChoice {
                torus: run.torus,
                phase1: run.phase1,
                phase2: run.phase2,
            };
            let times = closed_form_check::check_times(run.t_end, run.samples);
            match closed_form_check::check(run.a, run.b, run.m, run.h, choice, &times) {
                Ok(c) => r.closed_form = Some(c),
                Err(e) => r.error = Some(e.to_string()),
            }
        }
        Ok(Some(mut config)) => integrate_run(run, &mut config, &mut r),
    }
    judge(&mut r);
    r.timing.wall_seconds = started.elapsed().as_secs_f64();
    r
}

/// An adapter's integrator.
fn external(
    name: &str,
    command: &[String],
    rtol: f64,
    atol: f64,
    digits: Option<u32>,
    timeout: Option<f64>,
) -> Result<Exec, String> {
    let tol = Tolerances::new(rtol, atol).map_err(|e| e.to_string())?;
    let mut exec = Exec::from_argv(command.to_vec(), tol)?.named(name);
    if let Some(d) = digits {
        exec = exec.with_digits(d)?;
    }
    if let Some(t) = timeout {
        exec = exec.with_timeout(t)?;
    }
    Ok(exec)
}

/// Compare an integrator along the run's case: figures, growth fits, series.
fn integrate_run(run: &Run, integrator: &mut dyn Integrator, r: &mut RunResult) {
    let mut obs = Collector::default();
    let options = CompareOptions::default();
    match compare_integrator(&run.harness_case(), integrator, &options, &mut obs) {
        Err(e) => r.error = Some(e.to_string()),
        Ok(rep) => {
            r.figures = Some(Figures {
                max_state_error: rep.max_state_error,
                final_state_error: rep.final_state_error,
                max_orientation_error: rep.max_orientation_error,
                drift_h: rep.drift.h,
                drift_k: rep.drift.k,
                drift_g: rep.drift.g,
                drift_constraints: rep.drift.constraints,
                off_n: rep.drift.off_n,
                steps: rep.steps,
                rejected_steps: rep.rejected_steps,
                rhs_evals: rep.rhs_evals,
                samples_compared: rep.samples_compared,
                mescd_min: Some(rep.correct_digits.mescd_min).filter(|d| d.is_finite()),
            });
            // An integrator's run is always timed (kept at 0 were it not).
            r.timing.integration_seconds = rep.integration_seconds.unwrap_or_default();
            r.normal = rep.normal.clone();
            r.phase_error = rep.phase_error.clone();
            r.error_split = rep.error_split.clone();
            r.growth = GrowthFits {
                state_error: growth::fit(&obs.t, &obs.state_error),
                off_n: growth::fit(&obs.t, &obs.off_n),
            };
            let idx = downsample_indices(obs.t.len(), SERIES_POINTS);
            r.series = Series {
                t: idx.iter().map(|&k| obs.t[k]).collect(),
                state_error: idx.iter().map(|&k| obs.state_error[k]).collect(),
                off_n: idx.iter().map(|&k| obs.off_n[k]).collect(),
                distance_from_n: idx.iter().map(|&k| obs.distance_from_n[k]).collect(),
            };
        }
    }
}

/// Do all runs on `jobs` threads (0: rayon's default, the number of cores); results sorted by id.
pub fn execute_all(
    runs: &[Run],
    jobs: usize,
    progress: &(dyn Fn(&RunResult) + Sync),
) -> Result<Vec<RunResult>, ValidateError> {
    if jobs != 0 {
        rsts_harness::threads::check_jobs(jobs)
            .map_err(|e| ValidateError::Usage(format!("jobs: {e}")))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| ValidateError::Run(format!("cannot start {jobs} threads: {e}")))?;
    let mut results: Vec<RunResult> = pool.install(|| {
        runs.par_iter()
            .map(|run| {
                let r = execute(run);
                progress(&r);
                r
            })
            .collect()
    });
    results.sort_by(|x, y| x.id.cmp(&y.id));
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::Suite;

    #[test]
    fn downsampling_keeps_both_ends_and_at_most_n() {
        assert_eq!(downsample_indices(3, 400), vec![0, 1, 2]);
        let v = downsample_indices(10_001, 400);
        assert_eq!(v.len(), 400);
        assert_eq!((v[0], *v.last().unwrap()), (0, 10_000));
    }

    #[test]
    fn a_loose_run_passes_loose_thresholds_and_fails_strict_ones_naming_them() {
        let text = |thr: &str| {
            format!(
                "[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\nt_end = 20.0\nsamples = 101\nmethods = [\"dopri5\"]\ntolerances = [1e-6]\n[case.thresholds]\n{thr}\n"
            )
        };
        let loose = Suite::parse(&text("max_state_error = 1e-2\nmax_drift = 1e-3"), "s").unwrap();
        let results = execute_all(&loose.runs, 2, &|_| {}).unwrap();
        assert_eq!(results.len(), 2);
        assert!(
            results.iter().all(|r| r.status == Status::Pass),
            "{results:?}"
        );
        let cf = &results[0];
        assert_eq!(cf.method, "closed-form");
        assert!(cf.closed_form.unwrap().f64_error < 1e-12);
        let int = &results[1];
        assert_eq!(int.camera, "I+");
        let f = int.figures.unwrap();
        assert!(f.max_state_error > 1e-12 && f.steps > Some(0), "{f:?}");
        assert_eq!(int.series.t.len(), 101);

        let strict = Suite::parse(&text("max_state_error = 1e-15"), "s").unwrap();
        let results = execute_all(&strict.runs, 1, &|_| {}).unwrap();
        let int = &results[1];
        assert_eq!(int.status, Status::Fail);
        assert!(
            int.failures[0].starts_with("max_state_error"),
            "{:?}",
            int.failures
        );
        // Same figures whatever the number of threads.
        assert_eq!(int.figures, Some(f));
    }

    /// `min_mescd` and `max_error_over_tolerance` (the bench name of max_state_error_over_tol)
    /// pass a run that meets them and fail, naming the figure, one that does not.
    #[test]
    fn correct_digits_and_error_over_tolerance_thresholds() {
        let text = |thr: &str| {
            format!(
                "[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\nt_end = 10.0\nsamples = 21\nmethods = [\"dop853\"]\ntolerances = [1e-10]\nclosed_form = false\n[case.thresholds]\n{thr}\n"
            )
        };
        let run = |thr: &str| {
            let suite = Suite::parse(&text(thr), "s").unwrap();
            execute_all(&suite.runs, 1, &|_| {}).unwrap().remove(0)
        };
        let r = run("min_mescd = 6.0\nmax_error_over_tolerance = 1e4");
        assert_eq!(r.status, Status::Pass, "{:?}", r.failures);
        let digits = r.figures.unwrap().mescd_min.unwrap();
        // dop853 at 1e-10 over T = 10: about 9 correct digits.
        assert!(digits > 7.0 && digits < 12.0, "{digits}");
        assert_eq!(r.thresholds.max_state_error_over_tol, Some(1e4));
        let r = run(&format!("min_mescd = {}", digits + 0.5));
        assert_eq!(r.status, Status::Fail);
        assert!(r.failures[0].starts_with("mescd_min"), "{:?}", r.failures);
        let r = run("max_error_over_tolerance = 1e-3");
        assert_eq!(r.status, Status::Fail);
        assert!(r.failures[0].contains("rtol"), "{:?}", r.failures);
        assert!(Suite::parse(&text("min_mescd = -1.0"), "s").is_err());
    }

    #[test]
    fn runs_report_the_geometry_of_their_error_as_compare_does() {
        use rsts_closed_form::manifold::NormalType;
        // Camera V (m < 0, N normally hyperbolic) and I+ (elliptic), 1e-8.
        let text = "[[case]]\nname = \"v\"\nm = -0.7092\nh = 1.5643\ntori = [2]\nt_end = 100.0\nsamples = 1001\nmethods = [\"dopri5\"]\ntolerances = [1e-8]\nclosed_form = false\n[[case]]\nname = \"i\"\nm = 0.3\nh = -0.375\ntori = [0]\nt_end = 100.0\nsamples = 1001\nmethods = [\"dopri5\"]\ntolerances = [1e-8]\nclosed_form = false\n";
        let suite = Suite::parse(text, "s").unwrap();
        let results = execute_all(&suite.runs, 2, &|_| {}).unwrap();
        let by = |case: &str| results.iter().find(|r| r.case == case).unwrap();
        let (v, i) = (by("v"), by("i"));
        let n = v.normal.as_ref().unwrap();
        assert_eq!(n.kind, NormalType::Hyperbolic);
        let g = n.growth.unwrap();
        assert_eq!(g.kind, growth::Model::Exponential, "{n:?}");
        assert!(g.rate > 0.18 && g.rate < 0.3, "{g:?}");
        assert_eq!(v.error_split.as_ref().unwrap().dominant, "departure from N");
        let n = i.normal.as_ref().unwrap();
        assert_eq!(n.kind, NormalType::Elliptic);
        assert!(n.distance_from_n.max < 1e-6, "{n:?}");
        assert_eq!(
            i.error_split.as_ref().unwrap().dominant,
            "drift along the torus"
        );
        // report.json and baselines read it back.
        let back: RunResult = serde_json::from_str(&serde_json::to_string(v).unwrap()).unwrap();
        assert_eq!(back.normal, v.normal);
        assert_eq!(back.error_split, v.error_split);
        // A NaN (written as null) reads back as NaN.
        let mut nan = v.clone();
        nan.normal.as_mut().unwrap().distance_from_n.last = f64::NAN;
        let back: RunResult = serde_json::from_str(&serde_json::to_string(&nan).unwrap()).unwrap();
        assert!(back.normal.unwrap().distance_from_n.last.is_nan());
    }
}
