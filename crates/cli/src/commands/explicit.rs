//! `rsts explicit`: the closed-form motion on the invariant manifold N (seed sec. 1–3) at N times
//! evenly spaced on [0, T], in f64 or at any number of decimal digits. Parsing and formatting
//! only: the flow is `rsts_flows::explicit`.

use std::io::Write;

use clap::Args as ClapArgs;

use rsts_flows::explicit::{explicit, ExplicitRequest};
use rsts_flows::{Decimal, Times};

use crate::args::{count, decimal, flow_error, CaseArgs};
use crate::numbers::{cell, short, vector_columns};
use crate::output::{self, Format};

/// Shown at the end of `rsts explicit --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the built-in default case: a=1, b=0.5, m=0.3, h=-0.375 (camera I+), torus 0, phases 0, T=10, 11 samples
  rsts explicit

  # camera V (four tori): the fourth torus, phases (0.5, 1), 60 digits, JSON
  rsts explicit --a 1 --b 0.5 --m -0.7092 --h 1.5643 --torus 3 --phase1 0.5 --phase2 1 \\
      --t-end 20 --samples 5 --digits 60 --format json

Tori are numbered from 0; the phases are the angles (psi1, psi2) on the torus at t = 0, in radians
(psi = 0: each separated variable at the lower end of its oscillation segment, in x = 1/s1 and s2).
Every number is the decimal as written, at every precision; the times are k*T/(N-1) exactly (an
f64 row shows the f64 nearest its time, docs/numbers.md).
`rsts diagram --m M --h H` shows the camera, the tori and the segments of a point.";

/// Options of `rsts explicit`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// End time T >= 0
    #[arg(long, value_name = "T", default_value = "10", value_parser = decimal, allow_hyphen_values = true)]
    pub t_end: Decimal,
    /// Number N >= 1 of samples evenly spaced on [0, T] (N = 1: t = 0 only)
    #[arg(long, value_name = "N", default_value = "11", value_parser = count)]
    pub samples: usize,
    /// Decimal digits of the computation and of the output (16 to 100000); default: f64
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let request = ExplicitRequest {
        motion: args.case.motion(),
        times: Times::grid(args.t_end.clone(), args.samples),
        digits: args.digits,
    };
    let doc = explicit(&request).map_err(flow_error)?;
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv | Format::Table => {
            let mut header = vec!["t".to_string()];
            header.extend(vector_columns(&[
                "omega", "alpha", "beta", "gamma", "Omega",
            ]));
            let as_table = args.format == Format::Table && doc.digits <= 17;
            let cells = || {
                (0..doc.samples.len()).map(|k| {
                    doc.samples
                        .row(k)
                        .iter()
                        .map(|x| cell(x, as_table))
                        .collect()
                })
            };
            if args.format == Format::Csv {
                output::write_csv_rows(out, &header, cells())?;
            } else {
                let [p1, p2] = doc.periods;
                output::write_key_values(
                    out,
                    &[
                        ("camera", doc.camera.clone()),
                        ("torus", format!("{} of {}", doc.torus, doc.tori)),
                        ("a, b", format!("{}, {}", short(&doc.a), short(&doc.b))),
                        ("m, h", format!("{}, {}", short(&doc.m), short(&doc.h))),
                        ("periods", format!("{p1:.10}, {p2:.10}")),
                        ("rotation number", format!("{:.12}", doc.rotation_number)),
                        ("digits", doc.digits.to_string()),
                    ],
                )?;
                writeln!(out)?;
                output::write_table_rows(out, &header, cells)?;
            }
        }
    }
    Ok(())
}
