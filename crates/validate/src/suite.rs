//! Suite files (TOML): defaults, cases, and their expansion into runs with stable ids.
//!
//! A case names a point (m, h) of N — given directly or placed relative to Σ, to the hyperbola
//! ℓ = 0 or to an equilibrium — the tori, the methods and tolerances, and the thresholds every run
//! must meet. Expansion turns every (torus, method, tolerance) into a [`Run`] with an id
//! `case/t<torus>/<method>@<tol>` (and `case/t<torus>/closed-form` for the check of the closed
//! form itself); ids are unique in a suite and sorted.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice};
use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use serde::{Deserialize, Serialize};

use crate::convergence::convergence_runs;
pub use crate::convergence::ConvergenceSpec;
use crate::ValidateError;

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
}

impl Thresholds {
    /// Field-wise: `self` where set, else `base`.
    fn over(self, base: Thresholds) -> Thresholds {
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
        }
    }

    fn check(&self, what: &str) -> Result<(), ValidateError> {
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
        rsts_harness::Case {
            a: self.a,
            b: self.b,
            m: self.m,
            h: self.h,
            torus: self.torus,
            phase1: self.phase1,
            phase2: self.phase2,
            t_end: self.t_end,
            samples: self.samples,
        }
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

fn method_config(
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

/// A parsed, expanded suite.
#[derive(Clone, Debug, PartialEq)]
pub struct Suite {
    pub name: String,
    /// Runs sorted by id.
    pub runs: Vec<Run>,
    /// A digest of the expanded runs (FNV-1a of their JSON), shared by all shards of a suite.
    pub digest: String,
}

/// Largest number of samples of one run (every sample is kept for the fits).
pub const MAX_SAMPLES: usize = 1_000_000;
/// Most runs a suite may expand to (refused at once above it: the runs are held in memory).
pub const MAX_RUNS: usize = 20_000;
/// Largest suite file read (bytes).
pub const MAX_SUITE_BYTES: u64 = 4 * 1024 * 1024;

/// Default thresholds of the closed-form check (f64 against 50 digits; residual at 50 digits).
pub const DEFAULT_CLOSED_FORM_F64: f64 = 1e-12;
pub const DEFAULT_CLOSED_FORM_RESIDUAL: f64 = 1e-38;

impl Suite {
    /// Read and expand a suite file.
    pub fn load(path: &Path) -> Result<Suite, ValidateError> {
        Suite::load_with(path, None)
    }

    /// Parse and expand suite text; `fallback_name` names a suite without `name`.
    pub fn parse(text: &str, fallback_name: &str) -> Result<Suite, ValidateError> {
        Suite::parse_with(text, fallback_name, None)
    }

    /// Read a suite file; with `exec` = (NAME, adapter), that external integrator replaces the
    /// methods of every case (`rsts validate --exec`).
    pub fn load_with(
        path: &Path,
        exec: Option<(&str, &AdapterSpec)>,
    ) -> Result<Suite, ValidateError> {
        let cannot = |e: std::io::Error| {
            ValidateError::Io(format!("cannot read suite {}: {e}", path.display()))
        };
        let file = std::fs::File::open(path).map_err(cannot)?;
        let mut text = String::new();
        std::io::Read::read_to_string(
            &mut std::io::Read::take(file, MAX_SUITE_BYTES + 1),
            &mut text,
        )
        .map_err(cannot)?;
        if text.len() as u64 > MAX_SUITE_BYTES {
            return Err(ValidateError::Suite(format!(
                "{}: larger than {MAX_SUITE_BYTES} bytes (4 MiB), the most a suite file may have; split it",
                path.display()
            )));
        }
        let fallback = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "suite".into());
        Suite::parse_with(&text, &fallback, exec)
            .map_err(|e| ValidateError::Suite(format!("{}: {}", path.display(), e.detail())))
    }

    /// [`Suite::parse`], with every case's methods replaced by the adapter `exec` when given
    /// (the convergence cases, which hold built-in methods' orders, are then left out).
    pub fn parse_with(
        text: &str,
        fallback_name: &str,
        exec: Option<(&str, &AdapterSpec)>,
    ) -> Result<Suite, ValidateError> {
        let mut file: SuiteFile =
            toml::from_str(text).map_err(|e| ValidateError::Suite(format!("{e}")))?;
        if let Some((name, adapter)) = exec {
            file.adapters.insert(name.to_string(), adapter.clone());
            // Convergence cases hold the built-ins' orders (their min_order is a built-in's).
            file.cases.retain(|case| case.convergence.is_none());
            file.defaults.methods = Some(vec![name.to_string()]);
            for case in &mut file.cases {
                case.methods = Some(vec![name.to_string()]);
            }
        }
        Suite::expand(&file, fallback_name)
    }

    /// Expand every case into runs.
    pub fn expand(file: &SuiteFile, fallback_name: &str) -> Result<Suite, ValidateError> {
        if file.cases.is_empty() {
            return Err(ValidateError::Suite("the suite has no [[case]]".into()));
        }
        for (name, adapter) in &file.adapters {
            check_name(name).map_err(|e| ValidateError::Suite(format!("adapter {e}")))?;
            if name.parse::<MethodName>().is_ok() {
                return Err(ValidateError::Suite(format!(
                    "adapter '{name}': the name of a built-in method"
                )));
            }
            if adapter.command.is_empty() || adapter.command[0].is_empty() {
                return Err(ValidateError::Suite(format!(
                    "adapter '{name}': command must name a program, e.g. command = [\"python3\", \"my_adapter.py\"]"
                )));
            }
            if let Some(t) = adapter.timeout {
                rsts_external::check_timeout(t)
                    .map_err(|e| ValidateError::Suite(format!("[adapters.{name}] timeout: {e}")))?;
            }
        }
        let mut runs = Vec::new();
        let mut names = BTreeSet::new();
        for spec in &file.cases {
            if !names.insert(spec.name.clone()) {
                return Err(ValidateError::Suite(format!(
                    "case name '{}' is used twice",
                    spec.name
                )));
            }
            runs.extend(expand_case(&file.defaults, &file.adapters, spec)?);
            if runs.len() > MAX_RUNS {
                return Err(too_many_runs(runs.len(), &spec.name));
            }
        }
        runs.sort_by(|x, y| x.id.cmp(&y.id));
        for w in runs.windows(2) {
            if w[0].id == w[1].id {
                return Err(ValidateError::Suite(format!(
                    "run id '{}' occurs twice (a method or tolerance listed twice?)",
                    w[0].id
                )));
            }
        }
        let json = serde_json::to_string(&runs).expect("runs serialise");
        Ok(Suite {
            name: file.name.clone().unwrap_or_else(|| fallback_name.into()),
            digest: format!("{:016x}", fnv1a(json.as_bytes())),
            runs,
        })
    }
}

/// A suite that expands to more than [`MAX_RUNS`] runs (counted up to case `name`).
fn too_many_runs(runs: usize, name: &str) -> ValidateError {
    ValidateError::Suite(format!(
        "the suite expands to {runs} runs by case '{name}', more than the {MAX_RUNS} a suite may have; split it into several suites (or shards of one)"
    ))
}

/// FNV-1a, 64 bits.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// The tolerance as it appears in a run id: `1e-12`, `2.5e-8`.
pub fn tol_label(x: f64) -> String {
    format!("{x:e}")
}

/// A case name usable in ids and file names: letters, digits, `-`, `_`, `.`, `+`.
fn check_name(name: &str) -> Result<(), ValidateError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.+".contains(c))
    {
        return Err(ValidateError::Suite(format!(
            "case name '{name}': use only ASCII letters, digits and - _ . + (it is part of run ids and file names)"
        )));
    }
    Ok(())
}

