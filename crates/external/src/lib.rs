//! Integrators and trajectories from outside rsts (issue 10).
//!
//! - [`exec`]: an external program speaking `rsts-integrator/1` on stdin/stdout is an
//!   [`rsts_harness::Integrator`] ([`Exec`]), usable in `compare`, `bench` and suites like a
//!   built-in method;
//! - [`files`]: trajectories computed elsewhere (CSV, JSON, npy, the `/integrated/state` channel
//!   of an MCAP log) for `rsts check`, with errors naming file, row and column;
//! - [`stream`]: the same files (and standard input) in chunks of rows, for a check in
//!   bounded memory;
//! - [`samples`]: the values as read and the one rule that turns them into numbers (f64 data
//!   or exact high-precision decimals).
//!
//! Integrators written in Rust do not need this crate: implement
//! [`rsts_dynamics::integrators::Propagator`] and wrap it in [`rsts_harness::Propagated`].

mod bench;
pub mod dense;
pub mod exec;
pub mod files;
mod pipes;
pub mod samples;
pub mod stream;

pub use exec::{
    check_program, check_timeout, command_files, kill_running, split_command, Exec, DEFAULT_DIGITS,
    DEFAULT_TIMEOUT_SECONDS, MAX_TIMEOUT_SECONDS, PROTOCOL,
};
pub use files::{npy_bytes, npy_header, parse_trajectory, read_trajectory, FileFormat, COLUMNS};
pub use samples::{check_f64_states, BadComponent, Number, RawTrajectory, Samples};
pub use stream::{check_rest, check_rest_f64, F64Chunk, RestF64, Survey, TrajectoryReader};
