//! The cross-check harness: start an integrator from the closed-form state at t = 0 and compare
//! the integrated motion with the closed form along the motion (issue 4).
//!
//! A [`Case`] (a, b, m, h, torus, phases, T, N) and a [`MethodConfig`] are separate values;
//! [`compare`] returns a [`Report`] (errors, drifts, cost) and hands every [`SampleRecord`] to an
//! [`Observer`] (the CLI logs them to MCAP and draws a progress bar; it can stop the run).
//! The closed form is evaluated [`REFERENCE_GUARD_BITS`] beyond the integrator's precision, so the
//! reported error is the integrator's, not the reference's.

pub mod bench;
mod case;
mod compare;
mod metrics;

pub use bench::{measure, measure_against, BenchRow, Reference};
pub use case::Case;
pub use compare::{compare, preflight, reference_bits, NoObserver, Observer, REFERENCE_GUARD_BITS};
pub use metrics::{Drift, Report, SampleErrors, SampleRecord, StateSnapshot};
pub use rsts_dynamics::integrators::MethodConfig;

/// Errors of a comparison.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    #[error(transparent)]
    ClosedForm(#[from] rsts_closed_form::ClosedFormError),
    #[error(transparent)]
    Dynamics(#[from] rsts_dynamics::DynamicsError),
    #[error("{0}")]
    Case(String),
    #[error("observer: {0}")]
    Observer(String),
}
