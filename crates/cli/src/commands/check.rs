//! `rsts check FILE`: a trajectory computed elsewhere (CSV, JSON, npy, or the integrated channel
//! of an rsts MCAP log) against the closed-form motion on N — given by (m, h, torus, phases) or
//! identified from the first row — with the report of `rsts compare`.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::Ordering;

use anyhow::{anyhow, bail, Context};
use clap::Args as ClapArgs;
use rug::Float;
use serde::Serialize;

use rsts_closed_form::manifold::{identify, IdentifyError};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_harness::{Analysis, Case, Report, RunInfo, REFERENCE_GUARD_BITS};

use crate::args::{case_error, finite_f64, FieldArgs};
use crate::commands::compare::{
    check_finite_report, open_log, stop_on_ctrl_c, write_table, CliObserver, Interrupted,
};
use crate::commands::validate::Failed;
use crate::output::{self, Format};

/// Shown at the end of `rsts check --help`.
pub const EXAMPLES: &str = "\
Examples:
  # a trajectory written by rsts integrate from the start of camera V's third torus
  # (rsts reference --m -0.7092 --h 1.5643 --torus 2 --times 0 prints that state)
  mkdir -p out
  rsts integrate --omega=-1.0788400339538464,-0.3702277283006931,0 \\
      --alpha=-0.5266712206715436,-0.8500690709091504,0 --beta=-0.8500690709091504,0.5266712206715436,0 \\
      --t-end 20 --samples 201 --method dopri5 --rtol 1e-9 --atol 1e-9 --format csv > out/traj.csv
  rsts check out/traj.csv

  # the motion given: camera V, third torus; fail (exit 1) above an error of 1e-6
  rsts check out/traj.csv --m -0.7092 --h 1.5643 --torus 2 --max-error 1e-6 --format json

  # log the comparison for a viewer
  rsts check out/traj.csv --mcap out/check.mcap

FILE by extension: .csv (header t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3;
other columns ignored), .json ({\"samples\": [{\"t\", \"omega\", \"alpha\", \"beta\"}]}), .npy
(float64, shape (N, 10)), .mcap (/integrated/state of an rsts log). Times strictly increasing,
any spacing. Without --m/--h the motion is identified from the first row (which must lie on N).
Values with at most 17 significant digits are read as f64; a file with longer values is read
exactly at its precision. See docs/own-integrator.md.";

/// Options of `rsts check`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The trajectory: .csv, .json, .npy or .mcap
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    #[command(flatten)]
    pub fields: FieldArgs,
    /// Value m of the partial integral of N (with --h; without both: identified from the first row)
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_hyphen_values = true, requires = "h")]
    pub m: Option<f64>,
    /// Energy h (with --m)
    #[arg(long, value_name = "H", value_parser = finite_f64, allow_hyphen_values = true, requires = "m")]
    pub h: Option<f64>,
    /// Which Liouville torus (0-based; with --m/--h; default 0)
    #[arg(long, value_name = "K", requires = "m")]
    pub torus: Option<usize>,
    /// Angle psi1 on the torus at t = 0 (radians; with --m/--h; default 0)
    #[arg(long, value_name = "X", value_parser = finite_f64, allow_hyphen_values = true, requires = "m")]
    pub phase1: Option<f64>,
    /// Angle psi2 on the torus at t = 0 (radians; with --m/--h; default 0)
    #[arg(long, value_name = "Y", value_parser = finite_f64, allow_hyphen_values = true, requires = "m")]
    pub phase2: Option<f64>,
    /// Decimal digits the data carry (default: 15 for f64 data, else those of the longest value);
    /// the reference is evaluated 64 bits beyond (at least 30 digits)
    #[arg(long, value_name = "D")]
    pub digits: Option<u32>,
    /// Exit with status 1 when the max state error exceeds E
    #[arg(long, value_name = "E", value_parser = finite_f64)]
    pub max_error: Option<f64>,
    /// Write the comparison to this MCAP file (the layout of `rsts compare`; the file's trajectory
    /// is the integrated motion)
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Output format of the report
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

/// The motion a trajectory is checked against.
#[derive(Clone, Debug, Serialize)]
pub struct CheckedCase {
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    pub torus: usize,
    /// Angles on the torus at t = 0.
    pub phase1: f64,
    pub phase2: f64,
    /// True when (m, h, torus, phases) were identified from the first row.
    pub identified: bool,
}

/// The JSON of `rsts check`.
#[derive(Serialize)]
struct Document<'a> {
    file: String,
    case: &'a CheckedCase,
    /// max |x − x_exact| over the nine components at the first row (the start of the run).
    start_state_error: f64,
    /// Relative distance of the first row from N (identification only).
    #[serde(skip_serializing_if = "Option::is_none")]
    start_distance_from_n: Option<f64>,
    #[serde(flatten)]
    report: &'a Report,
    #[serde(skip_serializing_if = "Option::is_none")]
    mcap: Option<String>,
}

