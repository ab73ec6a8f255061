//! The suite file as written (TOML): defaults, cases, adapters, thresholds, placements.

use super::*;

/// Thresholds a run must meet (absent: not checked).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Thresholds {
    /// max over samples of max |x_int − x_exact| over (ω, α, β).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_state_error: Option<f64>,
    /// max state error ≤ this × the run's rtol (also spelt `max_error_over_tolerance`, as bench
    /// names the figure).
    #[serde(
        skip_serializing_if = "Option::is_none",
        alias = "max_error_over_tolerance"
    )]
    pub max_state_error_over_tol: Option<f64>,
    /// Correct digits: the run's `mescd_min` (Bari test set, docs/compare.md) ≥ this.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub min_mescd: Option<f64>,
    /// max drift of H, K, G and of the constraints.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_drift: Option<f64>,
    /// max distance from N.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_off_n: Option<f64>,
    /// Closed-form check: max |f64 − 50 digits| over the sampled times.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_form_f64: Option<f64>,
    /// Closed-form check: max Euler–Poisson residual at 50 digits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_form_residual: Option<f64>,
    /// Convergence runs: the observed order must be at least this.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_order: Option<f64>,
    /// Convergence runs: `"round-off"` fails a floor above round-off and competing windows
    /// (what `rsts convergence --strict` exits 1 on; docs/convergence.md).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub floor: Option<FloorThreshold>,
}

/// The only floor a suite may require: round-off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
pub enum FloorThreshold {
    #[serde(rename = "round-off")]
    RoundOff,
}

impl Thresholds {
    /// Field-wise: `self` where set, else `base`.
    pub(super) fn over(self, base: Thresholds) -> Thresholds {
        Thresholds {
            max_state_error: self.max_state_error.or(base.max_state_error),
            max_state_error_over_tol: self
                .max_state_error_over_tol
                .or(base.max_state_error_over_tol),
            min_mescd: self.min_mescd.or(base.min_mescd),
            max_drift: self.max_drift.or(base.max_drift),
            max_off_n: self.max_off_n.or(base.max_off_n),
            closed_form_f64: self.closed_form_f64.or(base.closed_form_f64),
            closed_form_residual: self.closed_form_residual.or(base.closed_form_residual),
            min_order: self.min_order.or(base.min_order),
            floor: self.floor.or(base.floor),
        }
    }

    pub(super) fn check(&self, what: &str) -> Result<(), ValidateError> {
        for (name, v) in [
            ("max_state_error", self.max_state_error),
            ("max_state_error_over_tol", self.max_state_error_over_tol),
            ("min_mescd", self.min_mescd),
            ("max_drift", self.max_drift),
            ("max_off_n", self.max_off_n),
            ("closed_form_f64", self.closed_form_f64),
            ("closed_form_residual", self.closed_form_residual),
            ("min_order", self.min_order),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err(ValidateError::Suite(format!(
                        "{what}: threshold {name} must be a positive finite number, got {v}"
                    )));
                }
            }
        }
        Ok(())
    }
}

/// Which tori of the point: `"all"`, one index or a list.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Tori {
    Name(String),
    One(usize),
    List(Vec<usize>),
}

/// Placement of a point relative to the bifurcation diagram.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// A curve of Σ: `outer-a` (h = r²m − 2a), `outer-b` (h = −r²m − 2b), `hyperbola`
    /// (2p²m² + 2hm + 1 = 0), `inner-a` (h = r²m + 2a), `inner-b` (h = −r²m + 2b); h is the
    /// curve's h at the case's m, moved by `delta` to `side`.
    pub near: Option<String>,
    /// `above` or `below` (h larger or smaller than on the curve); the outer curves have one
    /// admissible side, which is the default.
    pub side: Option<String>,
    /// Distance in h from the curve or the equilibrium.
    pub delta: Option<f64>,
    /// ℓ at the case's m < 0: h = (ℓ² − 1 − 2p²m²)/(2m).
    pub ell: Option<f64>,
    /// An equilibrium (a corner of Σ): `p1` = (1/(a+b), −a−b), `p2` = (1/(a−b), b−a),
    /// `p3` = (−1/(a−b), a−b), `p4` = (−1/(a+b), a+b); the point is `delta` inside the region.
    pub equilibrium: Option<String>,
}

/// Settings shared by the defaults and the cases (each case field overrides the default).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Defaults {
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub t_end: Option<f64>,
    pub samples: Option<usize>,
    pub phase1: Option<f64>,
    pub phase2: Option<f64>,
    pub tori: Option<Tori>,
    pub methods: Option<Vec<String>>,
    pub tolerances: Option<Vec<f64>>,
    /// Digits of taylor-mp.
    pub digits: Option<u32>,
    /// Fixed step of rk4 (default: from the tolerance).
    pub step: Option<f64>,
    /// Also check the closed form itself (f64 against 50 digits, Euler–Poisson residual).
    pub closed_form: Option<bool>,
    #[serde(default)]
    pub thresholds: Thresholds,
}

/// One `[[case]]` of a suite file.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    pub name: String,
    /// The camera the point must lie in (checked).
    pub camera: Option<String>,
    pub m: Option<f64>,
    pub h: Option<f64>,
    pub place: Option<Placement>,
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub t_end: Option<f64>,
    pub samples: Option<usize>,
    pub phase1: Option<f64>,
    pub phase2: Option<f64>,
    pub tori: Option<Tori>,
    pub methods: Option<Vec<String>>,
    pub tolerances: Option<Vec<f64>>,
    pub digits: Option<u32>,
    pub step: Option<f64>,
    pub closed_form: Option<bool>,
    /// A convergence case: the methods at these fixed steps, the observed order fitted
    /// (`rsts convergence`); held by `min_order`.
    pub convergence: Option<ConvergenceSpec>,
    #[serde(default)]
    pub thresholds: Thresholds,
}

/// An external integrator of a suite (`[adapters.NAME]`), used by its name in `methods` like a
/// built-in method (protocol rsts-integrator/1, docs/own-integrator.md).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AdapterSpec {
    /// The program and its arguments (run without a shell).
    pub command: Vec<String>,
    /// Seconds one run may take (default 600).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timeout: Option<f64>,
}

/// A suite file.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteFile {
    pub name: Option<String>,
    pub description: Option<String>,
    #[serde(default)]
    pub defaults: Defaults,
    /// External integrators by name.
    #[serde(default)]
    pub adapters: BTreeMap<String, AdapterSpec>,
    #[serde(default, rename = "case")]
    pub cases: Vec<CaseSpec>,
}
