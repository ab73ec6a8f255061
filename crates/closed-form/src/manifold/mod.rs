//! The shape of the invariant manifold N (issue 11): its invariant relations and the partial
//! integral M ([`relations`]), the regular distance from N ([`distance`]), the normal type of N
//! ([`normal`]) and the inverse of the closed form, state → (m, h, camera, torus, ψ₁, ψ₂)
//! ([`identify`]).

pub mod distance;
pub mod field_derivative;
pub mod identify;
pub mod lanes;
mod least_squares;
pub mod normal;
pub mod phi_field;
pub mod project;
pub mod relations;
pub mod spectral;
pub mod torus_map;
pub mod torus_table;

pub use distance::{distance, DistanceFromN};
pub use identify::{identify, Identified, IdentifyError};
pub use normal::{normal_type, Normal, NormalType};
pub use project::{Projection, Projector};
pub use relations::{m_of_integrals, Relations};
pub use torus_map::TorusMap;
pub use torus_table::TorusTable;
