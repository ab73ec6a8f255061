//! The integration tests of rsts-cli, one module per file, in one test binary (one link
//! instead of one per file). One file's tests:
//! `cargo test --release -p rsts-cli --test cli jobs::`.

mod adapter_version;
mod bad_input;
mod bench;
mod bench_ensemble;
mod bench_vs_heyoka;
mod check;
mod check_one_pass;
mod check_stream;
mod common;
mod compare;
mod contract;
mod convergence;
mod dense;
mod diagram;
mod events;
mod examples;
mod explicit;
mod external;
mod geometry;
mod hostile;
mod identify;
mod integrate;
mod jobs;
mod judge;
mod kernel_paths;
mod mcap_readers;
mod one_build;
mod reference_check;
mod reliability;
mod validate;
mod validate_convergence;
