//! `rsts reference`: the exact motion on N at times the user chooses (a list, a file, or an even
//! grid), with H, K, G per row, as CSV, JSON or npy — to start and check an integrator written
//! elsewhere (docs/own-integrator.md).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;

use anyhow::{anyhow, bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use rug::Float;
use serde_json::{json, Value};

use rsts_dynamics::integrators::OutputGrid;
use rsts_harness::reference::{check_digits, ReferenceTable, COLUMNS};

use crate::args::{case_error, count, finite_f64, CaseArgs, MAX_SAMPLES};
use crate::jobs::{for_each_batch, JobsArgs};
use crate::output;

/// Shown at the end of `rsts reference --help`.
pub const EXAMPLES: &str = "\
Examples:
  # the default motion (camera I+: a=1, b=0.5, m=0.3, h=-0.375) at three times, CSV
  rsts reference --times 0,0.5,2

  # camera V, third torus, 101 times on [0, 10], 40 digits, JSON to a file
  rsts reference --m -0.7092 --h 1.5643 --torus 2 --t-end 10 --samples 101 --digits 40 \\
      --format json -o out/ref-v.json

  # at the times of a file (one per line), as a numpy array (N, 13)
  rsts reference --times 0,1,2,3 --format npy -o out/ref.npy

Columns: t, omega1..3, alpha1..3, beta1..3 (the state in the body frame), H, K, G. Without
--digits the closed form is evaluated at 30 digits + 64 bits and rounded to f64 (17 significant
digits, read back exactly); with --digits D every value carries D digits (CSV and JSON only).
The f64 values come from the closed form in double-double, each checked to round to the same
f64 as the MPFR value (else that row is computed in MPFR): the same bits, faster. Rows are
computed on --jobs threads (default: every core) and written in order. The state at the first
time starts an integrator; `rsts check` compares its trajectory with this motion.";

/// Output formats of `rsts reference`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RefFormat {
    /// Comma-separated values with one header line
    Csv,
    /// One JSON document
    Json,
    /// numpy array of float64, shape (N, 13) (with -o FILE or a redirected stdout)
    Npy,
}

/// Options of `rsts reference`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Sample times, comma-separated, strictly increasing
    #[arg(long, value_name = "T0,T1,...", value_delimiter = ',', value_parser = finite_f64, allow_hyphen_values = true,
          conflicts_with_all = ["times_file", "t_end", "samples"])]
    pub times: Option<Vec<f64>>,
    /// Sample times from a file: numbers separated by newlines, commas or spaces ('#' comments)
    #[arg(long, value_name = "FILE", conflicts_with_all = ["t_end", "samples"])]
    pub times_file: Option<PathBuf>,
    /// End time T of N evenly spaced times on [0, T] (with --samples)
    #[arg(long, value_name = "T", value_parser = finite_f64, allow_hyphen_values = true, requires = "samples")]
    pub t_end: Option<f64>,
    /// Number N of evenly spaced times (with --t-end)
    #[arg(long, value_name = "N", value_parser = count, requires = "t_end")]
    pub samples: Option<usize>,
    /// Decimal digits of every value (18 to 10000; default: f64, correctly rounded)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Output format
    #[arg(long, value_enum, default_value_t = RefFormat::Csv)]
    pub format: RefFormat,
    /// Write to FILE (whole or not at all) instead of stdout
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub jobs: JobsArgs,
}

/// The requested times, checked.
fn times(args: &Args) -> anyhow::Result<Vec<f64>> {
    let (times, what) = match (&args.times, &args.times_file, args.t_end, args.samples) {
        (Some(t), _, _, _) => (t.clone(), "--times"),
        (None, Some(path), _, _) => (
            rsts_harness::times_file::read_times_file(path)
                .map_err(|e| anyhow!("--times-file {}: {e}", path.display()))?,
            "--times-file",
        ),
        (None, None, Some(t_end), Some(n)) => {
            if n > MAX_SAMPLES {
                bail!("--samples: at most {MAX_SAMPLES} samples are supported, got {n}");
            }
            let grid = OutputGrid::new(t_end, n).context("--t-end/--samples")?;
            (grid.times(), "--t-end/--samples")
        }
        _ => bail!("give the times: --times T0,T1,..., --times-file FILE or --t-end T --samples N"),
    };
    rsts_harness::reference::check_times(&times).map_err(|e| anyhow!("{what}: {e}"))?;
    Ok(times)
}

