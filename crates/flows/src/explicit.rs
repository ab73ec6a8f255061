//! `ExplicitRequest → explicit → ExplicitOutcome`: the closed-form motion on the invariant
//! manifold N (seed sec. 1–3) at given times — the whole state (ω, α, β, γ, Ω) — in f64 or to
//! any number of digits: the document of `rsts explicit`.
//!
//! The motion is built from its decimals at the working precision (the digits asked plus
//! [`REFERENCE_GUARD_BITS`], as `reference` and `events`) and evaluated at each time exact to
//! that precision ([`crate::times`]); every value is rounded once, to the digits asked, or to f64
//! (correctly: the double-double closed form where Ziv's test decides, else MPFR,
//! [`RoundedExplicit`]). A decimal time that is not an f64 (0.1 of a grid 0, 0.1, …) is the
//! exact time; its row shows the nearest f64.

use serde::ser::SerializeSeq;
use serde::{Serialize, Serializer};

use rsts_closed_form::events::Number;
use rsts_closed_form::{Decimal, Motion, Times};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::Real;
use rsts_harness::rounded_explicit::RoundedExplicit;
use rsts_harness::{HarnessError, MAX_SAMPLES, REFERENCE_GUARD_BITS};

use crate::{times, FlowError};

/// Digits an explicit run may carry (without: f64, correctly rounded).
pub const DIGITS: std::ops::RangeInclusive<u32> = 16..=100_000;
/// Most memory the samples of one run may take (2 GiB): they are kept until written.
pub const MAX_SAMPLE_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;
/// Values of a row: t, ω, α, β, γ, Ω.
pub const ROW: usize = 16;

/// The motion at given times.
#[derive(Clone, Debug, PartialEq)]
pub struct ExplicitRequest {
    pub motion: Motion,
    pub times: Times,
    /// Digits of the computation and the output (`None`: f64, correctly rounded).
    pub digits: Option<u32>,
}

/// The rows: t and the 15 values of the state, as f64 or as decimal strings.
#[derive(Clone, Debug, PartialEq)]
pub enum Rows {
    F64(Vec<[f64; ROW]>),
    Decimal(Vec<Vec<String>>),
}

impl Rows {
    pub fn len(&self) -> usize {
        match self {
            Rows::F64(r) => r.len(),
            Rows::Decimal(r) => r.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Row `k`: t, ω, α, β, γ, Ω.
    pub fn row(&self, k: usize) -> Vec<Number> {
        match self {
            Rows::F64(r) => r[k].iter().map(|&x| Number::F64(x)).collect(),
            Rows::Decimal(r) => r[k].iter().map(|s| Number::Decimal(s.clone())).collect(),
        }
    }
}

/// One sample of the document.
#[derive(Serialize)]
struct Sample<'a> {
    t: &'a Number,
    omega: &'a [Number],
    alpha: &'a [Number],
    beta: &'a [Number],
    gamma: &'a [Number],
    #[serde(rename = "Omega")]
    omega_fixed: &'a [Number],
}

/// The rows as the document's samples, made one at a time while it is written.
impl Serialize for Rows {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut seq = serializer.serialize_seq(Some(self.len()))?;
        for k in 0..self.len() {
            let r = self.row(k);
            seq.serialize_element(&Sample {
                t: &r[0],
                omega: &r[1..4],
                alpha: &r[4..7],
                beta: &r[7..10],
                gamma: &r[10..13],
                omega_fixed: &r[13..16],
            })?;
        }
        seq.end()
    }
}

/// The document of `rsts explicit`.
#[derive(Clone, Debug, Serialize)]
pub struct ExplicitOutcome {
    pub a: Number,
    pub b: Number,
    pub m: Number,
    pub h: Number,
    pub camera: String,
    pub tori: usize,
    pub torus: usize,
    pub phase1: Decimal,
    pub phase2: Decimal,
    /// Digits of the values (17: f64).
    pub digits: u32,
    pub samples: Rows,
    /// The periods of ψ₁, ψ₂ (for the table).
    #[serde(skip)]
    pub periods: [f64; 2],
    /// Their ratio.
    #[serde(skip)]
    pub rotation_number: f64,
}

