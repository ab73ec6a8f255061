//! `rsts.compare`: a built-in method or a Python callable against the closed form — the flow
//! of `rsts compare` ([`rsts_flows::compare`]), its document as a dict — and the callable as a
//! harness [`Integrator`].

use std::sync::{Arc, Mutex};
use std::time::Instant;

use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rug::Float;

use rsts_closed_form::events::EventSpec;
use rsts_dynamics::integrators::{MethodConfig, MethodName, Problem, Stats, Tolerances};
use rsts_dynamics::State;
use rsts_flows::compare::{CompareRequest, Method};
use rsts_flows::{FlowError, Limits, Times};
use rsts_harness::{
    check_times, HarnessError, Integrator, Observer, SampleRecord, Trajectory, DEFAULT_PIECES,
};

use crate::case::{int, whole, Case, Int};
use crate::{arrays, harness_error, report_dict, value_error, Interrupts};

/// A Python callable `f(x0, times, a, b, rtol, atol)` as an integrator: called once per run
/// (not restartable), with numpy arrays, the GIL held during the call, its time measured
/// around the call.
pub(crate) struct Callable {
    func: Arc<Py<PyAny>>,
    pub(crate) name: String,
    tolerances: Tolerances,
    /// The exception of the call or of its answer, raised as it is after the run (one slot
    /// shared by the callable's integrators at every tolerance).
    error: Arc<Mutex<Option<PyErr>>>,
}

impl Callable {
    pub(crate) fn new(func: &Bound<'_, PyAny>, tolerances: Tolerances) -> PyResult<Self> {
        let name = func
            .getattr("__qualname__")
            .or_else(|_| func.getattr("__name__"))
            .and_then(|n| n.extract::<String>())
            .unwrap_or_else(|_| "python".into());
        Ok(Self {
            func: Arc::new(func.clone().unbind()),
            name,
            tolerances,
            error: Arc::default(),
        })
    }

    /// The same callable at other tolerances (sharing its error slot).
    pub(crate) fn at(&self, tolerances: Tolerances) -> Self {
        Self {
            func: self.func.clone(),
            name: self.name.clone(),
            tolerances,
            error: self.error.clone(),
        }
    }

    /// The exception a call raised (or its answer caused), once.
    pub(crate) fn take_error(&self) -> Option<PyErr> {
        self.error.lock().ok()?.take()
    }

    /// Call the function and read its answer: (len(times), 9) finite values.
    fn call(
        &self,
        py: Python<'_>,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> PyResult<(Vec<[f64; 9]>, f64)> {
        let x0: Vec<f64> = problem
            .initial
            .to_array()
            .iter()
            .map(Float::to_f64)
            .collect();
        let x0 = PyArray1::from_vec(py, x0);
        let t = PyArray1::from_slice(py, times);
        let (a, b) = (problem.fields.a.to_f64(), problem.fields.b.to_f64());
        let tol = self.tolerances;
        let start = Instant::now();
        let out = self
            .func
            .call1(py, (x0, t, a, b, tol.rtol, tol.atol))?
            .into_bound(py);
        let seconds = start.elapsed().as_secs_f64();
        let what = format!("the integrator {} returned", self.name);
        if out.cast::<numpy::PyUntypedArray>().is_err() {
            return Err(PyValueError::new_err(format!(
                "{what} {}, not a numpy array of shape ({}, 9)",
                arrays::describe(&out),
                times.len()
            )));
        }
        let states = arrays::states(&out, &what, Some(times.len()), Some(times))?;
        Ok((states, seconds))
    }
}

impl Integrator for Callable {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn tolerances(&self) -> Option<Tolerances> {
        Some(self.tolerances)
    }

    fn working_bits(&self) -> u32 {
        rsts_dynamics::scalar::F64_BITS
    }

    /// Its time is measured around the call; its steps and evaluations are not seen (not
    /// known in compare and bench, not 0).
    fn stated_stats(&self) -> Option<rsts_harness::StatedStats> {
        Some(rsts_harness::StatedStats::default())
    }

