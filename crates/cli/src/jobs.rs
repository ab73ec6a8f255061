//! `--jobs N`: the threads a command computes its samples on (default: every core). Results are
//! collected in input order, so the output does not depend on N.

use anyhow::Context;
use clap::Args as ClapArgs;
use rayon::prelude::*;

/// Samples computed per parallel batch (written in order between batches).
pub const BATCH: usize = 8192;

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

/// `f` over `items` in batches of [`BATCH`] on `pool`, each batch's results handed to `sink` in
/// input order.
pub fn for_each_batch<T: Sync, R: Send, E>(
    pool: &rayon::ThreadPool,
    items: &[T],
    f: impl Fn(&T) -> R + Sync,
    mut sink: impl FnMut(Vec<R>) -> Result<(), E>,
) -> Result<(), E> {
    for chunk in items.chunks(BATCH) {
        let out: Vec<R> = pool.install(|| chunk.par_iter().map(&f).collect());
        sink(out)?;
    }
    Ok(())
}
