//! Convergence cases of a suite (`convergence = { steps, order }`, held by `min_order`): their
//! expansion into runs, one per built-in method and torus, and their execution by
//! `rsts_harness::convergence` (docs/convergence.md).

use rsts_dynamics::integrators::MethodName;
use rsts_harness::{ConvergencePlan, FixedStepIntegrator, FixedStepMethod};
use serde::Deserialize;

use crate::run::RunResult;
use crate::suite::{Run, RunKind};

/// `convergence = { steps = [...], order = P }` of a case.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConvergenceSpec {
    /// The fixed steps (at least 3; each made a whole fraction of the sample spacing).
    pub steps: Vec<f64>,
    /// Order of the Taylor methods.
    pub order: Option<usize>,
}

/// The runs of a convergence case on one torus: each built-in method at the fixed steps, checked
/// here (the steps against the grid, the Taylor order) so a bad case is a suite error.
pub(crate) fn convergence_runs(
    base: &Run,
    methods: &[String],
    conv: &ConvergenceSpec,
    digits: Option<u32>,
) -> Result<Vec<Run>, String> {
    let plan = ConvergencePlan::new(base.harness_case(), &conv.steps)
        .map_err(|err| format!("convergence: {err}"))?;
    let mut runs = Vec::new();
    for method in methods {
        let name: MethodName = method.parse().map_err(|err| {
            format!("convergence: {err} (convergence cases take built-in methods)")
        })?;
        let d = digits.unwrap_or(rsts_dynamics::integrators::DEFAULT_MP_DIGITS);
        let fixed = FixedStepMethod::new(name, conv.order, d)
            .map_err(|err| format!("convergence: {err}"))?;
        runs.push(Run {
            id: format!("{}/t{}/{}/order", base.case, base.torus, fixed.name()),
            kind: RunKind::Convergence {
                method: name.as_str().to_string(),
                steps: plan.steps.clone(),
                order: fixed.order,
                digits: (name == MethodName::TaylorMp).then_some(d),
            },
            ..base.clone()
        });
    }
    Ok(runs)
}

/// A convergence run: the method at the fixed steps, its order fitted.
pub(crate) fn execute(
    run: &Run,
    method: &str,
    steps: &[f64],
    order: Option<usize>,
    r: &mut RunResult,
) {
    let result = method
        .parse::<rsts_dynamics::integrators::MethodName>()
        .map_err(|e| e.to_string())
        .and_then(|m| {
            let digits = r
                .digits
                .unwrap_or(rsts_dynamics::integrators::DEFAULT_MP_DIGITS);
            FixedStepMethod::new(m, order, digits).map_err(|e| e.to_string())
        })
        .and_then(|mut method| {
            let plan =
                ConvergencePlan::new(run.harness_case(), steps).map_err(|e| e.to_string())?;
            rsts_harness::convergence(&plan, &mut [&mut method]).map_err(|e| e.to_string())
        });
    match result {
        Ok(mut report) => r.convergence = report.fits.pop(),
        Err(e) => r.error = Some(e),
    }
}