/// Largest trajectory file read (its values are kept at their precision while they are checked).
pub const MAX_FILE_BYTES: u64 = 2 * 1024 * 1024 * 1024;

/// Refuse a file too large to read, naming it (before any memory is spent on it).
fn check_file_size(path: &std::path::Path) -> anyhow::Result<()> {
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_file() && meta.len() > MAX_FILE_BYTES {
            bail!(
                "{}: {} bytes, more than the {} bytes (2 GiB) a trajectory file may have; check it in parts",
                path.display(),
                meta.len(),
                MAX_FILE_BYTES
            );
        }
    }
    Ok(())
}

/// Relative distance from N above which a first row is refused for identification.
pub const ON_N_TOLERANCE: f64 = 1e-8;

/// Identify the motion from the first state: (m, h, torus) and the phases at t = 0.
fn identify_case(
    a: f64,
    b: f64,
    t0: &Float,
    first: &rsts_dynamics::State<Float>,
) -> anyhow::Result<(CheckedCase, f64)> {
    let bits = t0.prec();
    let f = |x: f64| Float::with_val(bits, x);
    let id = identify(&f(a), &f(b), first).map_err(|e| match e {
        IdentifyError::Input(msg) => anyhow!("first row: {msg}"),
        IdentifyError::NoTorus { m, h, distance, reason } => anyhow!(
            "first row: not a state of a motion on N of a = {a}, b = {b}: its (m, h) = ({m}, {h}) has no torus ({reason}); its relative distance from N is {distance:.3e}"
        ),
    })?;
    let relative = id.distance.relative.to_f64();
    if relative.is_nan() || relative > ON_N_TOLERANCE {
        bail!(
            "first row: not on N of a = {a}, b = {b}: its relative distance from N is {relative:.3e} (> {ON_N_TOLERANCE:e}); give the motion with --m, --h (and --torus, --phase1, --phase2) to check it anyway"
        );
    }
    // ψ(t) = ψ⁰ + ν t: the phases at t = 0 from those at the first row's time.
    let motion = rsts_closed_form::ExplicitMotion::new(
        f(a),
        f(b),
        id.m.clone(),
        id.h.clone(),
        rsts_closed_form::TorusChoice {
            torus: id.torus,
            phase1: 0.0,
            phase2: 0.0,
        },
    )?;
    let nu = motion.frequencies();
    let two_pi = Float::with_val(bits, rug::float::Constant::Pi) * 2u32;
    let at_zero = |psi: &Float, nu: &Float| {
        let x = Float::with_val(bits, psi - nu.clone() * t0);
        let turns = Float::with_val(bits, &x / &two_pi).floor();
        let psi = (x - turns * &two_pi).to_f64();
        // 2π − 1e-16 is 0 on the torus.
        if psi > std::f64::consts::TAU - 1e-12 {
            0.0
        } else {
            psi
        }
    };
    Ok((
        CheckedCase {
            a,
            b,
            m: id.m.to_f64(),
            h: id.h.to_f64(),
            torus: id.torus,
            phase1: at_zero(&id.phases[0], &nu[0]),
            phase2: at_zero(&id.phases[1], &nu[1]),
            identified: true,
        },
        relative,
    ))
}

