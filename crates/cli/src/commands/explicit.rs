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
use rsts_dynamics::Real;

use rsts_harness::rounded_explicit::RoundedExplicit;

use crate::args::{count, finite_f64, ExactFieldArgs, MAX_SAMPLES};
use crate::output::{self, Cell, Format};

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
/// Most memory the samples of one run may take (2 GiB).
pub const MAX_SAMPLE_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

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

/// A number of the JSON document: an f64 number when the run is in f64, a decimal string at
/// `--digits` (more digits than an f64 number holds).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
enum Number {
    F64(f64),
    Decimal(String),
}

impl Number {
    fn cell(&self, table: bool) -> Cell {
        match self {
            Number::F64(x) => Cell::Num(*x),
            Number::Decimal(s) if table => s.parse().map_or(Cell::Text(s.clone()), Cell::Num),
            Number::Decimal(s) => Cell::Text(s.clone()),
        }
    }
}

#[derive(Debug, Serialize)]
struct Sample {
    t: Number,
    omega: [Number; 3],
    alpha: [Number; 3],
    beta: [Number; 3],
    gamma: [Number; 3],
    #[serde(rename = "Omega")]
    omega_fixed: [Number; 3],
}

/// The samples, kept as 16 numbers each (t, ω, α, β, γ, Ω) and turned into [`Sample`]s one at a
/// time while the JSON is written.
struct Samples<'a, T> {
    rows: &'a [[T; 16]],
    num: &'a dyn Fn(&T) -> Number,
}

impl<T> Serialize for Samples<'_, T> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let f = self.num;
        let v3 = |r: &[T; 16], k: usize| [f(&r[k]), f(&r[k + 1]), f(&r[k + 2])];
        serializer.collect_seq(self.rows.iter().map(|r| Sample {
            t: f(&r[0]),
            omega: v3(r, 1),
            alpha: v3(r, 4),
            beta: v3(r, 7),
            gamma: v3(r, 10),
            omega_fixed: v3(r, 13),
        }))
    }
}

