//! The integration tests of rsts-closed-form, one module per file, in one test binary (one link
//! instead of one per file). One file's tests:
//! `cargo test --release -p rsts-closed-form --test closed_form projector::`.

mod against_integrator;
mod common;
mod diagram;
mod events;
mod hard_regimes;
mod identify;
mod manifold;
mod mpfr_state;
mod phi_field;
mod projector;
mod seed_formulas;
mod tori_symmetry;
mod torus_table;
