//! `rsts events`: the exact times in (t_start, t_end] at which state components, components of
//! γ = α × β or the rates of the separated variables cross zero along the closed-form motion
//! (docs/events.md). Parsing and formatting only: the flow is `rsts_flows::events`.

use std::io::Write;

use clap::Args as ClapArgs;

use rsts_closed_form::events::{EventCase, EventRecord};
use rsts_flows::events::{events, EventsRequest};
use rsts_flows::sink::Sink;
use rsts_flows::{Decimal, FlowError};

use crate::args::{decimal, event_specs, flow_error, CaseArgs};
use crate::numbers::{cell, time_cell, vector_columns};
use crate::output::{self, Cell, Format};

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
    let asked: Vec<String> = specs
        .iter()
        .map(|s| format!("{}:{}", s.name, s.direction.as_str()))
        .collect();
    let mut sink = Output {
        format: args.format,
        out,
        asked: asked.join(" "),
        header: Vec::new(),
        started: Started::Not,
        rows: 0,
        width: 0,
    };
    // The flow checks the request and sizes the output before the head; the events are
    // written as they are found.
    events(&request, &mut sink).map_err(|e| match e.downcast::<FlowError>() {
        Ok(f) => flow_error(f),
        Err(e) => e,
    })?;
    sink.finish()
}

/// The document being written.
enum Started {
    Not,
    Json(output::StreamedJson),
    Csv,
    Table(output::StreamedTable),
}

/// The events document written as it comes: JSON `{"case", "events"}`, CSV rows or the table.
struct Output<'a> {
    format: Format,
    out: &'a mut dyn Write,
    asked: String,
    header: Vec<String>,
    started: Started,
    rows: usize,
    width: usize,
}

impl Output<'_> {
    /// One row of the CSV or the table: the time in full, the state, the name and direction.
    fn cells(e: &EventRecord, table: bool) -> Vec<Cell> {
        let mut row = vec![time_cell(&e.t)];
        for v in [&e.state.omega, &e.state.alpha, &e.state.beta] {
            row.extend(v.iter().map(|x| cell(x, table)));
        }
        row.push(Cell::Text(e.name.clone()));
        row.push(Cell::Text(e.direction.as_str().to_string()));
        row
    }

    /// Close the document.
    fn finish(self) -> anyhow::Result<()> {
        match self.started {
            Started::Json(doc) => doc.finish(self.out)?,
            Started::Table(_) => output::write_key_values_at(
                self.out,
                &[("events found", self.rows.to_string())],
                self.width,
            )?,
            Started::Csv | Started::Not => {}
        }
        Ok(())
    }
}

impl Sink<EventCase, EventRecord> for Output<'_> {
    type Error = anyhow::Error;

    fn head(&mut self, k: &EventCase) -> anyhow::Result<()> {
        // The state columns after t, as in every state CSV of rsts; then the event's name and
        // direction (`check --events` reads this file as it is).
        self.header = vec!["t".to_string()];
        self.header
            .extend(vector_columns(&["omega", "alpha", "beta"]));
        self.header
            .extend(["name".to_string(), "direction".to_string()]);
        self.started = match self.format {
            Format::Json => Started::Json(output::StreamedJson::start(
                self.out,
                &[("case", k)],
                "events",
            )?),
            Format::Csv => {
                output::write_csv_header(self.out, &self.header)?;
                Started::Csv
            }
            Format::Table => {
                let m = &k.motion;
                let items = [
                    ("camera", k.camera.clone()),
                    ("a, b, m, h", format!("{}, {}, {}, {}", m.a, m.b, m.m, m.h)),
                    (
                        "torus, phases",
                        format!("{}, ({}, {})", m.torus, m.phase1, m.phase2),
                    ),
                    ("window", format!("({}, {}]", k.t_start, k.t_end)),
                    ("events asked", self.asked.clone()),
                    (
                        "digits",
                        k.digits
                            .map_or("f64 (correctly rounded)".into(), |d| d.to_string()),
                    ),
                ];
                self.width = items
                    .iter()
                    .map(|(k, _)| k.chars().count())
                    .max()
                    .unwrap_or(0);
                output::write_key_values_at(self.out, &items, self.width)?;
                writeln!(self.out)?;
                // Columns as wide as their widest value: the time in full, the state readable.
                let t_width = k.digits.map_or(24, |d| d as usize + 12);
                let mut widths = vec![t_width];
                widths.extend([output::READABLE_WIDTH; 9]);
                widths.extend([6, 7]);
                let header: Vec<&str> = self.header.iter().map(String::as_str).collect();
                Started::Table(output::StreamedTable::start(self.out, &header, &widths)?)
            }
        };
        Ok(())
    }

    fn row(&mut self, e: EventRecord) -> anyhow::Result<()> {
        match &mut self.started {
            Started::Json(doc) => doc.item(self.out, &e)?,
            Started::Csv => {
                output::write_csv_row(self.out, &self.header, self.rows, &Self::cells(&e, false))?
            }
            Started::Table(table) => table.row(self.out, &Self::cells(&e, true))?,
            Started::Not => anyhow::bail!("an event before the head"),
        }
        self.rows += 1;
        Ok(())
    }
}
