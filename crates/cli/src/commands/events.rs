//! `rsts events`: the exact times in (t_start, t_end] at which state components, components of
//! γ = α × β or the rates of the separated variables cross zero along the closed-form motion
//! (docs/events.md). Parsing and formatting only: the events are `rsts_closed_form::events`.

use std::io::Write;

use anyhow::bail;
use clap::Args as ClapArgs;

use rsts_closed_form::events::{EventCase, EventRecord, EventSpec, EventsRun, Number};

use crate::args::{finite_f64, CaseArgs};
use crate::output::{self, Cell, Format};

/// Largest number of digits accepted.
pub const MAX_DIGITS: u32 = 10_000;

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
    #[arg(long, value_name = "T", default_value = "0", value_parser = finite_f64, allow_hyphen_values = true)]
    pub t_start: f64,
    /// End of the window (t_start, t_end]
    #[arg(long, value_name = "T", default_value = "10", value_parser = finite_f64, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Decimal digits of the times and states (16 to 10000; computed with 64 guard bits); default: f64, correctly rounded
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

/// The specs of the `--event` options, naming the option on a bad one.
pub fn parse_specs(raw: &[String]) -> anyhow::Result<Vec<EventSpec>> {
    let mut specs: Vec<EventSpec> = Vec::new();
    for s in raw {
        let spec: EventSpec = s
            .parse()
            .map_err(|e| anyhow::anyhow!("--event '{}': {e}", rsts_io::cut(s)))?;
        if specs.iter().any(|p| p.name == spec.name) {
            bail!(
                "--event '{}': {} is asked for twice",
                rsts_io::cut(s),
                spec.name
            );
        }
        specs.push(spec);
    }
    Ok(specs)
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let specs = parse_specs(&args.events)?;
    if let Some(d) = args.digits {
        if !(16..=MAX_DIGITS).contains(&d) {
            bail!("--digits: must be between 16 and {MAX_DIGITS}, got {d}");
        }
    }
    if args.t_end <= args.t_start {
        bail!(
            "--t-end: the window (t_start, t_end] = ({}, {}] is empty: need --t-end > --t-start",
            rsts_dynamics::shown(args.t_start),
            rsts_dynamics::shown(args.t_end)
        );
    }
    let c = &args.case;
    let case = EventCase {
        motion: c.motion(),
        t_start: args.t_start,
        t_end: args.t_end,
        digits: args.digits,
        camera: String::new(),
    };
    // The motion is built and the window checked; the output is sized before any event is
    // computed, then written as the events are found.
    let run = EventsRun::new(case, &specs).map_err(crate::args::case_error)?;
    output::check_output_bytes("--t-end/--event/--digits", "the events", run.most_bytes())?;
    // The state columns after t, as in every state CSV of rsts; then the event's name and
    // direction (`check --events` reads this file as it is).
    let names: Vec<String> = ["omega", "alpha", "beta"]
        .iter()
        .flat_map(|n| (1..=3).map(move |i| format!("{n}{i}")))
        .collect();
    let mut header = vec!["t"];
    header.extend(names.iter().map(String::as_str));
    header.extend(["name", "direction"]);
    let cell = |x: &Number, table: bool| match x {
        Number::F64(v) => Cell::Num(*v),
        Number::Decimal(_) if table => Cell::Num(x.to_f64()),
        Number::Decimal(s) => Cell::Text(s.clone()),
    };
    let row = |e: &EventRecord, table: bool| {
        let mut row = vec![match &e.t {
            // The time in full, also in the table.
            Number::F64(v) => Cell::Text(format!("{v:?}")),
            Number::Decimal(s) => Cell::Text(s.clone()),
        }];
        for v in [&e.state.omega, &e.state.alpha, &e.state.beta] {
            row.extend(v.iter().map(|x| cell(x, table)));
        }
        row.push(Cell::Text(e.name.clone()));
        row.push(Cell::Text(e.direction.as_str().to_string()));
        row
    };
    let k = run.case();
    match args.format {
        Format::Json => {
            let mut doc = output::StreamedJson::start(out, &[("case", k)], "events")?;
            run.for_each(|e| Ok::<(), Stop>(doc.item(out, &e)?))
                .map_err(|s| s.0)?;
            doc.finish(out)?;
        }
        Format::Csv => {
            let header: Vec<String> = header.iter().map(|s| s.to_string()).collect();
            output::write_csv_header(out, &header)?;
            let mut r = 0;
            run.for_each(|e| {
                output::write_csv_row(out, &header, r, &row(&e, false))?;
                r += 1;
                Ok::<(), Stop>(())
            })
            .map_err(|s| s.0)?;
        }
        Format::Table => {
            let asked: Vec<String> = specs
                .iter()
                .map(|s| format!("{}:{}", s.name, s.direction.as_str()))
                .collect();
            let items = [
                ("camera", k.camera.clone()),
                (
                    "a, b, m, h",
                    format!(
                        "{}, {}, {}, {}",
                        k.motion.a, k.motion.b, k.motion.m, k.motion.h
                    ),
                ),
                (
                    "torus, phases",
                    format!(
                        "{}, ({}, {})",
                        k.motion.torus, k.motion.phase1, k.motion.phase2
                    ),
                ),
                ("window", format!("({}, {}]", k.t_start, k.t_end)),
                ("events asked", asked.join(" ")),
                (
                    "digits",
                    k.digits
                        .map_or("f64 (correctly rounded)".into(), |d| d.to_string()),
                ),
            ];
            let width = items
                .iter()
                .map(|(k, _)| k.chars().count())
                .max()
                .unwrap_or(0);
            output::write_key_values_at(out, &items, width)?;
            writeln!(out)?;
            // Columns as wide as their widest value: the time in full, the state readable.
            let t_width = k.digits.map_or(24, |d| d as usize + 12);
            let mut widths = vec![t_width];
            widths.extend([output::READABLE_WIDTH; 9]);
            widths.extend([6, 7]);
            let mut table = output::StreamedTable::start(out, &header, &widths)?;
            let mut found = 0usize;
            run.for_each(|e| {
                table.row(out, &row(&e, true))?;
                found += 1;
                Ok::<(), Stop>(())
            })
            .map_err(|s| s.0)?;
            output::write_key_values_at(out, &[("events found", found.to_string())], width)?;
        }
    }
    Ok(())
}

/// What stops the events being written: the search (an error naming its option) or the output.
struct Stop(anyhow::Error);

impl From<rsts_closed_form::ClosedFormError> for Stop {
    fn from(e: rsts_closed_form::ClosedFormError) -> Self {
        Stop(crate::args::case_error(e))
    }
}

impl From<std::io::Error> for Stop {
    fn from(e: std::io::Error) -> Self {
        Stop(e.into())
    }
}
