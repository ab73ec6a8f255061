//! `rsts bench merge`: the shards of an ensemble (`rsts bench --ensemble N --shard K/N --json
//! FILE`) joined into the report of the whole ensemble, written as `rsts bench` writes it. The
//! checks and the merge are [`rsts_harness::bench::bench_merge`]'s.

use std::io::Write;
use std::path::PathBuf;

use clap::Args as ClapArgs;
use rsts_harness::bench::{bench_merge, BenchMergeRequest};

use crate::args::case_error;

/// Options of `rsts bench merge`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The JSON reports of the shards (`--json FILE` or `--format json` of each), in any order
    #[arg(value_name = "FILE", required = true)]
    pub shards: Vec<PathBuf>,
    #[command(flatten)]
    pub output: super::Outputs,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    args.output.check("FILE", &args.shards)?;
    let request = BenchMergeRequest {
        shards: args.shards.clone(),
    };
    let merged = bench_merge(&request).map_err(case_error)?;
    for note in &merged.notes {
        eprintln!("{note}");
    }
    args.output.write(&merged.report, out)
}
