//! `rsts identify`: which motion of N a state (ω, α, β) is on — (m, h), camera, torus and the
//! angles (ψ₁, ψ₂) on the torus, the inverse of `rsts explicit` — with the distance from N and
//! the residual |state − closed form(found)|, in f64 or at any number of digits.

use std::io::Write;

use anyhow::{bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use rug::Float;

use rsts_closed_form::diagram::tori_text;
use rsts_closed_form::scalar::Scalar;
use rsts_dynamics::scalar::{bits_for_digits, F64_BITS};
use rsts_dynamics::{Real, State};
use rsts_harness::identify::{identify_state, Identification};

use crate::args::ExactFieldArgs;
use crate::commands::explicit::MAX_DIGITS;
use crate::output;

/// Shown at the end of `rsts identify --help`.
pub const EXAMPLES: &str = "\
Examples:
  # a state of camera V to 10 digits (from `rsts explicit --m -0.7092 --h 1.5643 --torus 3
  # --phase1 0.5 --phase2 1`): m, h, the camera, the torus, the phases, the distance from N
  rsts identify --a 1 --b 0.5 --omega=-0.7647920880,0.0304544152,-0.0788113714 \\
      --alpha=-0.8092123863,0.4893823915,0.3250848946 --beta=0.1716166194,-0.3322951766,0.9274306721

  # a state off N: exit 1, and as JSON {\"on_N\": false, \"distance_from_N\": ...}
  # exit: 1
  rsts identify --omega 0.3,-0.2,0.5 --alpha 1,0,0 --beta 0,1,0 --format json

  # the same state at 30 digits (from `rsts explicit ... --digits 30`)
  rsts identify --digits 30 --tolerance 1e-25 \\
      --omega=-7.64792087987212188017224701883e-1,3.04544151786620162541079171943e-2,-7.88113713395717940203271906572e-2 \\
      --alpha=-8.09212386305527351781694531683e-1,4.89382391526321213666026249350e-1,3.25084894625530732343862694659e-1 \\
      --beta=1.71616619355052754140384229090e-1,-3.32295176633093360935866638703e-1,9.27430672097663705695264893261e-1

The phases are the angles (psi1, psi2) on the torus at which `rsts explicit --m M --h H --torus K
--phase1 PSI1 --phase2 PSI2` starts at the state. The distance from N is |X_Phi|/gain
(Phi = r^4 K - (2G - p^2 H)^2, in the units of the state; see docs/stability.md); the state is on
N when distance/|state| <= --tolerance. m and h are those of the nearest point of N (the values of
H and (2G - p^2 H)/r^4 for a state on N).";

/// Output formats of `rsts identify`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IdentifyFormat {
    /// Aligned key: value lines
    Table,
    /// One JSON document
    Json,
}

/// Options of `rsts identify`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: ExactFieldArgs,
    /// Angular velocity ω in the body frame
    #[arg(long, value_name = "W1,W2,W3", allow_hyphen_values = true)]
    pub omega: String,
    /// Direction α of the first field in the body frame; |α| = 1
    #[arg(long, value_name = "A1,A2,A3", allow_hyphen_values = true)]
    pub alpha: String,
    /// Direction β of the second field in the body frame; |β| = 1, α·β = 0
    #[arg(long, value_name = "B1,B2,B3", allow_hyphen_values = true)]
    pub beta: String,
    /// Decimal digits of the computation and of the output (16 to 100000); default: f64
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Largest relative distance from N (distance/|state|) of a state on N
    #[arg(long, value_name = "TOL", default_value = "1e-9", value_parser = crate::args::finite_f64, allow_hyphen_values = true)]
    pub tolerance: f64,
    /// Output format
    #[arg(long, value_enum, default_value_t = IdentifyFormat::Table)]
    pub format: IdentifyFormat,
}

/// A state that is not on N (exit code 1).
#[derive(Debug)]
pub struct NotOnN(pub String);

impl std::fmt::Display for NotOnN {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for NotOnN {}

/// Read a decimal at `bits`, naming the option on failure.
fn read<T: Real>(name: &str, s: &str, bits: u32) -> anyhow::Result<T> {
    let x = T::parse(s, bits)
        .with_context(|| format!("--{name}: '{}' is not a number", rsts_io::cut(s)))?;
    if !x.is_finite() {
        bail!("--{name}: must be a finite number, got {s}");
    }
    Ok(x)
}

/// Three comma-separated decimals.
fn read3<T: Real>(name: &str, s: &str, bits: u32) -> anyhow::Result<[T; 3]> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        bail!(
            "--{name}: expected exactly 3 comma-separated components, got {}",
            parts.len()
        );
    }
    let [x, y, z] = [parts[0], parts[1], parts[2]].map(|p| read::<T>(name, p.trim(), bits));
    Ok([x?, y?, z?])
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
    let a: T = read("a", args.fields.a.as_str(), bits)?;
    let b: T = read("b", args.fields.b.as_str(), bits)?;
    let state = State {
        omega: read3("omega", &args.omega, bits)?,
        alpha: read3("alpha", &args.alpha, bits)?,
        beta: read3("beta", &args.beta, bits)?,
    };
    let (doc, id) = match identify_state(&a, &b, &state, args.tolerance, digits) {
        Err(e) if e.parameters.is_empty() => bail!("{}", e.message),
        Err(e) => bail!("--{}: {}", e.parameters.join("/--"), e.message),
        Ok(Identification::OffN(off)) => {
            match args.format {
                IdentifyFormat::Json => output::write_json(out, &off)?,
                IdentifyFormat::Table => output::write_key_values(
                    out,
                    &[
                        ("on N", "no".to_string()),
                        ("distance from N", format!("{:.6e}", off.distance_from_n)),
                        (
                            "relative distance",
                            format!("{:.6e}", off.relative_distance_from_n),
                        ),
                        ("tolerance", format!("{:e}", args.tolerance)),
                    ],
                )?,
            }
            return Err(NotOnN(off.message()).into());
        }
        Ok(Identification::OnN(doc, id)) => (doc, id),
    };
    let relative = doc.relative_distance_from_n;
    // Shortest f64 text in f64, all digits otherwise.
    let text = |x: &T| {
        if digits <= 17 {
            x.to_f64().to_string()
        } else {
            x.to_decimal(digits)
        }
    };
    match args.format {
        IdentifyFormat::Json => output::write_json(out, &doc)?,
        IdentifyFormat::Table => output::write_key_values(
            out,
            &[
                ("camera", format!("{} ({})", doc.camera, tori_text(id.tori))),
                ("torus", id.torus.to_string()),
                ("m", text(&id.m)),
                ("h", text(&id.h)),
                ("phase1", text(&id.phases[0])),
                ("phase2", text(&id.phases[1])),
                (
                    "distance from N",
                    format!(
                        "{:.3e} (relative {relative:.3e}, tolerance {:e})",
                        doc.distance_from_n, args.tolerance
                    ),
                ),
                ("residual", format!("{:.3e}", doc.residual)),
                (
                    "normal type",
                    format!(
                        "{} (λ² = −4r⁴mℓ² = {:.6e})",
                        doc.normal.kind, doc.normal.lambda2
                    ),
                ),
                ("digits", digits.to_string()),
            ],
        )?,
    }
    Ok(())
}
