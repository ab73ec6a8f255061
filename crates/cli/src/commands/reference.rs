//! `rsts reference`: the exact motion on N at times the user chooses (a list, a file, or an even
//! grid), with H, K, G per row, as CSV, JSON or npy — to start and check an integrator written
//! elsewhere (docs/own-integrator.md).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;

use anyhow::{anyhow, bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use rug::Float;
use serde_json::{json, Value};

use rsts_dynamics::integrals;
use rsts_dynamics::integrators::OutputGrid;
use rsts_dynamics::scalar::bits_for_digits;
use rsts_harness::{Analysis, RunInfo, REFERENCE_GUARD_BITS};

use crate::args::{count, finite_f64, CaseArgs, MAX_SAMPLES};
use crate::output::{self, Cell, Tabular};

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
The state at the first time starts an integrator; `rsts check` compares its trajectory with
this motion.";

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
}

/// Read a times file: numbers separated by whitespace, commas or newlines; `#` starts a comment.
fn read_times_file(path: &PathBuf) -> anyhow::Result<Vec<f64>> {
    let name = path.display();
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("--times-file {name}: cannot read"))?;
    let mut times = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for word in line
            .split([',', ' ', '\t'])
            .filter(|w| !w.trim().is_empty())
        {
            let t = finite_f64(word)
                .map_err(|e| anyhow!("--times-file {name}: line {}: {e}", k + 1))?;
            times.push(t);
        }
    }
    Ok(times)
}

/// The requested times, checked.
fn times(args: &Args) -> anyhow::Result<Vec<f64>> {
    let (times, what) = match (&args.times, &args.times_file, args.t_end, args.samples) {
        (Some(t), _, _, _) => (t.clone(), "--times"),
        (None, Some(path), _, _) => (read_times_file(path)?, "--times-file"),
        (None, None, Some(t_end), Some(n)) => {
            if n > MAX_SAMPLES {
                bail!("--samples: at most {MAX_SAMPLES} samples are supported, got {n}");
            }
            let grid = OutputGrid::new(t_end, n).context("--t-end/--samples")?;
            (grid.times(), "--t-end/--samples")
        }
        _ => bail!("give the times: --times T0,T1,..., --times-file FILE or --t-end T --samples N"),
    };
    if times.is_empty() {
        bail!("{what}: no times");
    }
    if times.len() > MAX_SAMPLES {
        bail!(
            "{what}: at most {MAX_SAMPLES} times are supported, got {}",
            times.len()
        );
    }
    for (k, w) in times.windows(2).enumerate() {
        if w[1] <= w[0] {
            bail!(
                "{what}: times must be strictly increasing: time {} ({}) does not come after {}",
                k + 2,
                w[1],
                w[0]
            );
        }
    }
    Ok(times)
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let times = times(&args)?;
    let digits = match args.digits {
        None => None,
        Some(d) if (18..=10_000).contains(&d) => Some(d),
        Some(d) => bail!("--digits: must be between 18 and 10000 (without it: f64), got {d}"),
    };
    if digits.is_some() && args.format == RefFormat::Npy {
        bail!("--format npy holds float64 values: drop --digits, or use --format csv or json");
    }
    if args.format == RefFormat::Npy && args.output.is_none() && std::io::stdout().is_terminal() {
        bail!("--format npy is binary: write it with -o FILE (or redirect stdout)");
    }
    if let Some(path) = &args.output {
        rsts_io::check_writable(path).with_context(|| format!("-o {}", path.display()))?;
    }
    let bits = bits_for_digits(digits.unwrap_or(30)) + REFERENCE_GUARD_BITS;
    let case = args.case.case(0.0, 1);
    let info = RunInfo {
        method: "reference".into(),
        rtol: None,
        atol: None,
        digits: digits.unwrap_or(15),
    };
    let analysis = Analysis::for_case(&case, bits, info).map_err(|e| anyhow!("{e}"))?;
    // One row: t and the nine components, then H, K, G, at the reference precision.
    let rows: Vec<Vec<Float>> = times
        .iter()
        .map(|&t| {
            let t = Float::with_val(bits, t);
            let s = analysis.exact_state(&t);
            let i = integrals(analysis.fields(), &s);
            let mut row = vec![t];
            row.extend(s.to_array());
            row.extend([i.h, i.k, i.g]);
            row
        })
        .collect();
    let text = |x: &Float| match digits {
        Some(d) => x.to_string_radix(10, Some(d as usize)),
        None => format!("{:?}", x.to_f64()),
    };
    let bytes: Vec<u8> = match args.format {
        RefFormat::Npy => {
            let plain: Vec<Vec<f64>> = rows
                .iter()
                .map(|r| r.iter().map(Float::to_f64).collect())
                .collect();
            rsts_external::npy_bytes(&plain, 13)
        }
        RefFormat::Csv => {
            let mut header: Vec<&str> = rsts_external::COLUMNS.to_vec();
            header.extend(["H", "K", "G"]);
            let mut table = Tabular::new(header);
            for r in &rows {
                table.push(r.iter().map(|x| Cell::Text(text(x))).collect());
            }
            let mut buf = Vec::new();
            output::write_csv(&mut buf, &table)?;
            buf
        }
        RefFormat::Json => {
            let value = |x: &Float| -> Value {
                match digits {
                    Some(_) => Value::String(text(x)),
                    None => json!(x.to_f64()),
                }
            };
            let v3 = |r: &[Float]| r.iter().map(value).collect::<Vec<_>>();
            let samples: Vec<Value> = rows
                .iter()
                .map(|r| {
                    json!({
                        "t": value(&r[0]), "omega": v3(&r[1..4]), "alpha": v3(&r[4..7]),
                        "beta": v3(&r[7..10]), "H": value(&r[10]), "K": value(&r[11]), "G": value(&r[12]),
                    })
                })
                .collect();
            let c = &case;
            let doc = json!({
                "a": c.a, "b": c.b, "m": c.m, "h": c.h,
                "camera": analysis.motion().camera.label(),
                "torus": c.torus, "phase1": c.phase1, "phase2": c.phase2,
                "digits": digits,
                "samples": samples,
            });
            let mut buf = Vec::new();
            output::write_json(&mut buf, &doc)?;
            buf
        }
    };
    match &args.output {
        Some(path) => {
            rsts_io::write_atomic(path, &bytes).with_context(|| format!("-o {}", path.display()))?
        }
        None => out.write_all(&bytes)?,
    }
    Ok(())
}
