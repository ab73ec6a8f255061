//! Argument groups shared by subcommands (problem, time grid, method) and their value parsers.
//!
//! Parsers reject what clap would otherwise accept as an `f64` ("NaN", "inf"); the domain checks
//! (a > 0, 0 ≤ b ≤ a, orthonormal α, β, positive tolerances, …) are those of `rsts-dynamics`,
//! reported with the names of the options they concern.

use anyhow::Context;
use clap::builder::{PossibleValue, TypedValueParser};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::Args;
use rsts_closed_form::{Decimal, Motion};
use rsts_dynamics::integrators::{MethodConfig, MethodName, OutputGrid, Problem, Tolerances};
use rsts_dynamics::{Fields, State};

/// Largest number of samples accepted (keeps memory use bounded: every sample is kept).
pub use rsts_harness::MAX_SAMPLES;

/// A finite `f64` ("NaN" and "inf" are rejected).
pub fn finite_f64(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{}' is not a number", rsts_io::cut(s)))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("must be a finite number, got {x}"))
    }
}

/// A decimal as written ("NaN", "inf" and what overflows f64 are rejected): the number means
/// that decimal exactly at every precision (docs/output.md, "What a number means").
pub fn decimal(s: &str) -> Result<Decimal, String> {
    Decimal::parse(s).map_err(|e| e.to_string())
}

/// A whole number of samples (the lower bound 1 is checked with the grid).
pub fn count(s: &str) -> Result<usize, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("'{}' is not a whole number (need N >= 1)", rsts_io::cut(s)))
}

/// Three finite numbers separated by commas, e.g. `0.3,-0.2,0.5`.
pub fn vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected exactly 3 comma-separated components, got {}",
            parts.len()
        ));
    }
    let mut v = [0.0; 3];
    for (k, (slot, part)) in v.iter_mut().zip(parts).enumerate() {
        *slot = finite_f64(part).map_err(|e| format!("component {}: {e}", k + 1))?;
    }
    Ok(v)
}

/// Parser of method names; the possible values (shown by `--help` and in errors) are
/// [`MethodName::ALL`], so methods added to `rsts-dynamics` appear without a change here.
#[derive(Clone, Copy, Debug, Default)]
pub struct MethodParser;

impl TypedValueParser for MethodParser {
    type Value = MethodName;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<MethodName, clap::Error> {
        let invalid = || {
            let mut err = clap::Error::new(ErrorKind::InvalidValue).with_cmd(cmd);
            if let Some(arg) = arg {
                err.insert(
                    ContextKind::InvalidArg,
                    ContextValue::String(arg.to_string()),
                );
            }
            err.insert(
                ContextKind::InvalidValue,
                ContextValue::String(value.to_string_lossy().into_owned()),
            );
            err.insert(
                ContextKind::ValidValue,
                ContextValue::Strings(
                    MethodName::ALL
                        .iter()
                        .map(|m| m.as_str().to_string())
                        .collect(),
                ),
            );
            err
        };
        value
            .to_str()
            .and_then(|s| s.parse::<MethodName>().ok())
            .ok_or_else(invalid)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            MethodName::ALL
                .iter()
                .map(|m| PossibleValue::new(m.as_str())),
        ))
    }
}

/// Field strengths and initial state.
#[derive(Debug, Clone, Args)]
pub struct ProblemArgs {
    /// Strength a of the first field (direction α, applied at e1); a > 0
    #[arg(long, value_name = "A", default_value = "1", value_parser = finite_f64, allow_hyphen_values = true)]
    pub a: f64,
    /// Strength b of the second field (direction β, applied at e2); 0 <= b <= a
    #[arg(long, value_name = "B", default_value = "0.5", value_parser = finite_f64, allow_hyphen_values = true)]
    pub b: f64,
    /// Initial angular velocity ω in the body frame
    #[arg(long, value_name = "W1,W2,W3", default_value = "0.3,-0.2,0.5", value_parser = vec3, allow_hyphen_values = true)]
    pub omega: [f64; 3],
    /// Initial direction α of the first field in the body frame; |α| = 1
    #[arg(long, value_name = "A1,A2,A3", default_value = "1,0,0", value_parser = vec3, allow_hyphen_values = true)]
    pub alpha: [f64; 3],
    /// Initial direction β of the second field in the body frame; |β| = 1, α·β = 0
    #[arg(long, value_name = "B1,B2,B3", default_value = "0,1,0", value_parser = vec3, allow_hyphen_values = true)]
    pub beta: [f64; 3],
}

