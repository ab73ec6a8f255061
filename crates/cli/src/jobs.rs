//! `--jobs N`: the threads a command computes its samples on (default: every core). Results are
//! collected in input order (the flows batch them), so the output does not depend on N.

use clap::Args as ClapArgs;

/// The `--jobs` option.
#[derive(Debug, Clone, Copy, ClapArgs)]
pub struct JobsArgs {
    /// Threads to compute the samples on (default: every core; at most 8 per core); the output
    /// is the same for any N
    #[arg(long, value_name = "N", value_parser = threads)]
    pub jobs: Option<usize>,
}

/// A number of threads, from 1 to 8 per core (`rsts_harness::threads::check_jobs`).
fn threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => rsts_harness::threads::check_jobs(n),
        _ => Err(format!(
            "'{}' is not a number of threads (need N >= 1)",
            rsts_external::samples::cut(s)
        )),
    }
}
