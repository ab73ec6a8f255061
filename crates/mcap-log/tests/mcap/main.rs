//! The integration tests of rsts-mcap, one module per file, in one test binary (one link
//! instead of one per file). One file's tests:
//! `cargo test --release -p rsts-mcap --test mcap roundtrip::`.

mod common;
mod compat;
mod faults;
mod python_reader;
mod robustness;
mod roundtrip;
mod schemas;