/// Bytes one value takes in the output (digits, sign, point, exponent, separator).
fn bytes_per_value(format: RefFormat, digits: Option<u32>) -> f64 {
    match (format, digits) {
        (RefFormat::Npy, _) => 8.0,
        (_, Some(d)) => f64::from(d) + 12.0,
        (_, None) => 25.0,
    }
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if let (Some(input), Some(output)) = (&args.times_file, &args.output) {
        rsts_io::check_outputs(
            &[("--times-file", input)],
            &[rsts_io::Output::File("-o", output)],
        )?;
    }
    let times = times(&args)?;
    let digits = check_digits(args.digits.map(i64::from)).map_err(|e| anyhow!("--digits: {e}"))?;
    if digits.is_some() && args.format == RefFormat::Npy {
        bail!("--format npy holds float64 values: drop --digits, or use --format csv or json");
    }
    if args.format == RefFormat::Npy && args.output.is_none() && std::io::stdout().is_terminal() {
        bail!("--format npy is binary: write it with -o FILE (or redirect stdout)");
    }
    output::check_output_bytes(
        "--times/--samples/--digits",
        "the reference",
        times.len() as f64 * 13.0 * bytes_per_value(args.format, digits),
    )?;
    let case = args
        .case
        .case(&rsts_closed_form::Decimal::from_integer(0), 1);
    let table = ReferenceTable::new(&case, &times, digits).map_err(case_error)?;
    if let Some(path) = &args.output {
        rsts_io::check_writable(path).with_context(|| format!("-o {}", path.display()))?;
    }
    let pool = args.jobs.pool()?;
    // Rows in batches computed on every core and written in order (memory does not grow with
    // the number of times). f64 rows come from the double-double closed form, correctly rounded.
    let row = |t: f64| table.row(t).map_err(|e| anyhow!(e));
    let row_f64 = |t: f64| table.row_f64(t).map_err(|e| anyhow!(e));
    let text = |x: &Float| table.text(x);
    // One sample of the JSON document.
    let json_sample = |r: Vec<Value>| {
        json!({
            "t": r[0], "omega": r[1..4], "alpha": r[4..7], "beta": r[7..10],
            "H": r[10], "K": r[11], "G": r[12],
        })
    };
    // A row as the bytes of its format (npy: 13 little-endian f64; CSV: a line; JSON: a sample).
    let encode = |&t: &f64| -> anyhow::Result<Vec<u8>> {
        Ok(match (args.format, digits) {
            (RefFormat::Npy, _) => row_f64(t)?.iter().flat_map(|x| x.to_le_bytes()).collect(),
            (RefFormat::Csv, None) => {
                let r: Vec<String> = row_f64(t)?.iter().map(|x| format!("{x:?}")).collect();
                format!("{}\n", r.join(",")).into_bytes()
            }
            (RefFormat::Csv, Some(_)) => {
                let r: Vec<String> = row(t)?.iter().map(text).collect();
                format!("{}\n", r.join(",")).into_bytes()
            }
            (RefFormat::Json, None) => {
                let r = row_f64(t)?.iter().map(|x| json!(x)).collect();
                json_sample(r).to_string().into_bytes()
            }
            (RefFormat::Json, Some(_)) => {
                let r = row(t)?.iter().map(|x| Value::String(text(x))).collect();
                json_sample(r).to_string().into_bytes()
            }
        })
    };
    let write = |w: &mut dyn Write| -> anyhow::Result<()> {
        match args.format {
            RefFormat::Npy => w.write_all(&rsts_external::npy_header(times.len(), 13))?,
            RefFormat::Csv => writeln!(w, "{}", COLUMNS.join(","))?,
            RefFormat::Json => {
                // One document, one sample per line, written as the samples are made.
                let c = &case;
                let head = [
                    ("a", json!(c.motion.a)),
                    ("b", json!(c.motion.b)),
                    ("m", json!(c.motion.m)),
                    ("h", json!(c.motion.h)),
                    ("camera", json!(table.analysis().motion().camera.label())),
                    ("torus", json!(c.motion.torus)),
                    ("phase1", json!(c.motion.phase1)),
                    ("phase2", json!(c.motion.phase2)),
                    ("digits", json!(digits)),
                ];
                writeln!(w, "{{")?;
                for (k, v) in head {
                    writeln!(w, "  {}: {},", json!(k), v)?;
                }
                write!(w, "  \"samples\": [")?;
            }
        }
        let mut k = 0;
        for_each_batch(&pool, &times, encode, |rows| -> anyhow::Result<()> {
            for r in rows {
                let r = r?;
                if args.format == RefFormat::Json {
                    write!(w, "{}\n    ", if k == 0 { "" } else { "," })?;
                }
                w.write_all(&r)?;
                k += 1;
            }
            Ok(())
        })?;
        if args.format == RefFormat::Json {
            writeln!(w, "\n  ]\n}}")?;
        }
        Ok(())
    };
    match &args.output {
        Some(path) => {
            let name = || format!("-o {}", path.display());
            let mut file = rsts_io::AtomicFile::create(path).with_context(name)?;
            {
                let mut w = std::io::BufWriter::new(&mut file);
                // A failed write (disk full) names the file.
                write(&mut w).map_err(|e| {
                    if e.is::<std::io::Error>() {
                        e.context(name())
                    } else {
                        e
                    }
                })?;
                w.flush().with_context(name)?;
            }
            // The file appears only now, whole; an error above removed the temporary.
            file.commit().with_context(name)?;
        }
        None => {
            let mut w = std::io::BufWriter::new(out);
            write(&mut w)?;
            w.flush()?;
        }
    }
    Ok(())
}
