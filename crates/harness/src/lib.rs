//! The cross-check harness: produce a trajectory with any integrator, analyse it against the
//! closed-form motion on N (issue 4; opened to outside integrators in issue 10).
//!
//! Producing and analysing are separate:
//! - an [`Integrator`] (a built-in [`MethodConfig`], a user's [`Propagator`] wrapped in
//!   [`Propagated`], an external process of `rsts-external`) integrates from a state through any
//!   list of times and returns a [`Trajectory`];
//! - an [`Analysis`] measures samples (time, state) of any spacing against the closed form and
//!   produces the [`Report`] (errors, drifts, cost), handing every [`SampleRecord`] to an
//!   [`Observer`] (the CLI logs them to MCAP and draws a progress bar; it can stop the run).
//!
//! [`check`] is the analysis of a trajectory computed elsewhere (a file, arrays), the motion
//! given or identified from its first sample.
//!
//! [`compare_integrator`] is both for a [`Case`] (a, b, m, h, torus, phases, T, N); [`compare`]
//! is its form for a built-in method; [`bench::measure_against`] measures work against
//! precision. The closed form is evaluated [`REFERENCE_GUARD_BITS`] beyond the integrator's
//! precision, so the reported error is the integrator's, not the reference's.
//!
//! [`Propagator`]: rsts_dynamics::integrators::Propagator

pub mod analysis;
pub mod bench;
mod case;
pub mod check;
mod check_stream;
mod compare;
pub mod compare_diagram;
pub mod convergence;
pub mod dense;
pub mod detected;
pub mod digits;
pub mod drift_growth;
pub mod ensemble;
pub mod environment;
pub mod events;
pub mod geometry;
pub mod growth;
pub mod identify;
pub mod integrator;
mod metrics;
pub mod proportionality;
pub mod reference;
pub mod rounded_explicit;
pub mod rounded_reference;
pub mod shard;
pub mod threads;
pub mod times_file;

pub use analysis::{analyse, Analysis, NoObserver, Observer, RunInfo};
pub use bench::{
    bench, measure, measure_against, measure_integrator, BenchMethod, BenchReport, BenchRequest,
    BenchRow, Reference,
};
pub use case::Case;
pub use check::{check, Check, CheckMotion, CheckReport, CheckRequest, CheckedCase};
pub use check_stream::CheckStream;
pub use compare::{
    check_finite_report, compare, compare_at, compare_integrator, preflight, preflight_at,
    reference_bits, reference_bits_for, run_info, sampled, CompareOptions, SampleTimes,
    DEFAULT_PIECES, REFERENCE_GUARD_BITS,
};
pub use convergence::{
    convergence, convergence_until, fit_order, ConvergencePlan, ConvergenceReport, ConvergenceRow,
    FixedStepIntegrator, FixedStepMethod, OrderFit,
};
pub use digits::CorrectDigits;
pub use integrator::{check_times, Integrator, Propagated, Trajectory};
pub use metrics::{Drift, Report, SampleErrors, SampleRecord, StateSnapshot, StatedStats};
pub use rsts_dynamics::integrators::MethodConfig;
/// The crates the harness's signatures use (`Problem<rug::Float>`, `State`, …), re-exported so a
/// user depends on `rsts-harness` alone, with the workspace's exact `rug` features (GMP and MPFR
/// built once).
pub use {rsts_closed_form, rsts_dynamics, rug};

/// Errors of a comparison. A face reads the inputs an error concerns from its variant
/// ([`HarnessError::parameters`]) and its kind from the variant too; no message is parsed.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    #[error(transparent)]
    ClosedForm(#[from] rsts_closed_form::ClosedFormError),
    #[error(transparent)]
    Dynamics(#[from] rsts_dynamics::DynamicsError),
    /// Samples or times that cannot be used as given, naming no input of the request (times and
    /// states of different lengths, no samples, a first row off N).
    #[error("{0}")]
    Data(String),
    #[error("observer: {0}")]
    Observer(String),
    /// An integrator failed (an external process: what it did and the end of its stderr).
    #[error("{0}")]
    Integrator(String),
    /// Settings of a request that do not go together or are out of range: their names (the
    /// CLI's options without `--`) and why.
    #[error("{1}")]
    Setting(Vec<String>, String),
    /// Shards that do not merge into one report (`rsts bench merge`): which and why.
    #[error("merge: {0}")]
    Merge(String),
}

/// Largest number of samples or times a run accepts (every sample is kept in memory by some
/// outputs): the same limit for the CLI and the Python package.
pub const MAX_SAMPLES: usize = 10_000_000;

impl HarnessError {
    /// A setting error concerning the inputs `names` (the CLI's options without `--`).
    pub fn setting(names: &[&str], message: impl Into<String>) -> Self {
        HarnessError::Setting(
            names.iter().map(|n| n.to_string()).collect(),
            message.into(),
        )
    }

    /// The parameters an error concerns (`["m", "h"]` for a point on Σ, `["torus"]` for a
    /// missing torus, …; empty when it names none), read from its variant: the CLI writes them
    /// as options (`--m/--h:`), the Python package as its arguments (`m/h:`), in front of the
    /// same message.
    pub fn parameters(&self) -> Vec<String> {
        use rsts_closed_form::ClosedFormError as C;
        let names: &[&str] = match self {
            HarnessError::ClosedForm(c) => match c {
                C::Parameters(_) => &["a", "b"],
                C::Range(name, _) => return vec![name.to_string()],
                C::NotAdmissible(_) | C::OnSigma(_) => &["m", "h"],
                C::NoSuchTorus { .. } => &["torus"],
                C::Internal(_) => &[],
            },
            HarnessError::Dynamics(rsts_dynamics::DynamicsError::Settings(_)) => {
                &["t-end", "rtol", "atol"]
            }
            HarnessError::Setting(names, _) => return names.clone(),
            HarnessError::Dynamics(_)
            | HarnessError::Data(_)
            | HarnessError::Observer(_)
            | HarnessError::Integrator(_)
            | HarnessError::Merge(_) => &[],
        };
        names.iter().map(|n| n.to_string()).collect()
    }

    /// A run that failed (an integrator, an observer that stopped it, an integration that
    /// diverged), not input refused before the work.
    pub fn is_failure(&self) -> bool {
        matches!(
            self,
            HarnessError::Integrator(_)
                | HarnessError::Observer(_)
                | HarnessError::Dynamics(rsts_dynamics::DynamicsError::Integration(_))
        )
    }
}
