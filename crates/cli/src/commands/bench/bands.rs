//! The table of `rsts bench --ensemble`: the bands per method and tolerance, then the motions
//! (each can be rerun alone with `rsts compare … --pieces 1`).

use std::io::Write;

use rsts_harness::bench::BenchReport;

use crate::output::{self, Cell, Tabular};

/// The header lines, the bands and the motions.
pub(super) fn write_table(out: &mut dyn Write, report: &BenchReport) -> anyhow::Result<()> {
    let Some(e) = &report.ensemble else {
        return Ok(());
    };
    let case = &report.case;
    writeln!(
        out,
        "ensemble of {} motions (seed {}): a = {}, b = {}, T = {}, {} samples; time: median of {} runs",
        e.n, e.seed, case.motion.a, case.motion.b, case.t_end, case.samples, report.repeats
    )?;
    if let Some(sh) = &report.shard {
        let held = e.motions.len().saturating_sub(sh.k - 1).div_ceil(sh.n);
        writeln!(
            out,
            "shard {}/{}: the {held} motions whose index is {} mod {} (`rsts bench merge` joins the shards' --json reports)",
            sh.k,
            sh.n,
            sh.k - 1,
            sh.n
        )?;
    }
    writeln!(out, "{}", report.environment.describe())?;
    let mut t = Tabular::new(vec![
        "method",
        "tolerance",
        "motions",
        "max error: 5 %",
        "median",
        "95 %",
        "seconds: median (5 %..95 %)",
    ]);
    for b in &report.bands {
        t.push(vec![
            Cell::Text(report.label_of_method(&b.method).to_string()),
            Cell::Text(format!("{:e}", b.tolerance)),
            Cell::Int(b.motions as u64),
            Cell::Text(format!("{:.2e}", b.error_p05)),
            Cell::Text(format!("{:.2e}", b.error_median)),
            Cell::Text(format!("{:.2e}", b.error_p95)),
            Cell::Text(format!(
                "{:.3e} ({:.2e}..{:.2e})",
                b.time_median, b.time_p05, b.time_p95
            )),
        ]);
    }
    output::write_table(out, &t)?;
    let over = match report.shard {
        Some(_) => " (this shard's motions)",
        None => " (all motions)",
    };
    super::write_fits(out, report, over)?;
    writeln!(out)?;
    let mut m = Tabular::new(vec![
        "motion", "camera", "m", "h", "torus", "phase1", "phase2",
    ]);
    let held = |k: usize| report.shard.as_ref().is_none_or(|sh| k % sh.n == sh.k - 1);
    for (k, mo) in e.motions.iter().enumerate().filter(|(k, _)| held(*k)) {
        m.push(vec![
            Cell::Int(k as u64),
            Cell::Text(mo.camera.clone()),
            Cell::Text(mo.m.to_string()),
            Cell::Text(mo.h.to_string()),
            Cell::Int(mo.torus as u64),
            Cell::Text(mo.phase1.to_string()),
            Cell::Text(mo.phase2.to_string()),
        ]);
    }
    output::write_table(out, &m)?;
    Ok(())
}
