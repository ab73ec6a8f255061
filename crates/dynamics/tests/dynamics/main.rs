//! The integration tests of rsts-dynamics, one module per file, in one test binary (one link
//! instead of one per file). One file's tests:
//! `cargo test --release -p rsts-dynamics --test dynamics taylor::`.

mod conservation;
mod drift;
mod taylor;
mod taylor_dense;
mod taylor_mpfr;
