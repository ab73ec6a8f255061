//! Errors of the closed-form crate.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ClosedFormError {
    #[error("invalid parameters: {0}")]
    Parameters(String),
    #[error("(m, h) is outside the admissible region: {0}")]
    NotAdmissible(String),
    #[error("(m, h) lies on the bifurcation diagram Σ: {0}; the integral manifold is critical there (a separated variable sits at a multiple root), pick a point off Σ")]
    OnSigma(String),
    #[error("torus {torus} does not exist: camera {camera} has {tori} torus/tori (0..{tori})")]
    NoSuchTorus {
        torus: usize,
        camera: String,
        tori: usize,
    },
    /// A parameter outside the documented range of the closed form (docs/closed-form.md):
    /// the parameter's name (`a`, `b`, `m`, `h`) and why.
    #[error("{1}")]
    Range(&'static str, String),
    #[error("internal error: {0}")]
    Internal(String),
}
