//! Errors of the dynamics crate: bad parameters, bad states, integrator failures.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum DynamicsError {
    #[error("{0} is not a finite number")]
    NotFinite(&'static str),
    #[error("invalid field strengths: {0}")]
    Fields(String),
    #[error("invalid state: {0}")]
    State(String),
    #[error("invalid integrator settings: {0}")]
    Settings(String),
    #[error("integration failed: {0}")]
    Integration(String),
}