#[derive(Serialize)]
#[serde(bound = "")]
struct Document<'a, T> {
    a: Number,
    b: Number,
    m: Number,
    h: Number,
    camera: String,
    tori: usize,
    torus: usize,
    phase1: f64,
    phase2: f64,
    digits: u32,
    samples: Samples<'a, T>,
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
    let x = T::parse(s, bits)
        .with_context(|| format!("--{name}: '{}' is not a number", rsts_io::cut(s)))?;
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
        ("a", args.fields.a.as_str()),
        ("b", args.fields.b.as_str()),
        ("m", args.m.as_str()),
        ("h", args.h.as_str()),
    ]
    .map(|(name, s)| read::<T>(name, s, bits));
    let t_end: T = read("t-end", &args.t_end, bits)?;
    if t_end < t_end.zero_like() {
        bail!("--t-end: must be non-negative, got {}", args.t_end);
    }
    let t_max = t_end.to_f64();
    if !t_max.is_finite() {
        bail!(
            "--t-end: at most {:e} (the largest f64), got {}",
            f64::MAX,
            args.t_end
        );
    }
    let choice = TorusChoice {
        torus: args.torus,
        phase1: args.phase1,
        phase2: args.phase2,
    };
    // The phase clock carries as many bits as T needs: the state at t = 1e300 is the motion's.
    let motion = ExplicitMotion::new_until(a?, b?, m?, h?, choice, t_max)
        .map_err(crate::args::case_error)?;
    let n = args.samples;
    // Memory: the 16 numbers of every sample are kept (f64: 8 bytes each; MPFR: its limbs and
    // ~48 bytes of bookkeeping); the output is made from them row by row.
    let per_number = if bits > F64_BITS {
        48.0 + 8.0 * f64::from(bits.div_ceil(64))
    } else {
        8.0
    };
    let bytes = n as f64 * 16.0 * per_number;
    if bytes > MAX_SAMPLE_BYTES {
        bail!(
            "--samples/--digits: {n} samples at {digits} digits need about {} bytes of memory, more than {}; ask for fewer samples or digits",
            rsts_dynamics::short(bytes),
            rsts_dynamics::short(MAX_SAMPLE_BYTES)
        );
    }
    let mp = digits > 17 || bits > F64_BITS;
    // f64 output: the double-double closed form correctly rounded (MPFR where Ziv's test cannot
    // decide), the same bits as the MPFR rows rounded (rsts_harness::rounded_explicit).
    let rounded = if mp {
        None
    } else {
        let c = &motion.constants;
        let case = rsts_harness::Case::binary(
            [c.a.to_f64(), c.b.to_f64(), c.m.to_f64(), c.h.to_f64()],
            args.torus,
            [args.phase1, args.phase2],
            t_max,
            1,
        )
        .unwrap();
        Some(RoundedExplicit::new(&case, t_max).map_err(crate::args::case_error)?)
    };
    // t_k = T·k/(N−1), computed with guard bits and rounded once (T·k may overflow f64).
    let wide = bits.max(F64_BITS) + 64;
    let t_big = t_end.to_mpfr(wide);
    let mut rows: Vec<[T; 16]> = Vec::with_capacity(n);
    for k in 0..n {
        let t: T = if n == 1 {
            t_end.zero_like()
        } else if k + 1 == n {
            t_end.clone()
        } else {
            T::from_mpfr(
                &(Float::with_val(wide, &t_big * k as u64) / (n - 1) as u64),
                bits,
            )
        };
        let values: [T; 15] = match &rounded {
            Some(r) => r.row(t.to_f64()).map(|x| T::from_f64(x, bits)),
            None => {
                let s = motion.at(&t);
                let vs = [&s.omega, &s.alpha, &s.beta, &s.gamma, &s.omega_fixed];
                std::array::from_fn(|j| vs[j / 3][j % 3].clone())
            }
        };
        if values.iter().any(|v| !v.is_finite()) {
            bail!(
                "the closed form is not finite at t = {} (sample {k} of {n})",
                rsts_dynamics::short(t.to_f64())
            );
        }
        rows.push(std::array::from_fn(|j| {
            if j == 0 {
                t.clone()
            } else {
                values[j - 1].clone()
            }
        }));
    }
    let num = |x: &T| {
        if mp {
            Number::Decimal(x.to_decimal(digits))
        } else {
            Number::F64(x.to_f64())
        }
    };
    let c = &motion.constants;
    let doc = Document {
        a: num(&c.a),
        b: num(&c.b),
        m: num(&c.m),
        h: num(&c.h),
        camera: motion.camera.label().to_string(),
        tori: motion.tori,
        torus: args.torus,
        phase1: args.phase1,
        phase2: args.phase2,
        digits,
        samples: Samples {
            rows: &rows,
            num: &num,
        },
    };
    let text = |x: &T| x.to_decimal(digits);
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv | Format::Table => {
            let mut header = vec!["t".to_string()];
            for name in ["omega", "alpha", "beta", "gamma", "Omega"] {
                header.extend((1..=3).map(|i| format!("{name}{i}")));
            }
            let as_table = args.format == Format::Table && digits <= 17;
            let cells = || {
                rows.iter()
                    .map(|r| r.iter().map(|x| num(x).cell(as_table)).collect::<Vec<_>>())
            };
            if args.format == Format::Csv {
                output::write_csv_rows(out, &header, cells())?;
            } else {
                let [p1, p2] = motion.periods().map(|p| p.to_f64());
                output::write_key_values(
                    out,
                    &[
                        ("camera", doc.camera.clone()),
                        ("torus", format!("{} of {}", args.torus, motion.tori)),
                        (
                            "a, b",
                            format!("{}, {}", short(&text(&c.a)), short(&text(&c.b))),
                        ),
                        (
                            "m, h",
                            format!("{}, {}", short(&text(&c.m)), short(&text(&c.h))),
                        ),
                        ("periods", format!("{p1:.10}, {p2:.10}")),
                        (
                            "rotation number",
                            format!("{:.12}", motion.rotation_number().to_f64()),
                        ),
                        ("digits", digits.to_string()),
                    ],
                )?;
                writeln!(out)?;
                output::write_table_rows(out, &header, cells)?;
            }
        }
    }
    Ok(())
}