pub fn run(args: Args, out: &mut dyn Write) -> anyhow::Result<()> {
    if let Some(e) = args.max_error {
        if e < 0.0 {
            bail!("--max-error: must be non-negative, got {e}");
        }
    }
    if let Some(d) = args.digits {
        if !(1..=10_000).contains(&d) {
            bail!("--digits: must be between 1 and 10000, got {d}");
        }
    }
    let (a, b) = (args.fields.a, args.fields.b);
    rsts_dynamics::Fields::new(a, b).map_err(|e| anyhow!("--a/--b: {e}"))?;
    if let (Some(m), Some(h)) = (args.m, args.h) {
        // The motion given is checked before the file is read.
        let case = Case {
            a,
            b,
            m,
            h,
            torus: args.torus.unwrap_or(0),
            phase1: args.phase1.unwrap_or(0.0),
            phase2: args.phase2.unwrap_or(0.0),
            t_end: 0.0,
            samples: 1,
        };
        case.validate().map_err(case_error)?;
        case.reference_motion(64).map_err(case_error)?;
    }
    if let Some(path) = &args.mcap {
        rsts_io::check_writable(path).with_context(|| format!("--mcap {}", path.display()))?;
    }
    check_file_size(&args.file)?;
    let raw = rsts_external::read_trajectory(&args.file).map_err(|e| anyhow!("{e}"))?;
    let data_digits = match args.digits {
        Some(d) => d,
        None if raw.is_high_precision() => raw.digits() as u32,
        None => 15,
    };
    let bits = bits_for_digits(data_digits.max(30)) + REFERENCE_GUARD_BITS;
    let samples = raw.to_samples(bits);
    drop(raw);
    let (case, distance) = match (args.m, args.h) {
        (Some(m), Some(h)) => (
            CheckedCase {
                a,
                b,
                m,
                h,
                torus: args.torus.unwrap_or(0),
                phase1: args.phase1.unwrap_or(0.0),
                phase2: args.phase2.unwrap_or(0.0),
                identified: false,
            },
            None,
        ),
        _ => {
            let (case, d) = identify_case(a, b, &samples.times[0], &samples.states[0])?;
            (case, Some(d))
        }
    };
    let harness_case = Case {
        a,
        b,
        m: case.m,
        h: case.h,
        torus: case.torus,
        phase1: case.phase1,
        phase2: case.phase2,
        // The motion is built for the largest |t| of the file (its phase clock's bits).
        t_end: samples
            .times
            .iter()
            .fold(0.0, |m: f64, t| m.max(t.to_f64().abs())),
        samples: 1,
    };
    let name = args
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| args.file.display().to_string());
    let info = RunInfo {
        method: name,
        rtol: None,
        atol: None,
        digits: data_digits,
    };
    let mut analysis = Analysis::for_case(&harness_case, bits, info).map_err(|e| {
        if case.identified {
            anyhow!(
                "the motion identified from the first row of {}: {e}",
                args.file.display()
            )
        } else {
            case_error(e)
        }
    })?;
    let log = match &args.mcap {
        None => None,
        Some(path) => {
            let meta =
                serde_json::json!({"method": "check", "file": args.file.display().to_string()});
            Some(open_log(path, &case, &meta)?)
        }
    };
    let stop = stop_on_ctrl_c();
    let mut observer = CliObserver::new(log, samples.times.len() as u64, stop.clone());
    let mut start_error = None;
    let mut result = Ok(());
    for (t, s) in samples.times.iter().zip(&samples.states) {
        if stop.load(Ordering::SeqCst) {
            analysis.mark_incomplete();
            break;
        }
        match analysis.sample(t, s, &mut observer) {
            Ok(e) => {
                start_error.get_or_insert(e.state_error);
            }
            Err(e) => {
                result = Err(anyhow!("{e}"));
                break;
            }
        }
    }
    if let Err(e) = result {
        // A failed check discards its log: the temporary is removed, a previous file stays.
        observer.bar.finish_and_clear();
        drop(observer);
        return Err(e);
    }
    let log_stats = observer.finish()?;
    let report = analysis.finish();
    check_finite_report(&report)?;
    let mcap = args.mcap.as_ref().map(|p| p.display().to_string());
    let start_state_error = start_error.unwrap_or(f64::NAN);
    let doc = Document {
        file: args.file.display().to_string(),
        case: &case,
        start_state_error,
        start_distance_from_n: distance,
        report: &report,
        mcap: mcap.clone(),
    };
    match args.format {
        Format::Json => output::write_json(out, &doc)?,
        Format::Csv => output::write_records_csv(out, &[&doc])?,
        Format::Table => {
            output::write_key_values(
                out,
                &[
                    ("file", args.file.display().to_string()),
                    (
                        "motion",
                        format!(
                            "{} (phases {:.12}, {:.12} at t = 0)",
                            if case.identified {
                                "identified from the first row"
                            } else {
                                "given"
                            },
                            case.phase1,
                            case.phase2
                        ),
                    ),
                    ("start state error", format!("{start_state_error:.3e}")),
                ],
            )?;
            let t_last = samples.times.last().map_or(0.0, Float::to_f64);
            let t_first = samples.times[0].to_f64();
            write_table(
                out,
                &report,
                &format!("{t_first}, {t_last}"),
                (a, b, case.m, case.h, case.torus),
            )?;
        }
    }
    if let (Some(path), Some(stats)) = (&mcap, log_stats) {
        eprintln!(
            "MCAP log: {path} ({} samples, {} messages). Open it in Foxglove or Lichtblick (Open local file), or run `target/release/rsts inspect {path}`.",
            stats.samples, stats.messages
        );
    }
    if !report.complete {
        out.flush()?;
        return Err(Interrupted(format!(
            "interrupted: checked {} of {} samples",
            report.samples_compared,
            samples.times.len()
        ))
        .into());
    }
    if let Some(limit) = args.max_error {
        if report.max_state_error.is_nan() || report.max_state_error > limit {
            out.flush()?;
            return Err(Failed(format!(
                "{}: max state error {:.3e} exceeds --max-error {limit:e}",
                args.file.display(),
                report.max_state_error
            ))
            .into());
        }
    }
    Ok(())
}
