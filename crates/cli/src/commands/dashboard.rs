//! `rsts dashboard`: write the static site of a validation history (overview, trend pages, a
//! page per night), opened from the file system. See rsts-history and docs/validation.md.
//!
//! Exit codes: 0 written, 2 bad input (a missing, locked, foreign or newer database, a history
//! without nights, an output directory holding other files; nothing written).

use std::io::Write;
use std::path::PathBuf;

use clap::Args as ClapArgs;

/// Shown at the end of `rsts dashboard --help`.
pub const EXAMPLES: &str = "\
Examples:
  rsts validate --suite validation/quick.toml --report out/night-1 --history out/history.sqlite
  rsts dashboard --history out/history.sqlite --out out/dashboard
  # then open out/dashboard/index.html in a browser

Exit code 2 is bad input (nothing is written). See docs/validation.md.";

#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The history database
    #[arg(long, value_name = "FILE")]
    pub history: PathBuf,
    /// Directory of the site (written whole; a new, empty or earlier dashboard directory)
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let built = rsts_history::dashboard::build(&args.history, &args.out)?;
    writeln!(
        out,
        "dashboard: {} ({} nights, {} series in {} cells, {} regressions, {} pages)",
        args.out.join("index.html").display(),
        built.nights,
        built.series,
        built.cells,
        built.regressions,
        built.pages
    )?;
    Ok(())
}