impl ProblemArgs {
    /// The checked problem.
    pub fn problem(&self) -> anyhow::Result<Problem<f64>> {
        let fields = Fields::new(self.a, self.b).context("--a/--b")?;
        let initial = State {
            omega: self.omega,
            alpha: self.alpha,
            beta: self.beta,
        };
        initial.validate().context("--omega/--alpha/--beta")?;
        Ok(Problem { fields, initial })
    }
}

/// Output times: N samples evenly spaced on [0, T].
#[derive(Debug, Clone, Args)]
pub struct GridArgs {
    /// End time T >= 0
    #[arg(long, value_name = "T", default_value = "10", value_parser = finite_f64, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Number N >= 1 of samples evenly spaced on [0, T] (t = 0 and t = T included)
    #[arg(long, value_name = "N", default_value = "11", value_parser = count, allow_hyphen_values = true)]
    pub samples: usize,
}

impl GridArgs {
    /// The checked grid.
    pub fn grid(&self) -> anyhow::Result<OutputGrid> {
        if self.samples > MAX_SAMPLES {
            anyhow::bail!(
                "--samples: at most {MAX_SAMPLES} samples are supported, got {}",
                self.samples
            );
        }
        OutputGrid::new(self.t_end, self.samples).context("--t-end/--samples")
    }
}

/// The field strengths of the closed-form commands (a > b > 0: the manifold N of the seed).
#[derive(Debug, Clone, Copy, Args)]
pub struct FieldArgs {
    /// Strength a of the first field; a > b > 0
    #[arg(long, value_name = "A", default_value = "1", value_parser = finite_f64, allow_hyphen_values = true)]
    pub a: f64,
    /// Strength b of the second field
    #[arg(long, value_name = "B", default_value = "0.5", value_parser = finite_f64, allow_hyphen_values = true)]
    pub b: f64,
}

/// The field strengths as exact decimals (the motion's commands: read at the precision each
/// computation asks).
#[derive(Debug, Clone, Args)]
pub struct ExactFieldArgs {
    /// Strength a of the first field; a > b > 0 (an exact decimal)
    #[arg(long, value_name = "A", default_value = "1", value_parser = decimal, allow_hyphen_values = true)]
    pub a: Decimal,
    /// Strength b of the second field; 0 < b < a
    #[arg(long, value_name = "B", default_value = "0.5", value_parser = decimal, allow_hyphen_values = true)]
    pub b: Decimal,
}

/// The motion: fields, the point (m, h) of the invariant manifold N, the torus and the phases,
/// each an exact decimal (the time grid has its own options).
#[derive(Debug, Clone, Args)]
pub struct CaseArgs {
    #[command(flatten)]
    pub fields: ExactFieldArgs,
    /// Value m of the partial integral of N
    #[arg(long, value_name = "M", default_value = "0.3", value_parser = decimal, allow_hyphen_values = true)]
    pub m: Decimal,
    /// Energy h
    #[arg(long, value_name = "H", default_value = "-0.375", value_parser = decimal, allow_hyphen_values = true)]
    pub h: Decimal,
    /// Which Liouville torus (0-based)
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub torus: usize,
    /// Initial angle psi1 on the torus (radians)
    #[arg(long, value_name = "X", default_value = "0", value_parser = decimal, allow_hyphen_values = true)]
    pub phase1: Decimal,
    /// Initial angle psi2 on the torus (radians)
    #[arg(long, value_name = "Y", default_value = "0", value_parser = decimal, allow_hyphen_values = true)]
    pub phase2: Decimal,
}

