//! Options shared by the commands that run an external integrator (`--exec`): compare, bench,
//! validate. The protocol and the process handling are in `rsts-external`.

use anyhow::anyhow;
use clap::Args;
use rsts_dynamics::integrators::Tolerances;
use rsts_external::Exec;

use crate::args::finite_f64;

/// `--exec-timeout`.
#[derive(Debug, Clone, Args)]
pub struct TimeoutArgs {
    /// Seconds an external integrator (--exec) may take before it is killed (> 0)
    #[arg(long, value_name = "S", default_value = "600", value_parser = seconds)]
    pub exec_timeout: f64,
}

/// A positive, finite number of seconds (checked with or without --exec, by the rule of every
/// timeout: `rsts_external::check_timeout`).
fn seconds(s: &str) -> Result<f64, String> {
    let x = finite_f64(s)?;
    rsts_external::check_timeout(x)?;
    Ok(x)
}

/// An external integrator from a command line, with the settings of a request.
pub fn exec_integrator(
    command: &str,
    tolerances: Tolerances,
    digits: Option<u32>,
    timeout: f64,
) -> anyhow::Result<Exec> {
    let mut exec = Exec::new(command, tolerances).map_err(|e| anyhow!("--exec: {e}"))?;
    exec.check_program().map_err(|e| anyhow!("--exec: {e}"))?;
    if let Some(d) = digits {
        exec = exec.with_digits(d).map_err(|e| anyhow!("--digits: {e}"))?;
    }
    exec.with_timeout(timeout)
        .map_err(|e| anyhow!("--exec-timeout: {e}"))
}

/// An `--exec` command as a method of a benchmark: an [`Exec`] per tolerance.
pub struct ExecMethod {
    pub command: String,
    pub timeout: f64,
}

impl rsts_harness::bench::OutsideMethod for ExecMethod {
    fn what(&self) -> String {
        "--exec".into()
    }

    fn identity(&self) -> String {
        format!("--exec {}", self.command)
    }

    fn at(
        &mut self,
        tolerances: Tolerances,
        digits: u32,
    ) -> Result<Box<dyn rsts_harness::bench::BenchIntegrator>, rsts_harness::HarnessError> {
        let exec = exec_integrator(&self.command, tolerances, Some(digits), self.timeout)
            .map_err(|e| rsts_harness::HarnessError::Integrator(format!("{e:#}")))?;
        Ok(Box::new(exec))
    }
}
