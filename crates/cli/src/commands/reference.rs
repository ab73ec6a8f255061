//! `rsts reference`: the exact motion on N at times the user chooses (a list, a file, or an even
//! grid), with H, K, G per row, as CSV, JSON or npy — to start and check an integrator written
//! elsewhere (docs/own-integrator.md). Parsing and formatting only: the flow is
//! `rsts_flows::reference`, whose rows are written here as they come.

use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use serde_json::{json, Value};

use rsts_flows::reference::{reference, ReferenceHead, ReferenceRequest, ReferenceRow};
use rsts_flows::{times, Decimal, FlowError, Sink, Times};
use rsts_harness::reference::{check_digits, COLUMNS};

use crate::args::{count, decimal, flow_error, CaseArgs};
use crate::jobs::JobsArgs;
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

Columns: t, omega1..3, alpha1..3, beta1..3 (the state in the body frame), H, K, G. Every time is
exact (a decimal as written, a grid time k*T/(N-1)); without --digits the closed form is evaluated
at 30 digits + 64 bits and rounded to f64 (17 significant digits, read back exactly; a time that
is not an f64, such as 0.1, shows the f64 nearest it, docs/numbers.md); with --digits D every
value carries D digits (CSV and JSON only). The f64 values come from the closed form in
double-double, each checked to round to the same f64 as the MPFR value (else that row is
computed in MPFR): the same bits, faster. Rows are computed on --jobs threads (default: every
core) and written in order. The state at the first time starts an integrator; `rsts check`
compares its trajectory with this motion.";

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
    #[arg(long, value_name = "T0,T1,...", value_delimiter = ',', value_parser = decimal, allow_hyphen_values = true,
          conflicts_with_all = ["times_file", "t_end", "samples"])]
    pub times: Option<Vec<Decimal>>,
    /// Sample times from a file: numbers separated by newlines, commas or spaces ('#' comments)
    #[arg(long, value_name = "FILE", conflicts_with_all = ["t_end", "samples"])]
    pub times_file: Option<PathBuf>,
    /// End time T of N evenly spaced times on [0, T] (with --samples)
    #[arg(long, value_name = "T", value_parser = decimal, allow_hyphen_values = true, requires = "samples")]
    pub t_end: Option<Decimal>,
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
fn times(args: &Args) -> anyhow::Result<Times> {
    let (times, what) = match (&args.times, &args.times_file, &args.t_end, args.samples) {
        (Some(t), _, _, _) => (Times::Decimals(t.clone()), "--times".to_string()),
        (None, Some(path), _, _) => {
            let name = format!("--times-file {}", path.display());
            let t = times::read_times_file(path).map_err(|e| anyhow!("{name}: {e}"))?;
            (Times::Decimals(t), "--times-file".to_string())
        }
        (None, None, Some(t_end), Some(n)) => (
            Times::grid(t_end.clone(), n),
            "--t-end/--samples".to_string(),
        ),
        _ => bail!("give the times: --times T0,T1,..., --times-file FILE or --t-end T --samples N"),
    };
    times::check(&times).map_err(|e| anyhow!("{what}: {e}"))?;
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

/// A row as the bytes of its format (npy: 13 little-endian f64; CSV: a line; JSON: a sample).
fn encode(format: RefFormat, row: ReferenceRow) -> Vec<u8> {
    let sample = |r: Vec<Value>| {
        json!({
            "t": r[0], "omega": r[1..4], "alpha": r[4..7], "beta": r[7..10],
            "H": r[10], "K": r[11], "G": r[12],
        })
        .to_string()
        .into_bytes()
    };
    match (format, row) {
        (RefFormat::Npy, ReferenceRow::F64(r)) => r.iter().flat_map(|x| x.to_le_bytes()).collect(),
        (RefFormat::Csv, ReferenceRow::F64(r)) => {
            let r: Vec<String> = r.iter().map(|x| format!("{x:?}")).collect();
            format!("{}\n", r.join(",")).into_bytes()
        }
        (RefFormat::Csv, ReferenceRow::Decimal(r)) => format!("{}\n", r.join(",")).into_bytes(),
        (RefFormat::Json, ReferenceRow::F64(r)) => sample(r.iter().map(|x| json!(x)).collect()),
        (_, ReferenceRow::Decimal(r)) => sample(r.into_iter().map(Value::String).collect()),
    }
}

/// Where the rows go: stdout, or a file that appears whole when all is written.
enum Target<'a> {
    Closed,
    Stdout(BufWriter<&'a mut dyn Write>),
    File(BufWriter<rsts_io::AtomicFile>, &'a Path),
}

/// The sink of `rsts reference`: the head in the format's form, then the rows' bytes.
struct Output<'a> {
    format: RefFormat,
    path: Option<&'a Path>,
    stdout: Option<&'a mut dyn Write>,
    target: Target<'a>,
    rows: usize,
}

impl Output<'_> {
    fn out(&mut self) -> &mut dyn Write {
        match &mut self.target {
            Target::Stdout(w) => w,
            Target::File(w, _) => w,
            Target::Closed => unreachable!("written after the head"),
        }
    }

    /// A failed write (disk full) names the file.
    fn named(&self, e: std::io::Error) -> anyhow::Error {
        match &self.target {
            Target::File(_, path) => {
                anyhow::Error::from(e).context(format!("-o {}", path.display()))
            }
            _ => e.into(),
        }
    }

    fn put(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        self.out().write_all(bytes).map_err(|e| self.named(e))
    }

    /// Close the document; a file appears only now, whole.
    fn finish(self) -> anyhow::Result<()> {
        let json = self.format == RefFormat::Json;
        match self.target {
            Target::Stdout(mut w) => {
                if json {
                    writeln!(w, "\n  ]\n}}")?;
                }
                w.flush()?;
            }
            Target::File(mut w, path) => {
                let name = || format!("-o {}", path.display());
                if json {
                    writeln!(w, "\n  ]\n}}").with_context(name)?;
                }
                let file = w
                    .into_inner()
                    .map_err(|e| e.into_error())
                    .with_context(name)?;
                file.commit().with_context(name)?;
            }
            Target::Closed => {}
        }
        Ok(())
    }
}

