//! Geometry of the closed-form motions on N (seed sec. 2–3): meshes of the bearing surfaces
//! (P-surface in ω-space, Π-surface in Ω-space) over the angle coordinates of each Liouville
//! torus, the decomposition Q = Q″Q′ into pendulum-type motions classified from the motion itself,
//! the coordinate planes each connected surface is symmetric to (measured on the meshes), and
//! output as PLY meshes, shaded PNG pictures and an MCAP scene (Poinsot's picture).

pub mod classify;
pub mod mesh;
pub mod nearest;
pub mod ply;
pub mod render;
pub mod scene;
pub mod tables;
pub mod text;

pub use classify::{camera_geometry, CameraGeometry, MotionKinds, PendulumKind};
pub use mesh::{Surface, TorusMesh};

use rsts_closed_form::ClosedFormError;
use thiserror::Error;

/// Errors of the geometry crate.
#[derive(Debug, Error)]
pub enum GeometryError {
    #[error(transparent)]
    ClosedForm(#[from] ClosedFormError),
    #[error("invalid input: {0}")]
    Input(String),
    #[error("numerical failure: {0}")]
    Numerical(String),
    #[error("{context}: {source}")]
    Io {
        context: String,
        #[source]
        source: std::io::Error,
    },
    #[error("MCAP: {0}")]
    Mcap(String),
}
