//! `rsts diagram`: the (m, h) plane of N — admissible region, bifurcation diagram Σ and the cameras
//! of Table 1 as an SVG picture, or the description of one point (camera, θ's, segments, tori,
//! periods).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Args as ClapArgs;

use rsts_closed_form::diagram::{describe_point, diagram_svg, DiagramOptions};

use crate::args::{case_error, finite_f64, FieldArgs};
use crate::output::{self, Format};

/// Shown at the end of `rsts diagram --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the picture of the (m, h) plane for a = 1, b = 0.5
  rsts diagram --a 1 --b 0.5 --svg out/diagram.svg

  # one point: camera, roots of Phi, oscillation segments of s1 and s2, tori, periods
  rsts diagram --a 1 --b 0.5 --m -0.7092 --h 1.5643
  rsts diagram --m 0.3 --h -0.375 --format json";

/// Options of `rsts diagram`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: FieldArgs,
    /// Write the picture of the (m, h) plane to this SVG file (written whole or not at all)
    #[arg(long, value_name = "FILE", conflicts_with_all = ["m", "h", "format"])]
    pub svg: Option<PathBuf>,
    /// Describe the point (m, h) (needs --h)
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_hyphen_values = true, requires = "h")]
    pub m: Option<f64>,
    /// Describe the point (m, h) (needs --m)
    #[arg(long, value_name = "H", value_parser = finite_f64, allow_hyphen_values = true, requires = "m")]
    pub h: Option<f64>,
    /// m-range of the picture, LO,HI (default: a window showing every camera)
    #[arg(long, value_name = "LO,HI", value_parser = range, allow_hyphen_values = true)]
    pub m_range: Option<(f64, f64)>,
    /// h-range of the picture, LO,HI
    #[arg(long, value_name = "LO,HI", value_parser = range, allow_hyphen_values = true)]
    pub h_range: Option<(f64, f64)>,
    /// Output format of a point description (csv: one header line and one row, the JSON fields
    /// flattened) [default: table]
    #[arg(long, value_enum)]
    pub format: Option<Format>,
}

/// `LO,HI` with LO < HI, both finite.
fn range(s: &str) -> Result<(f64, f64), String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [lo, hi] = parts[..] else {
        return Err(format!("expected LO,HI, got '{}'", rsts_io::cut(s)));
    };
    let (lo, hi) = (finite_f64(lo)?, finite_f64(hi)?);
    if lo >= hi {
        return Err(format!("need LO < HI, got {lo},{hi}"));
    }
    Ok((lo, hi))
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    match (&args.svg, args.m, args.h) {
        (Some(path), None, None) => {
            let opts = DiagramOptions {
                m_range: args.m_range,
                h_range: args.h_range,
                ..DiagramOptions::default()
            };
            rsts_io::check_writable(path).with_context(|| format!("--svg {}", path.display()))?;
            let svg = diagram_svg(args.fields.a, args.fields.b, &opts).map_err(case_error)?;
            rsts_io::write_atomic(path, svg.as_bytes())
                .with_context(|| format!("--svg {}", path.display()))?;
            eprintln!("wrote {}", path.display());
        }
        (None, Some(m), Some(h)) => {
            let d = describe_point(args.fields.a, args.fields.b, m, h).map_err(case_error)?;
            match args.format.unwrap_or(Format::Table) {
                Format::Json => output::write_json(out, &d)?,
                Format::Csv => output::write_records_csv(out, &[&d])?,
                Format::Table => write!(out, "{d}")?,
            }
        }
        _ => bail!("give either --svg FILE (the picture) or --m M --h H (one point)"),
    }
    Ok(())
}
