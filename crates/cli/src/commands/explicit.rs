//! `rsts explicit`: the closed-form motion on the invariant manifold N (seed sec. 1–3) at N times
//! evenly spaced on [0, T], in f64 or at any number of decimal digits.

use std::io::Write;

use anyhow::{bail, Context};
use clap::Args as ClapArgs;
use rug::Float;
use serde::Serialize;

use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::{bits_for_digits, F64_BITS};
use rsts_dynamics::vec3::Vec3;
use rsts_dynamics::Real;

use crate::args::{count, finite_f64, ExactFieldArgs, MAX_SAMPLES};
use crate::output::{self, Cell, Format, Tabular};

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
`rsts diagram --m M --h H` shows the camera, the tori and the segments of a point.";

/// Largest number of digits accepted.
pub const MAX_DIGITS: u32 = 100_000;

/// Options of `rsts explicit`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: ExactFieldArgs,
    /// Value m of the partial integral M of N
    #[arg(
        long,
        value_name = "M",
        default_value = "0.3",
        allow_hyphen_values = true
    )]
    pub m: String,
    /// Energy h
    #[arg(
        long,
        value_name = "H",
        default_value = "-0.375",
        allow_hyphen_values = true
    )]
    pub h: String,
    /// Which Liouville torus of the integral manifold (0-based)
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub torus: usize,
    /// Initial angle psi1 on the torus (radians)
    #[arg(long, value_name = "X", default_value = "0", value_parser = finite_f64, allow_hyphen_values = true)]
    pub phase1: f64,
    /// Initial angle psi2 on the torus (radians)
    #[arg(long, value_name = "Y", default_value = "0", value_parser = finite_f64, allow_hyphen_values = true)]
    pub phase2: f64,
    /// End time T >= 0
    #[arg(
        long,
        value_name = "T",
        default_value = "10",
        allow_hyphen_values = true
    )]
    pub t_end: String,
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

#[derive(Debug, Serialize)]
struct Sample {
    t: String,
    omega: [String; 3],
    alpha: [String; 3],
    beta: [String; 3],
    gamma: [String; 3],
    #[serde(rename = "Omega")]
    omega_fixed: [String; 3],
}

#[derive(Debug, Serialize)]
struct Document {
    a: String,
    b: String,
    m: String,
    h: String,
    camera: String,
    tori: usize,
    torus: usize,
    phase1: f64,
    phase2: f64,
    digits: u32,
    samples: Vec<Sample>,
}

/// A decimal string shortened for the table header (`1e0` → `1`).
fn short(s: &str) -> String {
    match s.parse::<f64>() {
        Ok(x) if s.len() <= 24 => format!("{x}"),
        _ => s.to_string(),
    }
}

/// Read a decimal at `bits`, naming the option on failure.
fn read<T: Real>(name: &str, s: &str, bits: u32) -> anyhow::Result<T> {
    let x = T::parse(s, bits).with_context(|| format!("--{name}: '{s}' is not a number"))?;
    if !x.is_finite() {
        bail!("--{name}: must be a finite number, got {s}");
    }
    Ok(x)
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    match args.digits {
        None => run_in::<f64>(&args, F64_BITS, 17, out),
        Some(d) if (16..=MAX_DIGITS).contains(&d) => {
            run_in::<Float>(&args, bits_for_digits(d), d, out)
        }
        Some(d) => bail!("--digits: must be between 16 and {MAX_DIGITS}, got {d}"),
    }
}

fn run_in<T: Scalar>(
    args: &Args,
    bits: u32,
    digits: u32,
    out: &mut dyn Write,
) -> anyhow::Result<()> {
    if args.samples == 0 {
        bail!("--samples: need at least 1 sample");
    }
    if args.samples > MAX_SAMPLES {
        bail!(
            "--samples: at most {MAX_SAMPLES} samples are supported, got {}",
            args.samples
        );
    }
    let [a, b, m, h] = [
        ("a", &args.fields.a),
        ("b", &args.fields.b),
        ("m", &args.m),
        ("h", &args.h),
    ]
    .map(|(name, s)| read::<T>(name, s, bits));
    let t_end: T = read("t-end", &args.t_end, bits)?;
    if t_end < t_end.zero_like() {
        bail!("--t-end: must be non-negative, got {}", args.t_end);
    }
    let choice = TorusChoice {
        torus: args.torus,
        phase1: args.phase1,
        phase2: args.phase2,
    };
    let motion = ExplicitMotion::new(a?, b?, m?, h?, choice)?;
    let n = args.samples;
    let text = |x: &T| x.to_decimal(digits);
    let v3 = |v: &Vec3<T>| [text(&v[0]), text(&v[1]), text(&v[2])];
    let mut samples = Vec::with_capacity(n);
    for k in 0..n {
        let t = if n == 1 {
            t_end.zero_like()
        } else {
            t_end.clone() * t_end.lit(k as f64) / t_end.lit((n - 1) as f64)
        };
        let s = motion.at(&t);
        samples.push(Sample {
            t: text(&t),
            omega: v3(&s.omega),
            alpha: v3(&s.alpha),
            beta: v3(&s.beta),
            gamma: v3(&s.gamma),
            omega_fixed: v3(&s.omega_fixed),
        });
    }
    let c = &motion.constants;
    let doc = Document {
        a: text(&c.a),
        b: text(&c.b),
        m: text(&c.m),
        h: text(&c.h),
        camera: motion.camera.label().to_string(),
        tori: motion.tori,
        torus: args.torus,
        phase1: args.phase1,
        phase2: args.phase2,
        digits,
        samples,
    };
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv | Format::Table => {
            let mut header = vec!["t".to_string()];
            for (name, n) in [
                ("omega", 3),
                ("alpha", 3),
                ("beta", 3),
                ("gamma", 3),
                ("Omega", 3),
            ] {
                header.extend((1..=n).map(|i| format!("{name}{i}")));
            }
            let mut table = Tabular::new(header);
            for s in &doc.samples {
                let mut row = vec![s.t.clone()];
                for v in [&s.omega, &s.alpha, &s.beta, &s.gamma, &s.omega_fixed] {
                    row.extend(v.iter().cloned());
                }
                let cells = if args.format == Format::Table && digits <= 17 {
                    row.iter()
                        .map(|x| Cell::Num(x.parse().unwrap_or(f64::NAN)))
                        .collect()
                } else {
                    row.into_iter().map(Cell::Text).collect()
                };
                table.push(cells);
            }
            if args.format == Format::Csv {
                output::write_csv(out, &table)?;
            } else {
                let [p1, p2] = motion.periods().map(|p| p.to_f64());
                output::write_key_values(
                    out,
                    &[
                        ("camera", doc.camera.clone()),
                        ("torus", format!("{} of {}", args.torus, motion.tori)),
                        ("a, b", format!("{}, {}", short(&doc.a), short(&doc.b))),
                        ("m, h", format!("{}, {}", short(&doc.m), short(&doc.h))),
                        ("periods", format!("{p1:.10}, {p2:.10}")),
                        (
                            "rotation number",
                            format!("{:.12}", motion.rotation_number().to_f64()),
                        ),
                        ("digits", digits.to_string()),
                    ],
                )?;
                writeln!(out)?;
                output::write_table(out, &table)?;
            }
        }
    }
    Ok(())
}
