//! `rsts table1`: the seed's Table 1 recomputed — at a representative point of each camera, the
//! roots θ₁, θ₂ of Φ in order with ±a, ±b and the oscillation segments of s₁ and s₂ (from the
//! closed form's segments in x = 1/s₁ and s₂), each compared with the printed row.

use std::io::Write;

use clap::Args as ClapArgs;

use rsts_geometry::tables::table1;

use crate::args::FieldArgs;
use crate::output::{self, Cell, Format, Tabular};

/// Shown at the end of `rsts table1 --help`.
pub const EXAMPLES: &str = "\
Examples:
  rsts table1
  rsts table1 --a 1 --b 0.3 --format json";

/// Options of `rsts table1`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: FieldArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

fn yes_no(b: bool) -> Cell {
    Cell::Text(if b { "yes" } else { "NO" }.into())
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let rows = table1(args.fields.a, args.fields.b).map_err(|e| anyhow::anyhow!("--a/--b: {e}"))?;
    if args.format == Format::Csv {
        // One row per camera, the columns of the JSON rows (docs/output.md).
        output::write_records_csv(out, &rows)?;
        return Ok(());
    }
    if args.format == Format::Json {
        output::write_json(
            out,
            &serde_json::json!({"a": args.fields.a, "b": args.fields.b, "cameras": rows}),
        )?;
        return Ok(());
    }
    let mut t = Tabular::new([
        "camera",
        "m",
        "h",
        "roots of Phi (computed)",
        "paper",
        "ok",
        "s1 segment",
        "s2 segment",
        "paper s1",
        "paper s2",
        "ok",
        "tori",
    ]);
    for r in &rows {
        t.push(vec![
            Cell::Text(r.camera.label().into()),
            Cell::Num(r.m),
            Cell::Num(r.h),
            Cell::Text(r.roots_order.clone()),
            Cell::Text(r.paper_roots.into()),
            yes_no(r.roots_agree),
            Cell::Text(r.s1_segment.clone()),
            Cell::Text(r.s2_segment.clone()),
            Cell::Text(r.paper_s1.into()),
            Cell::Text(r.paper_s2.into()),
            yes_no(r.segments_agree),
            Cell::Int(r.tori as u64),
        ]);
    }
    // The table (CSV and JSON returned above).
    output::write_missing_cameras(out, |l| rows.iter().any(|r| r.camera.label() == l))?;
    writeln!(
        out,
        "Table 1 at a = {}, b = {} (one representative point per camera)",
        args.fields.a, args.fields.b
    )?;
    output::write_table(out, &t)?;
    let bad = rows
        .iter()
        .filter(|r| !(r.roots_agree && r.segments_agree))
        .count();
    writeln!(
        out,
        "{} of {} rows agree with the paper",
        rows.len() - bad,
        rows.len()
    )?;
    Ok(())
}
