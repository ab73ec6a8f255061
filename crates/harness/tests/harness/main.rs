//! The integration tests of rsts-harness, one module per file, in one test binary (one link
//! instead of one per file). One file's tests:
//! `cargo test --release -p rsts-harness --test harness geometry::`.

mod check_f64;
mod compare;
mod dd_paths;
mod drift_growth;
mod ensemble;
mod geometry;
mod reference_digits;
mod rounded_explicit;
mod rounded_reference;
mod tori_symmetry;
