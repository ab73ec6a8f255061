//! A run of an expanded suite: a case, a torus and a method (or the closed-form check).

use super::*;

/// What a run does.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum RunKind {
    /// An integrator against the closed form (the harness).
    Integrator {
        method: String,
        rtol: f64,
        atol: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        digits: Option<u32>,
        #[serde(skip_serializing_if = "Option::is_none")]
        step: Option<f64>,
    },
    /// The closed form in f64 against itself at 50 digits, and its Euler–Poisson residual.
    ClosedForm,
    /// A built-in method at fixed steps: its observed order (`rsts convergence`).
    Convergence {
        method: String,
        steps: Vec<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        order: Option<usize>,
        #[serde(skip_serializing_if = "Option::is_none")]
        digits: Option<u32>,
    },
    /// An external integrator (`[adapters.NAME]`) against the closed form.
    External {
        method: String,
        command: Vec<String>,
        rtol: f64,
        atol: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        digits: Option<u32>,
        #[serde(skip_serializing_if = "Option::is_none")]
        timeout: Option<f64>,
    },
}

/// One run of a suite: a case, a torus and a method (or the closed-form check).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Run {
    pub id: String,
    pub case: String,
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    pub torus: usize,
    pub phase1: f64,
    pub phase2: f64,
    pub t_end: f64,
    pub samples: usize,
    pub camera: String,
    #[serde(flatten)]
    pub kind: RunKind,
    pub thresholds: Thresholds,
}

impl Run {
    /// The harness case.
    pub fn harness_case(&self) -> rsts_harness::Case {
        // A suite's numbers as written: a TOML float is the shortest decimal that rounds to it.
        let d =
            |x: f64| rsts_closed_form::Decimal::shortest(x).expect("a suite's numbers are finite");
        let motion = rsts_closed_form::Motion {
            a: d(self.a),
            b: d(self.b),
            m: d(self.m),
            h: d(self.h),
            torus: self.torus,
            phase1: d(self.phase1),
            phase2: d(self.phase2),
        };
        rsts_harness::Case::new(motion, d(self.t_end), self.samples)
    }

    /// The method config of an integrator run.
    pub fn method_config(&self) -> Result<Option<MethodConfig>, ValidateError> {
        match &self.kind {
            RunKind::ClosedForm | RunKind::External { .. } | RunKind::Convergence { .. } => {
                Ok(None)
            }
            RunKind::Integrator {
                method,
                rtol,
                atol,
                digits,
                step,
            } => Ok(Some(method_config(method, *rtol, *atol, *digits, *step)?)),
        }
    }
}

pub(super) fn method_config(
    method: &str,
    rtol: f64,
    atol: f64,
    digits: Option<u32>,
    step: Option<f64>,
) -> Result<MethodConfig, ValidateError> {
    let name: MethodName = method
        .parse()
        .map_err(|e| ValidateError::Suite(format!("{e}")))?;
    let tol = Tolerances::new(rtol, atol).map_err(|e| ValidateError::Suite(format!("{e}")))?;
    let mut config =
        MethodConfig::new(name, tol, step).map_err(|e| ValidateError::Suite(format!("{e}")))?;
    if let Some(d) = digits {
        config = config
            .with_digits(d)
            .map_err(|e| ValidateError::Suite(format!("{e}")))?;
    }
    Ok(config)
}