fn finite(what: &str, name: &str, v: f64) -> Result<f64, ValidateError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ValidateError::Suite(format!(
            "{what}: {name} must be a finite number, got {v}"
        )))
    }
}

/// The h of a placement at (a, b, m).
pub fn place_h(
    what: &str,
    a: f64,
    b: f64,
    m: Option<f64>,
    p: &Placement,
) -> Result<(f64, f64), ValidateError> {
    let err = |msg: String| ValidateError::Suite(format!("{what}: place: {msg}"));
    let (p2, r2) = (a * a + b * b, a * a - b * b);
    let given = [p.near.is_some(), p.ell.is_some(), p.equilibrium.is_some()]
        .iter()
        .filter(|x| **x)
        .count();
    if given != 1 {
        return Err(err(
            "give exactly one of near = CURVE, ell = L, equilibrium = pN".into(),
        ));
    }
    let delta = |required: bool| -> Result<f64, ValidateError> {
        match p.delta {
            Some(d) if d.is_finite() && d > 0.0 => Ok(d),
            Some(d) => Err(err(format!("delta must be positive and finite, got {d}"))),
            None if required => Err(err("delta is required".into())),
            None => Ok(0.0),
        }
    };
    let need_m = || m.ok_or_else(|| err("this placement needs m".into()));
    if let Some(curve) = &p.near {
        let m = need_m()?;
        let d = delta(true)?;
        let (h0, default_side) = match curve.as_str() {
            "outer-a" => (r2 * m - 2.0 * a, Some(1.0)),
            "outer-b" => (-r2 * m - 2.0 * b, Some(1.0)),
            "hyperbola" => {
                if m >= 0.0 {
                    return Err(err(format!("the hyperbola needs m < 0, got m = {m}")));
                }
                (-p2 * m - 0.5 / m, Some(-1.0))
            }
            "inner-a" => (r2 * m + 2.0 * a, None),
            "inner-b" => (-r2 * m + 2.0 * b, None),
            other => {
                return Err(err(format!(
                    "unknown curve '{other}' (outer-a, outer-b, hyperbola, inner-a, inner-b)"
                )))
            }
        };
        let sign = match (p.side.as_deref(), default_side) {
            (Some("above"), _) => 1.0,
            (Some("below"), _) => -1.0,
            (None, Some(s)) => s,
            (None, None) => return Err(err(format!("{curve}: side = \"above\" or \"below\""))),
            (Some(other), _) => {
                return Err(err(format!(
                    "side must be \"above\" or \"below\", got '{other}'"
                )))
            }
        };
        return Ok((m, h0 + sign * d));
    }
    if p.side.is_some() {
        return Err(err("side only goes with near = CURVE".into()));
    }
    if let Some(ell) = p.ell {
        let m = need_m()?;
        if p.delta.is_some() {
            return Err(err("delta does not go with ell".into()));
        }
        if !(ell.is_finite() && ell > 0.0) || m >= 0.0 || !m.is_finite() {
            return Err(err(format!(
                "ell needs ℓ > 0 and m < 0, got ℓ = {ell}, m = {m}"
            )));
        }
        return Ok((m, (ell * ell - 1.0 - 2.0 * p2 * m * m) / (2.0 * m)));
    }
    let name = p.equilibrium.as_deref().unwrap_or_default();
    let d = delta(true)?;
    if m.is_some() {
        return Err(err("an equilibrium placement sets m itself: drop m".into()));
    }
    Ok(match name {
        // The corner of the two outer lines; straight up is inside camera I+.
        "p1" => (1.0 / (a + b), -(a + b) + d),
        // Where h = −r²m + 2b ends on h = r²m − 2a: step right of it, just above the boundary.
        "p2" => (1.0 / (a - b) + d, r2 * (1.0 / (a - b) + d) - 2.0 * a + d),
        // Where h = r²m + 2a starts on h = −r²m − 2b: step left of it, just above the boundary.
        "p3" => (-1.0 / (a - b) - d, -r2 * (-1.0 / (a - b) - d) - 2.0 * b + d),
        // The crossing of the two inner lines; straight up.
        "p4" => (-1.0 / (a + b), a + b + d),
        other => {
            return Err(err(format!(
                "unknown equilibrium '{other}' (p1, p2, p3, p4)"
            )))
        }
    })
}

