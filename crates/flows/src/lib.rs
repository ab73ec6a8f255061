//! One library call per command (issue 32, "one motion, one number, one flow"): every face —
//! the `rsts` CLI, the Python package — parses its input into a request, makes one call here
//! and formats the outcome, a serde document that is the same for both faces.
//!
//! ```text
//! CompareRequest  { motion, times, integrator, events, dense, pieces, mcap } -> compare  -> CompareOutcome
//! CheckRequest    { motion or fields, source, events, mcap }                  -> check    -> CheckOutcome
//! EventsRequest, IdentifyRequest, ReferenceRequest, ExplicitRequest, ConvergenceRequest,
//! ValidateRequest                                                            (same shape)
//! ```
//!
//! The motion is one [`Motion`] value (fields a, b; m, h; torus; phases, each a decimal as
//! written), the times one [`Times`] value; a flow never rounds an input before the precision
//! it computes at is known. Verdicts (`--max-error`, `--max-event-error`, suite thresholds) are
//! the library's ([`verdict`]); a face maps [`Verdict::Fail`] to its exit status. Errors are
//! [`FlowError`]: a face maps its kind to an exit status and names the inputs it concerns in its
//! own spelling (the CLI's `--t-end`, Python's `t_end`); no message is parsed.
//!
//! What only organises the work (pieces, threads, chunks, one pass or two) never changes a digit
//! of an outcome: each flow proves it in its tests.

pub mod check;
pub mod compare;
pub mod error;
pub mod events;
pub mod explicit;
pub mod identify;
pub mod log;
pub mod reference;
pub mod sink;
pub mod times;
pub mod verdict;

#[cfg(test)]
mod agreement;

pub use error::{ErrorKind, FlowError};
/// A number of an outcome: an f64 (correctly rounded) or a decimal string of the digits asked.
pub use rsts_closed_form::events::Number;
pub use rsts_closed_form::{Decimal, Motion, Times};
pub use sink::{Collect, Sink};
pub use verdict::{Limits, Verdict};
