//! Writes a demo log (closed-form regular precession) to the path given as argument.
//!
//! `cargo run -p rsts-mcap --example write_demo -- /tmp/demo.mcap [SAMPLES] [T_END]`
//! then `python3 scripts/check_mcap.py /tmp/demo.mcap`, or open it in Foxglove/Lichtblick.

use rsts_mcap::demo::{self, Precession};
use rsts_mcap::TrajectoryLog;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: write_demo OUT.mcap [SAMPLES=2000] [T_END=20]");
        std::process::exit(2);
    };
    let n: usize = args
        .next()
        .map_or(2000, |s| s.parse().expect("SAMPLES: an integer"));
    let t_end: f64 = args
        .next()
        .map_or(20.0, |s| s.parse().expect("T_END: a number"));
    let p = Precession::EXAMPLE;
    let run = || -> Result<(), rsts_mcap::LogError> {
        let mut log = TrajectoryLog::create(&path, &demo::metadata(&p, t_end, n))?;
        for i in 0..n {
            log.log_sample(&demo::sample(&p, 1e-3, t_end, i, n))?;
        }
        let stats = log.finish()?;
        let size = std::fs::metadata(&path)?.len();
        println!(
            "wrote {path}: {} samples, {} messages, {} bytes on disk ({:.0} B/sample), {:.0} B/sample uncompressed",
            stats.samples,
            stats.messages,
            size,
            size as f64 / n.max(1) as f64,
            stats.payload_bytes as f64 / n.max(1) as f64
        );
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
