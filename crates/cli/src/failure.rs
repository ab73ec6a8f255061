//! How a command fails, shared by the commands (none imports another): a verdict that failed
//! ([`Failed`], exit 1) and a flow's error as a message naming the options it concerns
//! ([`flow_error`], exit 2). Kinds and names are read from the error's variant, never from
//! its message.

use rsts_flows::FlowError;

/// Some run missed what it was asked to meet or regressed (exit code 1): `rsts validate`'s
/// thresholds and baseline, `--max-error`, `--max-event-error`.
#[derive(Debug)]
pub struct Failed(pub String);

impl std::fmt::Display for Failed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Failed {}

/// The run was stopped by Ctrl-C (the report and the log cover what was done; exit 130).
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}

/// A flow's error, prefixed with the options it concerns (`--m/--h: (m, h) lies on Σ …`,
/// `--steps: …`); an error that names none is its message alone; a stopped run is
/// [`Interrupted`].
pub fn flow_error(e: impl Into<FlowError>) -> anyhow::Error {
    let e: FlowError = e.into();
    match e {
        FlowError::Interrupted(_) => return Interrupted(e.to_string()).into(),
        // The output named as the option that gave it: `--svg out/x.svg: …`.
        FlowError::Output { output, message } => return anyhow::anyhow!("--{output} {message}"),
        _ => {}
    }
    let names = e.names();
    if names.is_empty() {
        anyhow::anyhow!("{e}")
    } else {
        anyhow::anyhow!("--{}: {e}", names.join("/--"))
    }
}
