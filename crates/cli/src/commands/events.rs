//! `rsts events`: the exact times in (t_start, t_end] at which state components, components of
//! γ = α × β or the rates of the separated variables cross zero along the closed-form motion
//! (docs/events.md). Parsing and formatting only: the flow is `rsts_flows::events`.

use std::io::Write;

use clap::Args as ClapArgs;

use rsts_flows::events::{events_report, EventsRequest};
use rsts_flows::Decimal;

use crate::args::{decimal, event_specs, flow_error, CaseArgs};
use crate::numbers::{cell, time_cell, vector_columns};
use crate::output::{self, Cell, Format, Tabular};

/// Shown at the end of `rsts events --help`.
pub const EXAMPLES: &str = "\
Examples:
  # when omega1 crosses zero and s2 turns, camera I+ (the default case), t in (0, 20]
  rsts events --event omega1 --event s2 --t-end 20

  # downward crossings of gamma3 at 40 digits, camera V (m < 0), JSON
  rsts events --m -0.7092 --h 1.5643 --torus 3 --event gamma3:down --t-end 10 --digits 40 --format json

Names: omega1..3, alpha1..3, beta1..3 (the state), gamma1..3 (gamma = alpha x beta), s1, s2 (turning
points of the separated variables: ds_i/dt = 0). Directions: up (- to +), down, both (default); a
double root (the function touches zero to the digits asked) is one event with direction 'tangent'
and passes every filter.";

/// Options of `rsts events`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Event NAME[:up|down|both] (repeatable): omega1..3, alpha1..3, beta1..3, gamma1..3, s1, s2
    #[arg(long = "event", value_name = "NAME[:DIR]", required = true)]
    pub events: Vec<String>,
    /// Start of the window (t_start, t_end]
    #[arg(long, value_name = "T", default_value = "0", value_parser = decimal, allow_hyphen_values = true)]
    pub t_start: Decimal,
    /// End of the window (t_start, t_end]
    #[arg(long, value_name = "T", default_value = "10", value_parser = decimal, allow_hyphen_values = true)]
    pub t_end: Decimal,
    /// Decimal digits of the times and states (16 to 10000; computed with 64 guard bits); default: f64, correctly rounded
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let specs = event_specs(&args.events)?;
    let request = EventsRequest {
        motion: args.case.motion(),
        events: specs.clone(),
        t_start: args.t_start.clone(),
        t_end: args.t_end.clone(),
        digits: args.digits,
    };
    let report = events_report(&request).map_err(flow_error)?;
    // The state columns after t, as in every state CSV of rsts; then the event's name and
    // direction (`check --events` reads this file as it is).
    let mut header = vec!["t".to_string()];
    header.extend(vector_columns(&["omega", "alpha", "beta"]));
    header.extend(["name".to_string(), "direction".to_string()]);
    let rows = |table: bool| {
        report.events.iter().map(move |e| {
            // The time in full, also in the table.
            let mut row = vec![time_cell(&e.t)];
            for v in [&e.state.omega, &e.state.alpha, &e.state.beta] {
                row.extend(v.iter().map(|x| cell(x, table)));
            }
            row.push(Cell::Text(e.name.clone()));
            row.push(Cell::Text(e.direction.as_str().to_string()));
            row
        })
    };
    match args.format {
        Format::Json => output::write_json(out, &report)?,
        Format::Csv => output::write_csv_rows(out, &header, rows(false))?,
        Format::Table => {
            let k = &report.case;
            let m = &k.motion;
            let asked: Vec<String> = specs
                .iter()
                .map(|s| format!("{}:{}", s.name, s.direction.as_str()))
                .collect();
            output::write_key_values(
                out,
                &[
                    ("camera", k.camera.clone()),
                    ("a, b, m, h", format!("{}, {}, {}, {}", m.a, m.b, m.m, m.h)),
                    (
                        "torus, phases",
                        format!("{}, ({}, {})", m.torus, m.phase1, m.phase2),
                    ),
                    ("window", format!("({}, {}]", k.t_start, k.t_end)),
                    ("events asked", asked.join(" ")),
                    (
                        "digits",
                        k.digits
                            .map_or("f64 (correctly rounded)".into(), |d| d.to_string()),
                    ),
                    ("events found", report.events.len().to_string()),
                ],
            )?;
            writeln!(out)?;
            let mut table = Tabular::new(header);
            for row in rows(true) {
                table.push(row);
            }
            output::write_table(out, &table)?;
        }
    }
    Ok(())
}
