//! Verdicts: what a user asked a run to meet (`--max-error`, `--max-event-error`, a suite's
//! thresholds) and whether it did. A verdict is a claim about the integrator: a limit on what
//! was not measured never fails a run (it is said to be not measured).

use serde::Serialize;

/// What a run must meet; `None`: not asked.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Limits {
    /// Largest state error allowed (max over samples and components).
    pub max_error: Option<f64>,
    /// Largest event time error allowed, and no event missed among those looked for.
    pub max_event_error: Option<f64>,
    /// A first sample far from the given motion (`start_offset` in the report) is reported
    /// without failing the run.
    pub allow_start_offset: bool,
}

/// Whether a run met its limits.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "verdict", content = "why", rename_all = "lowercase")]
pub enum Verdict {
    /// Every limit asked was met (or none was asked).
    Pass,
    /// Limits missed, each said in words.
    Fail(Vec<String>),
}

impl Verdict {
    /// A verdict from the reasons a run failed (none: pass).
    pub fn from_reasons(reasons: Vec<String>) -> Self {
        if reasons.is_empty() {
            Verdict::Pass
        } else {
            Verdict::Fail(reasons)
        }
    }

    pub fn passed(&self) -> bool {
        matches!(self, Verdict::Pass)
    }
}
