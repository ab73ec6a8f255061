//! Dynamics of the Kowalevski top (inertia diag(2, 2, 1)) in two constant force fields, the
//! Reyman–Semenov-Tian-Shansky problem: the Euler–Poisson equations written once over a generic
//! scalar ([`scalar::Real`]: `f64`, `rug::Float`, dual numbers), their first integrals and
//! constraints, the orientation, and integrators behind one interface ([`integrators`]).
//!
//! Small public surface: [`Fields`], [`State`], [`VectorField`], [`integrals()`],
//! [`integrators::Propagator::propagate_grid`].

pub mod dual;
pub mod equations;
pub mod error;
pub mod fields;
pub mod integrals;
pub mod integrators;
pub mod scalar;
pub mod state;
pub mod vec3;

pub use equations::VectorField;
pub use error::DynamicsError;
pub use fields::Fields;
pub use integrals::{integrals, Integrals};
pub use scalar::Real;
pub use state::State;
