//! `rsts identify`: which motion of N a state (ω, α, β) is on — (m, h), camera, torus and the
//! angles (ψ₁, ψ₂) on the torus, the inverse of `rsts explicit` — with the distance from N and
//! the residual |state − closed form(found)|, in f64 or at any number of digits. Parsing and
//! formatting only: the flow is `rsts_flows::identify`.

use std::io::Write;

use anyhow::bail;
use clap::{Args as ClapArgs, ValueEnum};
use serde_json::Value;

use rsts_closed_form::diagram::tori_text;
use rsts_flows::identify::{identify, IdentifyOutcome, IdentifyRequest};
use rsts_flows::Decimal;

use crate::args::{flow_error, ExactFieldArgs};
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
H and (2G - p^2 H)/r^4 for a state on N). The state's numbers are the decimals as written; the
computation carries the digits asked (f64: 17) and 64 guard bits.";

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

/// Three comma-separated decimals.
fn read3(name: &str, s: &str) -> anyhow::Result<[Decimal; 3]> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        bail!(
            "--{name}: expected exactly 3 comma-separated components, got {}",
            parts.len()
        );
    }
    let read = |p: &str| Decimal::parse(p).map_err(|e| anyhow::anyhow!("--{name}: {e}"));
    Ok([read(parts[0])?, read(parts[1])?, read(parts[2])?])
}

/// A number of the document as the table shows it: an f64 shortest, a decimal as written.
fn text(x: &Value) -> String {
    match x {
        Value::String(s) => s.clone(),
        other => other.as_f64().map_or(other.to_string(), |v| v.to_string()),
    }
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    let [w, a, b] = [
        read3("omega", &args.omega)?,
        read3("alpha", &args.alpha)?,
        read3("beta", &args.beta)?,
    ];
    let request = IdentifyRequest {
        a: args.fields.a.clone(),
        b: args.fields.b.clone(),
        state: [w, a, b].concat().try_into().expect("nine numbers"),
        tolerance: args.tolerance,
        digits: args.digits,
    };
    let doc = match identify(&request).map_err(flow_error)? {
        IdentifyOutcome::OffN(off) => {
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
        IdentifyOutcome::OnN(doc) => doc,
    };
    match args.format {
        IdentifyFormat::Json => output::write_json(out, &doc)?,
        IdentifyFormat::Table => output::write_key_values(
            out,
            &[
                (
                    "camera",
                    format!("{} ({})", doc.camera, tori_text(doc.tori)),
                ),
                ("torus", doc.torus.to_string()),
                ("m", text(&doc.m)),
                ("h", text(&doc.h)),
                ("phase1", text(&doc.phase1)),
                ("phase2", text(&doc.phase2)),
                (
                    "distance from N",
                    format!(
                        "{:.3e} (relative {:.3e}, tolerance {:e})",
                        doc.distance_from_n, doc.relative_distance_from_n, args.tolerance
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
                ("digits", doc.digits.to_string()),
            ],
        )?,
    }
    Ok(())
}