    fn integrate(
        &mut self,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        check_times(times)?;
        let bits = problem.initial.omega[0].prec();
        match Python::attach(|py| self.call(py, problem, times)) {
            Ok((rows, seconds)) => Ok(Trajectory {
                times: times.to_vec(),
                states: rows
                    .iter()
                    .map(|r| State::from_slice(r).map(|x| Float::with_val(bits, *x)))
                    .collect(),
                stats: Stats {
                    integration_seconds: seconds,
                    ..Stats::default()
                },
                wall_seconds: None,
            }),
            Err(e) => {
                let text = Python::attach(|py| e.value(py).to_string());
                if let Ok(mut slot) = self.error.lock() {
                    *slot = Some(e);
                }
                Err(HarnessError::Integrator(text))
            }
        }
    }

    fn restartable(&self) -> bool {
        false
    }
}

/// Stops a run on Ctrl-C (polled between samples and pieces).
pub(crate) struct Watch(pub(crate) Interrupts);

impl Observer for Watch {
    /// Only the errors are looked at.
    fn wants_states(&self) -> bool {
        false
    }

    fn on_sample(&mut self, _record: &SampleRecord) -> Result<(), String> {
        if self.0.stopped() {
            return Err("interrupted".into());
        }
        Ok(())
    }

    fn should_stop(&self) -> bool {
        self.0.error.is_some()
    }
}

impl rsts_flows::check::Progress for Watch {}

/// The integrator of a comparison: a built-in method or a callable.
enum Chosen {
    Method(MethodConfig),
    Callable(Callable),
}

/// `events=`: names such as "omega1:up" (each once).
pub(crate) fn event_specs(names: Option<Vec<String>>, what: &str) -> PyResult<Vec<EventSpec>> {
    let mut specs: Vec<EventSpec> = Vec::new();
    for s in names.unwrap_or_default() {
        let spec: EventSpec = s
            .parse()
            .map_err(|e| value_error(&[what], format!("'{s}': {e}")))?;
        if specs.iter().any(|p| p.name == spec.name) {
            return Err(value_error(
                &[what],
                format!("'{s}': {} is asked for twice", spec.name),
            ));
        }
        specs.push(spec);
    }
    Ok(specs)
}