impl CaseArgs {
    /// The motion, as written.
    pub fn motion(&self) -> Motion {
        Motion {
            a: self.fields.a.clone(),
            b: self.fields.b.clone(),
            m: self.m.clone(),
            h: self.h.clone(),
            torus: self.torus,
            phase1: self.phase1.clone(),
            phase2: self.phase2.clone(),
        }
    }

    /// The harness case on the grid of `samples` times over [0, `t_end`].
    pub fn case(&self, t_end: &Decimal, samples: usize) -> rsts_harness::Case {
        rsts_harness::Case::new(self.motion(), t_end.clone(), samples)
    }
}

/// Integration method and its settings.
#[derive(Debug, Clone, Args)]
pub struct MethodArgs {
    /// Integration method (rk4: classical fixed step; dopri5, dop853: adaptive Dormand–Prince)
    #[arg(long, value_name = "METHOD", default_value = "dop853", value_parser = MethodParser)]
    pub method: MethodName,
    /// Relative tolerance (> 0)
    #[arg(long, value_name = "R", default_value = "1e-12", value_parser = finite_f64, allow_hyphen_values = true)]
    pub rtol: f64,
    /// Absolute tolerance (> 0)
    #[arg(long, value_name = "R", default_value = "1e-12", value_parser = finite_f64, allow_hyphen_values = true)]
    pub atol: f64,
    /// Fixed step of rk4 (> 0; default: rtol^(1/4), at most 0.01); not used by adaptive methods
    #[arg(long, value_name = "H", value_parser = finite_f64, allow_hyphen_values = true)]
    pub step: Option<f64>,
}

impl MethodArgs {
    /// The checked method configuration.
    pub fn config(&self) -> anyhow::Result<MethodConfig> {
        let tolerances = Tolerances::new(self.rtol, self.atol).context("--rtol/--atol")?;
        if let Some(h) = self.step {
            MethodConfig::new(MethodName::Rk4, tolerances, Some(h)).context("--step")?;
        }
        MethodConfig::new(self.method, tolerances, self.step).context("--rtol")
    }
}

/// An error of the closed form or of a comparison, prefixed with the options it concerns
/// (`--m/--h: (m, h) lies on Σ …`, `--t-end/--rtol/--atol: … steps …`).
pub fn case_error(e: impl Into<rsts_harness::HarnessError>) -> anyhow::Error {
    crate::failure::flow_error(rsts_flows::FlowError::Harness(e.into()))
}

/// The specs of `--event` options (`NAME[:up|down|both]`, each function once), naming the
/// option and the spec on a bad one.
pub fn event_specs(raw: &[String]) -> anyhow::Result<Vec<rsts_closed_form::events::EventSpec>> {
    rsts_flows::events::event_specs(raw).map_err(|e| anyhow::anyhow!("--event {e}"))
}

pub use crate::failure::flow_error;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vec3_accepts_three_finite_components() {
        assert_eq!(vec3("0.3,-0.2, 5e-1"), Ok([0.3, -0.2, 0.5]));
    }

    #[test]
    fn vec3_rejects_wrong_counts_and_non_finite() {
        for bad in [
            "", "1", "1,2", "1,2,3,4", "1,,3", "1,x,3", "nan,0,0", "1,inf,0",
        ] {
            assert!(vec3(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn finite_f64_rejects_nan_and_infinities() {
        for bad in ["NaN", "nan", "inf", "-inf", "infinity", "1e999", "abc", ""] {
            assert!(finite_f64(bad).is_err(), "{bad:?} accepted");
        }
        assert_eq!(finite_f64("-2.5"), Ok(-2.5));
    }
}
