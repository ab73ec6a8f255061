//! The errors of a flow: what went wrong, the inputs it concerns, and its kind.

use rsts_harness::HarnessError;

/// What kind of failure an error is: a face maps it to its exit status (CLI: 2 for bad input
/// and failed runs, 130 for an interrupted one) or exception (Python: `ValueError` for bad input,
/// `RuntimeError` for a failed run, `KeyboardInterrupt`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The request cannot be carried out as given (a value out of range, a file that is not a
    /// trajectory, a motion that does not exist).
    BadInput,
    /// The work failed (an integrator that diverged, an external process that died).
    Failed,
    /// Stopped by the user (Ctrl-C) or by an observer.
    Interrupted,
}

/// An error of a flow.
#[derive(Debug, thiserror::Error)]
pub enum FlowError {
    /// Bad input: the inputs it concerns (the CLI's option names without `--`: `t-end`, `m`; a
    /// face spells them its own way) and why.
    #[error("{message}")]
    Input {
        names: Vec<&'static str>,
        message: String,
    },
    /// The comparison, the closed form or the integrator failed or refused.
    #[error(transparent)]
    Harness(#[from] HarnessError),
    /// The run was stopped; what was done is described.
    #[error("interrupted: {0}")]
    Interrupted(String),
    /// An output could not be written: the input naming it (`mcap`, `svg`), its path and why.
    #[error("{output} {message}")]
    Output {
        output: &'static str,
        message: String,
    },
}

impl FlowError {
    /// Bad input concerning `names`.
    pub fn input(names: &[&'static str], message: impl Into<String>) -> Self {
        FlowError::Input {
            names: names.to_vec(),
            message: message.into(),
        }
    }

    /// The inputs the error concerns (empty when it names none).
    pub fn names(&self) -> Vec<String> {
        match self {
            FlowError::Input { names, .. } => names.iter().map(|n| n.to_string()).collect(),
            FlowError::Harness(e) => e.parameters(),
            _ => Vec::new(),
        }
    }

    /// What kind of failure it is.
    pub fn kind(&self) -> ErrorKind {
        match self {
            FlowError::Input { .. } => ErrorKind::BadInput,
            FlowError::Harness(e) if e.is_failure() => ErrorKind::Failed,
            FlowError::Harness(_) => ErrorKind::BadInput,
            FlowError::Interrupted(_) => ErrorKind::Interrupted,
            FlowError::Output { .. } => ErrorKind::Failed,
        }
    }
}

impl From<rsts_closed_form::InputError> for FlowError {
    fn from(e: rsts_closed_form::InputError) -> Self {
        FlowError::input(&[e.name], e.error.to_string())
    }
}

impl From<rsts_closed_form::ClosedFormError> for FlowError {
    fn from(e: rsts_closed_form::ClosedFormError) -> Self {
        FlowError::Harness(e.into())
    }
}

impl From<rsts_dynamics::DynamicsError> for FlowError {
    fn from(e: rsts_dynamics::DynamicsError) -> Self {
        FlowError::Harness(e.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsts_closed_form::ClosedFormError;
    use rsts_dynamics::DynamicsError;

    /// Names and kinds come from the variants: the same message in another variant is
    /// another kind, and a message that starts with an option's name names nothing.
    #[test]
    fn names_and_kinds_are_read_from_variants() {
        let steps = FlowError::from(HarnessError::setting(&["steps"], "steps: too few"));
        assert_eq!(steps.names(), ["steps"]);
        assert_eq!(steps.kind(), ErrorKind::BadInput);
        assert_eq!(steps.to_string(), "steps: too few");
        let data = FlowError::from(HarnessError::Data("t-end must be positive".into()));
        assert!(data.names().is_empty());
        assert_eq!(data.kind(), ErrorKind::BadInput);
        let sigma = FlowError::from(ClosedFormError::OnSigma("h = 0".into()));
        assert_eq!(sigma.names(), ["m", "h"]);
        assert_eq!(sigma.kind(), ErrorKind::BadInput);
        let settings = FlowError::from(DynamicsError::Settings("too many steps".into()));
        assert_eq!(settings.names(), ["t-end", "rtol", "atol"]);
        for failed in [
            FlowError::from(HarnessError::Integrator("died".into())),
            FlowError::from(HarnessError::Observer("stopped".into())),
            FlowError::from(DynamicsError::Integration("step size underflow".into())),
            FlowError::Output {
                output: "svg",
                message: "out.svg: disk full".into(),
            },
        ] {
            assert_eq!(failed.kind(), ErrorKind::Failed, "{failed}");
            assert!(failed.names().is_empty(), "{failed}");
        }
        let input = FlowError::input(&["t-end"], "must be positive");
        assert_eq!(
            (input.names(), input.kind()),
            (vec!["t-end".to_string()], ErrorKind::BadInput)
        );
        assert_eq!(
            FlowError::Interrupted("3 of 5 runs".into()).kind(),
            ErrorKind::Interrupted
        );
    }
}