/// Compare an integrator with the closed form along `case` (default: `Case.default()`) at
/// `samples` times evenly spaced on [0, t_end], or at `times` (1-D, from 0, strictly
/// increasing: used exactly as given): a dict with the keys of `rsts compare --format json`
/// (method, rtol, atol, digits, camera, samples_compared, max_state_error, final_state_error,
/// drift, steps, rhs_evals, integration_seconds, normal, phase_error, error_split, ...,
/// environment; with `events`, "events"; with `dense`, dense, dense_steps, step_max_error,
/// dense_max_error).
///
/// `integrator` is a built-in method name (rsts.METHODS: "rk4", "dopri5", "dop853",
/// "taylor-f64", "taylor-dd", "taylor-mp"; `digits` sets taylor-mp's) or a callable
/// `f(x0, times, a, b, rtol, atol)` returning a float array of shape (len(times), 9): the states
/// (omega, alpha, beta) at `times` from x0 at times[0] = 0. It is called once, in this process,
/// with numpy arrays; its time is measured around the call (integration_seconds; steps and
/// rhs_evals are None, not seen from outside). An exception
/// it raises propagates unchanged; an answer of the wrong shape, with NaN, or not an array
/// raises ValueError naming what was wrong.
///
/// `events`: names such as ["omega1:up", "gamma2"], located in the samples (cubic Hermite
/// interpolation) and matched with the exact events (docs/events.md). `dense=K`: K samples of a
/// built-in method's dense output inside each of its steps, checked apart from the step ends.
/// `pieces`: at most this many calls of a restartable integrator (Ctrl-C between them); no
/// digit of the report depends on it.
///
/// The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (integrator, case = None, t_end = 100.0, samples = Int::of(1001), rtol = 1e-10, atol = 1e-10, digits = None, times = None, events = None, dense = None, pieces = Int::of(DEFAULT_PIECES as i64)))]
#[allow(clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    integrator: &Bound<'py, PyAny>,
    case: Option<Case>,
    t_end: f64,
    samples: Int,
    rtol: f64,
    atol: f64,
    digits: Option<Int>,
    times: Option<&Bound<'py, PyAny>>,
    events: Option<Vec<String>>,
    dense: Option<Int>,
    pieces: Int,
) -> PyResult<Bound<'py, PyAny>> {
    let digits = int("digits", digits)?;
    let case = Case::or_default(case)?;
    let times = match times {
        Some(t) => {
            arrays::times_count(t, "times")?;
            Times::Binary(arrays::vector(t, "times")?)
        }
        None => Times::grid(
            crate::case::time("t_end", t_end)?,
            whole("samples", samples)?,
        ),
    };
    let tolerances = Tolerances::new(rtol, atol).map_err(|e| value_error(&["rtol", "atol"], e))?;
    let mut chosen = if let Ok(name) = integrator.extract::<String>() {
        let method: MethodName = name.parse().map_err(|e| value_error(&["integrator"], e))?;
        let mut config =
            MethodConfig::new(method, tolerances, None).map_err(|e| value_error(&["rtol"], e))?;
        if let Some(d) = digits {
            config = config
                .with_digits(u32::try_from(d).unwrap_or(0))
                .map_err(|e| value_error(&["digits"], e))?;
        }
        Chosen::Method(config)
    } else if integrator.is_callable() {
        Chosen::Callable(Callable::new(integrator, tolerances)?)
    } else {
        return Err(value_error(
            &["integrator"],
            format!(
                "expected a method name (one of {}) or a callable f(x0, times, a, b, rtol, atol), got {}",
                MethodName::ALL.map(|m| m.as_str()).join(", "),
                arrays::describe(integrator)
            ),
        ));
    };
    let events = event_specs(events, "events")?;
    let dense = dense.map(|k| whole("dense", k)).transpose()?;
    let pieces = whole("pieces", pieces)?;
    let result = py.detach(|| {
        let mut watch = Watch(Interrupts::new());
        let method = match &mut chosen {
            Chosen::Method(config) => Method::Builtin(*config),
            Chosen::Callable(callable) => Method::Outside(callable),
        };
        let request = CompareRequest {
            motion: case.motion.clone(),
            times,
            method,
            events,
            dense,
            pieces,
            mcap: None,
            svg: None,
            limits: Limits::default(),
        };
        let result = rsts_flows::compare::compare(request, &mut watch);
        (result, watch.0.take())
    });
    let outcome = finish(result, chosen_error(&mut chosen))?;
    report_dict(py, &outcome)
}

fn chosen_error(chosen: &mut Chosen) -> Option<PyErr> {
    match chosen {
        Chosen::Callable(c) => c.take_error(),
        Chosen::Method(_) => None,
    }
}

/// The outcome of a flow, or the exception that stopped it: the callable's own, then Ctrl-C's,
/// then the flow's error (ValueError for bad input, RuntimeError for a failed run).
pub(crate) fn finish<R>(
    (result, interrupt): (Result<R, FlowError>, Option<PyErr>),
    callable_error: Option<PyErr>,
) -> PyResult<R> {
    if let Some(e) = callable_error {
        return Err(e);
    }
    if let Some(e) = interrupt {
        return Err(e);
    }
    result.map_err(flow_error)
}

/// A flow's error as Python raises it.
pub(crate) fn flow_error(e: FlowError) -> PyErr {
    match e {
        FlowError::Harness(h) => harness_error(h),
        FlowError::Input { names, message } => value_error(&names, message),
        FlowError::Interrupted(_) => pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
        FlowError::Output { .. } => pyo3::exceptions::PyRuntimeError::new_err(e.to_string()),
    }
}

/// The report of a harness run, or the exception that stopped it: the callable's own, then
/// Ctrl-C's, then the harness's error as ValueError/RuntimeError.
pub(crate) fn finish_harness<R>(
    result: Result<(Result<R, HarnessError>, Option<PyErr>), HarnessError>,
    callable_error: Option<PyErr>,
) -> PyResult<R> {
    if let Some(e) = callable_error {
        return Err(e);
    }
    let (result, interrupt) = result.map_err(harness_error)?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    result.map_err(harness_error)
}
