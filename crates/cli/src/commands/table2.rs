//! `rsts table2`: the classification of sec. 2–3, measured at a representative point of each
//! camera — the partial motions driven by F₁* and F₂ and the semi-moving frame's pendulum motion
//! (oscillation/rotation from the sign changes along the torus), and the coordinate planes each
//! connected P-surface (and Π-surface) is symmetric to, measured on the meshes of every torus.

use std::io::Write;

use clap::Args as ClapArgs;

use rsts_geometry::tables::table2;

use crate::args::FieldArgs;
use crate::output::{self, Cell, Format, Tabular};

/// Shown at the end of `rsts table2 --help`.
pub const EXAMPLES: &str = "\
Examples:
  rsts table2
  rsts table2 --a 1 --b 0.5 --format json";

/// Options of `rsts table2`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: FieldArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let rows = table2(args.fields.a, args.fields.b).map_err(|e| anyhow::anyhow!("--a/--b: {e}"))?;
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
        "tori",
        "F1*-partial",
        "F2-partial",
        "semi-moving",
        "P symmetric to",
        "Pi symmetric to",
        "sign-changing radicals",
    ]);
    let list = |v: &[&str]| {
        if v.is_empty() {
            "-".to_string()
        } else {
            v.join(" ")
        }
    };
    for r in &rows {
        t.push(vec![
            Cell::Text(r.camera.into()),
            Cell::Int(r.tori as u64),
            Cell::Text(r.first_partial.as_str().into()),
            Cell::Text(r.second_partial.as_str().into()),
            Cell::Text(r.semi_moving.as_str().into()),
            Cell::Text(list(&r.symmetry_planes).replace("omega", "ω")),
            Cell::Text(list(&r.pi_symmetry_planes).replace("Omega", "Ω")),
            Cell::Text(list(&r.radicals_changing_sign)),
        ]);
    }
    // The table (CSV and JSON returned above).
    output::write_missing_cameras(out, |l| rows.iter().any(|r| r.camera == l))?;
    writeln!(
        out,
        "Table 2 at a = {}, b = {} (one representative point per camera)",
        args.fields.a, args.fields.b
    )?;
    output::write_table(out, &t)?;
    writeln!(out, "differences from the seed (sec. 3):")?;
    let mut any = false;
    for r in &rows {
        for d in &r.differs_from_paper {
            any = true;
            writeln!(out, "  {}: {d}", r.camera)?;
        }
    }
    if !any {
        writeln!(out, "  none")?;
    }
    Ok(())
}