/// Check the times and the digits, and that the rows fit in [`MAX_SAMPLE_BYTES`].
fn check(request: &ExplicitRequest) -> Result<(), FlowError> {
    if let Some(d) = request.digits {
        if !DIGITS.contains(&d) {
            return Err(FlowError::input(
                &["digits"],
                format!(
                    "must be between {} and {}, got {d}",
                    DIGITS.start(),
                    DIGITS.end()
                ),
            ));
        }
    }
    let n = request.times.len();
    match &request.times {
        Times::Grid { t_end, samples } => {
            if *samples == 0 {
                return Err(FlowError::input(&["samples"], "need at least 1 sample"));
            }
            if *samples > MAX_SAMPLES {
                return Err(FlowError::input(
                    &["samples"],
                    format!("at most {MAX_SAMPLES} samples are supported, got {samples}"),
                ));
            }
            if t_end.is_negative() {
                return Err(FlowError::input(
                    &["t-end"],
                    format!("must be non-negative, got {t_end}"),
                ));
            }
        }
        other => times::check(other).map_err(|e| FlowError::input(&["times"], e))?,
    }
    // Memory: the 16 numbers of every sample are kept (f64: 8 bytes; a decimal: its characters
    // and a string's bookkeeping); the output is made from them row by row.
    let per_number = match request.digits {
        None => 8.0,
        Some(d) => f64::from(d) + 48.0,
    };
    let bytes = n as f64 * ROW as f64 * per_number;
    if bytes > MAX_SAMPLE_BYTES {
        return Err(FlowError::input(
            &["samples", "digits"],
            format!(
                "{n} samples at {} digits need about {} bytes of memory, more than {}; ask for fewer samples or digits",
                request.digits.unwrap_or(17),
                rsts_dynamics::short(bytes),
                rsts_dynamics::short(MAX_SAMPLE_BYTES)
            ),
        ));
    }
    Ok(())
}

fn harness(e: impl Into<HarnessError>) -> FlowError {
    FlowError::from(e.into())
}

/// The closed-form motion of the request at its times.
pub fn explicit(request: &ExplicitRequest) -> Result<ExplicitOutcome, FlowError> {
    check(request)?;
    let motion = &request.motion;
    let t_max = times::reach(&request.times);
    if !t_max.is_finite() {
        return Err(FlowError::input(
            &["t-end"],
            format!("at most {:e} (the largest f64), got {t_max}", f64::MAX),
        ));
    }
    let digits = request.digits.unwrap_or(17);
    // The motion at the working precision: its camera, tori, periods (and, with digits, its
    // values).
    let bits = bits_for_digits(digits) + REFERENCE_GUARD_BITS;
    let reach =
        Decimal::from_f64(t_max).map_err(|e| FlowError::input(&["t-end"], e.to_string()))?;
    let case = rsts_harness::Case::new(motion.clone(), reach, 1);
    let (exact, _) = case.reference_motion(bits).map_err(harness)?;
    let n = request.times.len();
    let not_finite = |k: usize, t: f64| {
        FlowError::input(
            &[],
            format!(
                "the closed form is not finite at t = {} (sample {k} of {n})",
                rsts_dynamics::short(t)
            ),
        )
    };
    let samples = match request.digits {
        None => {
            // f64: the double-double closed form correctly rounded (MPFR where Ziv's test
            // cannot decide, and at times that are not f64 numbers).
            let rounded = RoundedExplicit::new(&case, t_max).map_err(harness)?;
            let mut rows = Vec::with_capacity(n);
            for k in 0..n {
                let (hi, lo) = times::split(&request.times, k);
                let values = if lo == 0.0 {
                    rounded.row(hi)
                } else {
                    rounded.row_at(&times::exact(&request.times, k, rounded.mp_bits()))
                };
                if values.iter().any(|v| !v.is_finite()) {
                    return Err(not_finite(k, hi));
                }
                let mut row = [hi; ROW];
                row[1..].copy_from_slice(&values);
                rows.push(row);
            }
            Rows::F64(rows)
        }
        Some(d) => {
            let mut rows = Vec::with_capacity(n);
            for k in 0..n {
                let t = times::exact(&request.times, k, bits);
                let s = exact.at(&t);
                let vs = [&s.omega, &s.alpha, &s.beta, &s.gamma, &s.omega_fixed];
                if vs.iter().flat_map(|v| v.iter()).any(|v| !v.is_finite()) {
                    return Err(not_finite(k, t.to_f64()));
                }
                let mut row = Vec::with_capacity(ROW);
                row.push(t.to_decimal(d));
                row.extend(vs.iter().flat_map(|v| v.iter()).map(|x| x.to_decimal(d)));
                rows.push(row);
            }
            Rows::Decimal(rows)
        }
    };
    let number = |x: &Decimal| match request.digits {
        None => Number::F64(x.to_f64()),
        Some(d) => Number::Decimal(x.to_float(bits).to_decimal(d)),
    };
    Ok(ExplicitOutcome {
        a: number(&motion.a),
        b: number(&motion.b),
        m: number(&motion.m),
        h: number(&motion.h),
        camera: exact.camera.label().to_string(),
        tori: exact.tori,
        torus: motion.torus,
        phase1: motion.phase1.clone(),
        phase2: motion.phase2.clone(),
        digits,
        samples,
        periods: exact.periods().map(|p| p.to_f64()),
        rotation_number: exact.rotation_number().to_f64(),
    })
}
