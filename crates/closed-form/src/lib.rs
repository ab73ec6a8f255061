//! The closed-form motion of the Kowalevski top in two constant fields on the invariant
//! manifold N (Kharlamova & Savushkin, "On the geometry of motions in one integrable problem of
//! the rigid body dynamics", sec. 1–3): integral constants and the bifurcation diagram, cameras
//! and Liouville tori, the separated variables as Jacobi elliptic functions of angles on the
//! torus, and the state (ω, α, β, γ, Ω, Q, Q′, Q″, ω′, ω″) at any time — written once over
//! [`rsts_dynamics::Real`], so the same code runs in f64 and in `rug::Float` at any precision.
//!
//! Entry point: [`ExplicitMotion::new`], then [`ExplicitMotion::at`].

pub mod camera;
pub mod constants;
pub mod diagram;
pub mod elliptic;
pub mod error;
pub mod events;
pub mod formulas;
pub mod manifold;
pub mod motion;
pub mod roots;
pub mod rounded;
pub mod scalar;
pub mod separated;

pub use camera::{Camera, EXAMPLE_POINTS_A1_B05};
pub use constants::{check_ranges, IntegralConstants, SigmaCurve};
pub use error::{tori_phrase, ClosedFormError};
pub use formulas::{BodyState, ExplicitState};
pub use motion::{BatchPath, DdPath, ExplicitMotion, InputError, Motion, TorusChoice};
pub use rsts_dynamics::number::{Decimal, NumberError, Times};