impl Sink<ReferenceHead, Vec<u8>> for Output<'_> {
    type Error = anyhow::Error;

    fn head(&mut self, head: &ReferenceHead) -> anyhow::Result<()> {
        self.target = match self.path {
            Some(path) => {
                let name = || format!("-o {}", path.display());
                rsts_io::check_writable(path).with_context(name)?;
                let file = rsts_io::AtomicFile::create(path).with_context(name)?;
                Target::File(BufWriter::new(file), path)
            }
            None => Target::Stdout(BufWriter::new(self.stdout.take().expect("stdout"))),
        };
        match self.format {
            RefFormat::Npy => self.put(&rsts_external::npy_header(head.rows, 13)),
            RefFormat::Csv => self.put(format!("{}\n", COLUMNS.join(",")).as_bytes()),
            RefFormat::Json => {
                // One document, one sample per line, written as the samples are made.
                let fields = [
                    ("a", json!(head.a)),
                    ("b", json!(head.b)),
                    ("m", json!(head.m)),
                    ("h", json!(head.h)),
                    ("camera", json!(head.camera)),
                    ("torus", json!(head.torus)),
                    ("phase1", json!(head.phase1)),
                    ("phase2", json!(head.phase2)),
                    ("digits", json!(head.digits)),
                ];
                let mut text = "{\n".to_string();
                for (k, v) in fields {
                    text += &format!("  {}: {},\n", json!(k), v);
                }
                text += "  \"samples\": [";
                self.put(text.as_bytes())
            }
        }
    }

    fn row(&mut self, row: Vec<u8>) -> anyhow::Result<()> {
        if self.format == RefFormat::Json {
            let sep = if self.rows == 0 { "\n    " } else { ",\n    " };
            self.put(sep.as_bytes())?;
        }
        self.rows += 1;
        self.put(&row)
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
    let request = ReferenceRequest {
        motion: args.case.motion(),
        times,
        digits,
        jobs: args.jobs.jobs,
    };
    let mut sink = Output {
        format: args.format,
        path: args.output.as_deref(),
        stdout: Some(out),
        target: Target::Closed,
        rows: 0,
    };
    let format = args.format;
    reference(&request, |row| encode(format, row), &mut sink).map_err(|e| {
        match e.downcast::<FlowError>() {
            Ok(f) => flow_error(f),
            Err(e) => e,
        }
    })?;
    sink.finish()
}
