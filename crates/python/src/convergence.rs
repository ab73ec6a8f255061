//! `rsts.convergence`: built-in methods at fixed steps and their observed orders, the document
//! of `rsts convergence --format json` (the same library function and report type).

use pyo3::prelude::*;

use rsts_dynamics::integrators::MethodName;
use rsts_harness::{
    convergence_until as run, ConvergencePlan, FixedStepIntegrator, FixedStepMethod,
};

use crate::case::{int, whole, Case, Int};
use crate::{harness_error, report_dict, value_error, Interrupts};

/// Run built-in `methods` ("rk4", "dopri5", "dop853": step control off; "taylor-f64",
/// "taylor-dd", "taylor-mp" at `order`) at the fixed `steps` (at least 3; each made a whole
/// fraction of the sample spacing t_end/(samples - 1)) along `case` (default: `Case.default()`)
/// and fit each method's order over its asymptotic window: a dict with `case`, `rows` (method,
/// step, max_error, final_error, steps, rhs_evals) and `fits` (method, order, order_stderr, regimes, competing, floor,
/// window, excluded: [{step, why}]), equal to `rsts convergence --format json`.
///
/// The GIL is released while Rust works; Ctrl-C raises KeyboardInterrupt before the next run
/// (a method at a step).
#[pyfunction]
#[pyo3(signature = (methods, steps, case = None, t_end = 10.0, samples = Int::of(11), order = None, digits = Int::of(40)))]
#[allow(clippy::too_many_arguments)]
pub fn convergence<'py>(
    py: Python<'py>,
    methods: Vec<String>,
    steps: Vec<f64>,
    case: Option<Case>,
    t_end: f64,
    samples: Int,
    order: Option<Int>,
    digits: Int,
) -> PyResult<Bound<'py, PyAny>> {
    let order = int("order", order)?;
    let digits = digits.get("digits")?;
    let case = Case::or_default(case)?;
    let samples = whole("samples", samples)?;
    if methods.is_empty() {
        return Err(value_error(&["methods"], "give at least one method"));
    }
    let digits = u32::try_from(digits)
        .ok()
        .filter(|d| (10..=rsts_dynamics::integrators::MAX_MP_DIGITS).contains(d))
        .ok_or_else(|| value_error(&["digits"], format!("must be 10 to 10000, got {digits}")))?;
    let order = order
        .map(|p| usize::try_from(p).map_err(|_| value_error(&["order"], "must be positive")))
        .transpose()?;
    let mut fixed = Vec::new();
    for m in &methods {
        let name: MethodName = m.parse().map_err(|e| value_error(&["methods"], e))?;
        fixed.push(FixedStepMethod::new(name, order, digits).map_err(harness_error)?);
    }
    if order.is_some() && !fixed.iter().any(|f| f.order.is_some()) {
        return Err(value_error(
            &["order"],
            "only the Taylor methods take a fixed order",
        ));
    }
    let plan = ConvergencePlan::new(
        case.on_grid(crate::case::time("t_end", t_end)?, samples),
        &steps,
    )
    .map_err(harness_error)?;
    let (report, interrupt) = py.detach(|| {
        let mut refs: Vec<&mut dyn FixedStepIntegrator> = fixed
            .iter_mut()
            .map(|f| f as &mut dyn FixedStepIntegrator)
            .collect();
        let mut interrupts = Interrupts::new();
        let report = run(&plan, &mut refs, &mut || interrupts.stopped());
        (report, interrupts.take())
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    report_dict(py, &report.map_err(harness_error)?)
}