fn expand_case(
    defaults: &Defaults,
    adapters: &BTreeMap<String, AdapterSpec>,
    spec: &CaseSpec,
) -> Result<Vec<Run>, ValidateError> {
    check_name(&spec.name)?;
    let what = format!("case '{}'", spec.name);
    let e = |msg: String| ValidateError::Suite(format!("{what}: {msg}"));
    let a = finite(&what, "a", spec.a.or(defaults.a).unwrap_or(1.0))?;
    let b = finite(&what, "b", spec.b.or(defaults.b).unwrap_or(0.5))?;
    let (m, h) = match (&spec.place, spec.h) {
        (Some(_), Some(_)) => return Err(e("give h or place, not both".into())),
        (Some(p), None) => place_h(&what, a, b, spec.m, p)?,
        (None, Some(h)) => (
            spec.m.ok_or_else(|| e("m is missing".into()))?,
            finite(&what, "h", h)?,
        ),
        (None, None) => return Err(e("give h (with m) or place".into())),
    };
    finite(&what, "m", m)?;
    let t_end = finite(
        &what,
        "t_end",
        spec.t_end.or(defaults.t_end).unwrap_or(100.0),
    )?;
    if t_end < 0.0 {
        return Err(e(format!("t_end must be non-negative, got {t_end}")));
    }
    let samples = spec.samples.or(defaults.samples).unwrap_or(201);
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(e(format!(
            "samples must be between 1 and {MAX_SAMPLES}, got {samples}"
        )));
    }
    let phase1 = finite(
        &what,
        "phase1",
        spec.phase1.or(defaults.phase1).unwrap_or(0.0),
    )?;
    let phase2 = finite(
        &what,
        "phase2",
        spec.phase2.or(defaults.phase2).unwrap_or(0.0),
    )?;
    let choice = TorusChoice {
        torus: 0,
        phase1,
        phase2,
    };
    let motion = ExplicitMotion::new(a, b, m, h, choice)
        .map_err(|err| e(format!("(a, b, m, h) = ({a}, {b}, {m}, {h}): {err}")))?;
    let camera = motion.camera;
    if let Some(expected) = &spec.camera {
        let want: Camera = expected.parse().map_err(e)?;
        if want != camera {
            return Err(e(format!(
                "(m, h) = ({m}, {h}) lies in camera {camera}, not {want}"
            )));
        }
    }
    let tori: Vec<usize> = match spec.tori.as_ref().or(defaults.tori.as_ref()) {
        None => vec![0],
        Some(Tori::Name(s)) if s == "all" => (0..motion.tori).collect(),
        Some(Tori::Name(s)) => {
            return Err(e(format!(
                "tori must be \"all\", an index or a list, got '{s}'"
            )))
        }
        Some(Tori::One(k)) => vec![*k],
        Some(Tori::List(v)) if v.is_empty() => return Err(e("tori is an empty list".into())),
        Some(Tori::List(v)) => v.clone(),
    };
    for &k in &tori {
        if k >= motion.tori {
            return Err(e(format!(
                "torus {k} does not exist: camera {camera} has {} (0..{})",
                motion.tori, motion.tori
            )));
        }
    }
    let methods = spec
        .methods
        .clone()
        .or(defaults.methods.clone())
        .unwrap_or_else(|| vec!["dop853".into()]);
    let tolerances = spec
        .tolerances
        .clone()
        .or(defaults.tolerances.clone())
        .unwrap_or_else(|| vec![1e-12]);
    let digits = spec.digits.or(defaults.digits);
    let step = spec.step.or(defaults.step);
    let closed_form = spec.closed_form.or(defaults.closed_form).unwrap_or(true);
    if methods.is_empty() {
        return Err(e(
            "methods is an empty list: name at least one (leave methods out for dop853)".into(),
        ));
    }
    if tolerances.is_empty() {
        return Err(e("tolerances is an empty list".into()));
    }
    let count = tori
        .len()
        .saturating_mul(usize::from(closed_form) + methods.len().saturating_mul(tolerances.len()));
    if count > MAX_RUNS {
        return Err(too_many_runs(count, &spec.name));
    }
    let mut thresholds = spec.thresholds.over(defaults.thresholds);
    thresholds.check(&what)?;
    if thresholds.min_order.is_some() && spec.convergence.is_none() {
        return Err(e(
            "min_order holds convergence cases only (give convergence = { steps = [...] })".into(),
        ));
    }
    if thresholds.closed_form_f64.is_none() {
        thresholds.closed_form_f64 = Some(DEFAULT_CLOSED_FORM_F64);
    }
    if thresholds.closed_form_residual.is_none() {
        thresholds.closed_form_residual = Some(DEFAULT_CLOSED_FORM_RESIDUAL);
    }
    let mut runs = Vec::new();
    for &torus in &tori {
        let base = Run {
            id: String::new(),
            case: spec.name.clone(),
            a,
            b,
            m,
            h,
            torus,
            phase1,
            phase2,
            t_end,
            samples,
            camera: camera.label().to_string(),
            kind: RunKind::ClosedForm,
            thresholds,
        };
        if closed_form {
            runs.push(Run {
                id: format!("{}/t{torus}/closed-form", spec.name),
                ..base.clone()
            });
        }
        if let Some(conv) = &spec.convergence {
            runs.extend(convergence_runs(&base, &methods, conv, digits).map_err(e)?);
            continue;
        }
        for method in &methods {
            if let Some(adapter) = adapters.get(method) {
                for &tol in &tolerances {
                    if !(tol.is_finite() && tol > 0.0) {
                        return Err(e(format!("tolerance must be positive, got {tol}")));
                    }
                    runs.push(Run {
                        id: format!("{}/t{torus}/{method}@{}", spec.name, tol_label(tol)),
                        kind: RunKind::External {
                            method: method.clone(),
                            command: adapter.command.clone(),
                            rtol: tol,
                            atol: tol,
                            digits,
                            timeout: adapter.timeout,
                        },
                        ..base.clone()
                    });
                }
                continue;
            }
            for &tol in &tolerances {
                // Checked here so a bad method or tolerance is a suite error, not a failed run.
                let config =
                    method_config(method, tol, tol, digits, step).map_err(|err| e(err.detail()))?;
                let name = config.method.as_str().to_string();
                let run_digits =
                    (config.method == MethodName::TaylorMp).then(|| config.mp_digits());
                let run_step = (config.method == MethodName::Rk4).then_some(step).flatten();
                let mut id = format!("{}/t{torus}/{name}@{}", spec.name, tol_label(tol));
                if let Some(d) = run_digits {
                    id.push_str(&format!("/{d}d"));
                }
                if let Some(s) = run_step {
                    id.push_str(&format!("/step{}", tol_label(s)));
                }
                runs.push(Run {
                    id,
                    kind: RunKind::Integrator {
                        method: name,
                        rtol: tol,
                        atol: tol,
                        digits: run_digits,
                        step: run_step,
                    },
                    ..base.clone()
                });
            }
        }
    }
    Ok(runs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_expands_to_sorted_unique_ids() {
        let s = Suite::parse(
            r#"
name = "t"
[defaults]
t_end = 1.0
samples = 3
[[case]]
name = "V"
camera = "V"
m = -0.7092
h = 1.5643
tori = "all"
methods = ["dop853", "dopri5"]
tolerances = [1e-8, 1e-10]
"#,
            "x",
        )
        .unwrap();
        // 4 tori × (1 closed-form + 2 methods × 2 tolerances).
        assert_eq!(s.runs.len(), 20);
        let ids: Vec<&str> = s.runs.iter().map(|r| r.id.as_str()).collect();
        let mut sorted = ids.clone();
        sorted.sort();
        assert_eq!(ids, sorted);
        assert!(ids.contains(&"V/t3/dopri5@1e-10"));
        assert!(ids.contains(&"V/t0/closed-form"));
        assert!(s.runs.iter().all(|r| r.camera == "V"));
    }

    #[test]
    fn placements_land_where_asked() {
        let (a, b) = (1.0, 0.5);
        let place = |p: Placement, m: Option<f64>| place_h("t", a, b, m, &p).unwrap();
        let near = |c: &str, side: Option<&str>| Placement {
            near: Some(c.into()),
            side: side.map(String::from),
            delta: Some(1e-6),
            ..Placement::default()
        };
        assert_eq!(place(near("outer-a", None), Some(1.0)).1, 0.75 - 2.0 + 1e-6);
        assert_eq!(
            place(near("inner-b", Some("below")), Some(0.0)).1,
            1.0 - 1e-6
        );
        let (m, h) = place(near("hyperbola", None), Some(-1.0));
        let ell2 = 2.0 * 1.25 * m * m + 2.0 * h * m + 1.0;
        assert!((ell2 - 2e-6).abs() < 1e-12, "{ell2}");
        let (m, h) = place(
            Placement {
                ell: Some(1e-6),
                ..Placement::default()
            },
            Some(-1.0),
        );
        let ell2 = 2.0 * 1.25 * m * m + 2.0 * h * m + 1.0;
        assert!((ell2.sqrt() - 1e-6).abs() < 1e-9, "{ell2}");
        for p in ["p1", "p2", "p3", "p4"] {
            let (m, h) = place(
                Placement {
                    equilibrium: Some(p.into()),
                    delta: Some(1e-3),
                    ..Placement::default()
                },
                None,
            );
            ExplicitMotion::new(a, b, m, h, TorusChoice::default())
                .unwrap_or_else(|e| panic!("{p} at ({m}, {h}): {e}"));
        }
    }

    #[test]
    fn bad_input_is_a_clear_error() {
        let err = |text: &str| Suite::parse(text, "x").unwrap_err().to_string();
        assert!(err("[[case]\n").contains("TOML") || err("[[case]\n").contains("expected"));
        let base = "[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\n";
        assert!(err(&format!("{base}methods = [\"euler\"]\n")).contains("unknown method 'euler'"));
        assert!(err(&format!("{base}tolerances = [-1.0]\n")).contains("rtol"));
        assert!(err(&format!("{base}camera = \"V\"\n")).contains("not V"));
        assert!(err(&format!("{base}tori = 3\n")).contains("torus 3 does not exist"));
        assert!(err(&format!("{base}bogus = 1\n")).contains("bogus"));
        assert!(err("[[case]]\nname = \"c\"\nm = 0.0\nh = 2.0\n").contains("h = r²m + 2a"));
        assert!(err("name = \"x\"\n").contains("no [[case]]"));
        assert!(err(&format!("{base}{}", base)).contains("used twice"));
        assert!(err(&format!("{base}[case.thresholds]\nmax_drift = 0.0\n")).contains("max_drift"));
    }
}
