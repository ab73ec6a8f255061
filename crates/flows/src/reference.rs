//! `ReferenceRequest → reference → ReferenceOutcome`: the exact motion at the times asked, with
//! H, K, G per row — the rows of `rsts reference` and of the Python package's `Case.reference`
//! (docs/own-integrator.md), streamed: up to 10⁷ rows in the memory of one batch.
//!
//! Each time is exact ([`crate::times`]); the closed form is evaluated at the digits asked
//! (default 30) plus [`REFERENCE_GUARD_BITS`] and every value rounded once, to f64 or to the
//! digits asked. f64 rows at f64 times come from the double-double closed form, correctly
//! rounded (the same bits at a fifth of the cost); at a time that is not an f64 (0.1) the row
//! is the state at that exact time, rounded, and shows the f64 nearest it.

use rayon::prelude::*;
use serde::Serialize;

use rsts_closed_form::{Decimal, Motion, Times};
use rsts_harness::reference::{check_digits, ReferenceTable};
use rsts_harness::HarnessError;

use crate::sink::{Collect, Sink};
use crate::{times, FlowError};

/// Rows computed per parallel batch in f64 (written in order between batches); fewer at more
/// digits, so that a batch takes about a second whatever the digits.
pub const BATCH: usize = 8192;

/// The exact motion at given times.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceRequest {
    pub motion: Motion,
    pub times: Times,
    /// Digits of every value (`None`: f64, correctly rounded).
    pub digits: Option<u32>,
    /// Threads to compute the rows on (`None`: every core); the rows do not depend on it.
    pub jobs: Option<usize>,
}

/// The head of the document: the motion, its camera and the digits.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceHead {
    pub a: Decimal,
    pub b: Decimal,
    pub m: Decimal,
    pub h: Decimal,
    pub camera: String,
    pub torus: usize,
    pub phase1: Decimal,
    pub phase2: Decimal,
    pub digits: Option<u32>,
    /// How many rows follow.
    #[serde(skip)]
    pub rows: usize,
}

/// A row: t, ω, α, β (body frame), H, K, G ([`rsts_harness::reference::COLUMNS`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceRow {
    /// f64 values, correctly rounded (t: the f64 nearest the time).
    F64([f64; 13]),
    /// Decimal strings of the digits asked.
    Decimal(Vec<String>),
}

/// What a reference run wrote.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceOutcome {
    pub rows: usize,
}

/// Rows per batch at `digits`.
fn batch(digits: Option<u32>) -> usize {
    match digits {
        None => BATCH,
        Some(d) => (BATCH * 18 / d.max(18) as usize).clamp(64, BATCH),
    }
}

fn harness(e: HarnessError) -> FlowError {
    FlowError::from(e)
}

/// The rows of the request: the head to `sink`, then each row, computed in parallel batches on
/// `jobs` threads, turned by `encode` into what the sink takes (the bytes of a CSV line, a JSON
/// object; the row itself) on the same threads, and handed to the sink in order. Bad input is
/// refused before anything goes to the sink.
pub fn reference<E, S>(
    request: &ReferenceRequest,
    encode: impl Fn(ReferenceRow) -> E + Sync,
    sink: &mut S,
) -> Result<ReferenceOutcome, S::Error>
where
    E: Send,
    S: Sink<ReferenceHead, E>,
{
    let digits = check_digits(request.digits.map(i64::from))
        .map_err(|e| FlowError::input(&["digits"], e))?;
    times::check(&request.times).map_err(|e| FlowError::input(&["times"], e))?;
    let motion = &request.motion;
    let case = rsts_harness::Case::new(motion.clone(), Decimal::from_integer(0), 1);
    let table =
        ReferenceTable::for_reach(&case, times::reach(&request.times), digits).map_err(harness)?;
    let mut threads = rayon::ThreadPoolBuilder::new();
    if let Some(n) = request.jobs {
        threads = threads.num_threads(n);
    }
    let pool = threads
        .build()
        .map_err(|e| FlowError::input(&["jobs"], format!("cannot start the threads: {e}")))?;
    let n = request.times.len();
    let head = ReferenceHead {
        a: motion.a.clone(),
        b: motion.b.clone(),
        m: motion.m.clone(),
        h: motion.h.clone(),
        camera: table.analysis().motion().camera.label().to_string(),
        torus: motion.torus,
        phase1: motion.phase1.clone(),
        phase2: motion.phase2.clone(),
        digits,
        rows: n,
    };
    sink.head(&head)?;
    let row = |k: usize| -> Result<ReferenceRow, FlowError> {
        let failed = |e: String| FlowError::input(&[], e);
        Ok(match digits {
            None => {
                let (hi, lo) = times::split(&request.times, k);
                let r = if lo == 0.0 {
                    table.row_f64(hi)
                } else {
                    table.row_f64_at(&times::exact(&request.times, k, table.bits()), hi)
                };
                ReferenceRow::F64(r.map_err(failed)?)
            }
            Some(_) => {
                let t = times::exact(&request.times, k, table.bits());
                let r = table.row_at(&t).map_err(failed)?;
                ReferenceRow::Decimal(r.iter().map(|x| table.text(x)).collect())
            }
        })
    };
    let step = batch(digits);
    let mut first = 0;
    while first < n {
        let last = (first + step).min(n);
        let encoded: Vec<Result<E, FlowError>> = pool.install(|| {
            (first..last)
                .into_par_iter()
                .map(|k| row(k).map(&encode))
                .collect()
        });
        for e in encoded {
            sink.row(e?)?;
        }
        first = last;
    }
    Ok(ReferenceOutcome { rows: n })
}

/// The head and every row of [`reference`] in memory (the Python face; tests).
pub fn reference_rows(
    request: &ReferenceRequest,
) -> Result<(ReferenceHead, Vec<ReferenceRow>), FlowError> {
    let mut all = Collect::default();
    reference(request, |r| r, &mut all)?;
    Ok((all.head.expect("the head comes first"), all.rows))
}
