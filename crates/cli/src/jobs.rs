//! `--jobs N`: the threads a command computes its samples on (default: every core). Results are
//! collected in input order (the flows batch them), so the output does not depend on N.

use anyhow::Context;
use clap::Args as ClapArgs;

/// The `--jobs` option.
#[derive(Debug, Clone, Copy, ClapArgs)]
pub struct JobsArgs {
    /// Threads to compute the samples on (default: every core); the output is the same for any N
    #[arg(long, value_name = "N", value_parser = threads)]
    pub jobs: Option<usize>,
}

/// A number of threads, at least 1.
fn threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("'{s}' is not a number of threads (need N >= 1)")),
    }
}

impl JobsArgs {
    /// A thread pool of `--jobs` threads.
    pub fn pool(&self) -> anyhow::Result<rayon::ThreadPool> {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(n) = self.jobs {
            b = b.num_threads(n);
        }
        b.build().context("--jobs: cannot start the threads")
    }
}
