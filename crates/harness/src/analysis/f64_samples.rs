//! The analysis of f64 data kept in f64 (`rsts check` of an f64 file): no MPFR number per
//! value. The exact state comes from the closed form in double-double, and everything measured
//! against it — the errors, H, K, G, the correct digits, the geometry's clock — is computed in
//! double-double (106 bits, 53 beyond the data; docs/closed-form.md, "Why the reported error of
//! f64 data is still the data's"). The report is that of [`Analysis::sample_all`] of the same
//! samples widened to MPFR, but for a value within 2⁻¹⁰⁰ of an f64 rounding boundary.

use rug::Float;

use rsts_closed_form::BatchPath;
use rsts_dynamics::scalar::{DoubleDouble, LANES};
use rsts_dynamics::state::DIM;
use rsts_dynamics::State;

use super::f64_errors::f64_sample_errors;
use super::{Analysis, DdMeasure, Evaluated, Observer};
use crate::geometry::WarmStart;
use crate::metrics::{sample_errors, SampleErrors, StateSnapshot};
use crate::HarnessError;

/// Bits of MPFR numbers widened from f64 data at once (those of 1.6·10⁷ digits, as a chunk of
/// high-precision data read from a file holds: `rsts_external::stream::CHUNK_DIGITS`).
const WIDE_BITS: usize = 53_150_850;

impl Analysis {
    /// [`Analysis::sample_all`] of f64 samples: `times` and one state (ω, α, β) per time. In
    /// double-double for data of at most 16 digits (the analysis made by
    /// [`Analysis::for_case`]); otherwise the samples are widened to the reference precision.
    pub fn sample_all_f64(
        &mut self,
        times: &[f64],
        states: &[[f64; DIM]],
        observer: &mut dyn Observer,
    ) -> Result<Option<SampleErrors>, HarnessError> {
        if times.len() != states.len() {
            return Err(HarnessError::Data(format!(
                "{} times and {} states",
                times.len(),
                states.len()
            )));
        }
        if self.dd.is_none() || self.dd_measure.is_none() {
            // Widened a part at a time: at most WIDE_BITS bits of numbers at once (at 10000
            // digits 160 rows, not the whole chunk: 8192 rows would take 340 MB). Each MPFR
            // sample is evaluated apart from the others: the parts change no digit.
            let bits = self.bits;
            let rows = (WIDE_BITS / (10 * bits as usize).max(1)).clamp(1, super::BATCH);
            let wide = |x: &f64| Float::with_val(bits, *x);
            let mut first = None;
            for (tc, sc) in times.chunks(rows).zip(states.chunks(rows)) {
                let t: Vec<Float> = tc.iter().map(wide).collect();
                let s: Vec<State<Float>> = sc
                    .iter()
                    .map(|x| State::from_slice(&x.each_ref().map(wide)))
                    .collect();
                let errors = self.sample_all(&t, &s, observer)?;
                first = first.or(errors);
                if !self.report().complete {
                    break;
                }
            }
            return Ok(first);
        }
        self.in_batches(
            times,
            states,
            observer,
            |me, ts, xs, wanted, out| {
                let (Some(dd), Some(m)) = (me.dd.as_ref(), me.dd_measure.as_ref()) else {
                    unreachable!("checked above")
                };
                let exact = dd.states(ts);
                let start = out.len();
                measure_all(m, &exact, xs, me.digits.ratio(), wanted, out);
                me.geometry_f64(ts, xs, &exact, &mut out[start..]);
            },
            |t, _| (*t, None),
            super::CHUNK,
        )
    }

    /// The geometry of each f64 sample of a chunk (`out`: their errors measured), in time
    /// order: the projector of each sample starts from the one before (the first: cold).
    fn geometry_f64(
        &self,
        ts: &[f64],
        xs: &[[f64; DIM]],
        exact: &[State<DoubleDouble>],
        out: &mut [Evaluated],
    ) {
        let Some(g) = self.geometry.as_ref() else {
            return;
        };
        let mut warm = WarmStart::default();
        for (((ev, t), x), e) in out.iter_mut().zip(ts).zip(xs).zip(exact) {
            ev.geometry = g.evaluate_f64(*t, x, e, &mut warm);
        }
    }
}

/// What [`measure_portable`] returns: the errors, the snapshots (when asked: boxed, so that
/// the usual answer without them is small to return) and the relative and mixed error of the
/// correct digits.
type Measured = (SampleErrors, Option<Box<[StateSnapshot; 2]>>, (f64, f64));

/// The errors of f64 data `x` against the exact state in double-double: with the fused
/// multiply-add of the processor where it has one (the same numbers: an FMA rounds once
/// either way; without it each `mul_add` of double-double is a call to the library's).
fn measure(
    m: &DdMeasure,
    exact: &State<DoubleDouble>,
    x: &[f64; DIM],
    ratio: f64,
    snapshots: bool,
) -> Measured {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the processor has FMA (checked just above).
        return unsafe { measure_fma(m, exact, x, ratio, snapshots) };
    }
    measure_portable(m, exact, x, ratio, snapshots)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
pub(super) unsafe fn measure_fma(
    m: &DdMeasure,
    exact: &State<DoubleDouble>,
    x: &[f64; DIM],
    ratio: f64,
    snapshots: bool,
) -> Measured {
    measure_portable(m, exact, x, ratio, snapshots)
}

/// [`sample_errors`] and [`crate::digits::sample_errors_dd`] of one f64 sample: the kernel
/// [`f64_sample_errors`] in one lane (the snapshots, when asked, from the general code).
#[inline(always)]
pub(super) fn measure_portable(
    m: &DdMeasure,
    exact: &State<DoubleDouble>,
    x: &[f64; DIM],
    ratio: f64,
    snapshots: bool,
) -> Measured {
    let [(errors, digits)] = f64_sample_errors::<1>(
        &m.fields,
        &m.n,
        &m.initial_integrals,
        std::slice::from_ref(exact),
        std::slice::from_ref(x),
        ratio,
    );
    let snapshots = if snapshots {
        let state = State::from_slice(&x.map(DoubleDouble::from_f64_exact));
        let (_, s) = sample_errors(&m.fields, &m.n, &m.initial_integrals, exact, &state, true);
        s.map(Box::new)
    } else {
        None
    };
    (errors, snapshots, digits)
}

/// A sample's measures as evaluated (its geometry to come).
#[inline(always)]
pub(super) fn evaluated((errors, snapshots, digits): Measured) -> Evaluated {
    Evaluated {
        exact: None,
        errors,
        digits,
        snapshots,
        geometry: None,
    }
}

/// The errors of each f64 sample `xs[i]` against `exact[i]`, appended to `out` (no geometry
/// yet): four samples at a time on a CPU with AVX2 and FMA, otherwise one at a time
/// ([`measure`]); the same numbers either way.
fn measure_all(
    m: &DdMeasure,
    exact: &[State<DoubleDouble>],
    xs: &[[f64; DIM]],
    ratio: f64,
    snapshots: bool,
    out: &mut Vec<Evaluated>,
) {
    if !measure_all_on(BatchPath::Avx2Fma, m, exact, xs, ratio, snapshots, out) {
        for (e, x) in exact.iter().zip(xs) {
            out.push(evaluated(measure(m, e, x, ratio, snapshots)));
        }
    }
}

/// [`measure_all`] four at a time on a given build; false (and nothing appended) when this
/// CPU lacks it.
pub(super) fn measure_all_on(
    path: BatchPath,
    m: &DdMeasure,
    exact: &[State<DoubleDouble>],
    xs: &[[f64; DIM]],
    ratio: f64,
    snapshots: bool,
    out: &mut Vec<Evaluated>,
) -> bool {
    if !path.available() {
        return false;
    }
    match path {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        BatchPath::Avx2Fma => unsafe { measure_all_avx2(m, exact, xs, ratio, snapshots, out) },
        _ => measure_all_portable(m, exact, xs, ratio, snapshots, out),
    }
    true
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn measure_all_avx2(
    m: &DdMeasure,
    exact: &[State<DoubleDouble>],
    xs: &[[f64; DIM]],
    ratio: f64,
    snapshots: bool,
    out: &mut Vec<Evaluated>,
) {
    measure_all_portable(m, exact, xs, ratio, snapshots, out)
}

/// [`f64_sample_errors`] of each group of four samples in four lanes (errors and digits), the
/// rest (and every sample when the snapshots are asked) in one lane by [`measure_portable`].
/// Plain loops, no closure: compiled with the caller's features.
#[inline(always)]
fn measure_all_portable(
    m: &DdMeasure,
    exact: &[State<DoubleDouble>],
    xs: &[[f64; DIM]],
    ratio: f64,
    snapshots: bool,
    out: &mut Vec<Evaluated>,
) {
    let grouped = if snapshots {
        0
    } else {
        exact.len().min(xs.len()) / LANES * LANES
    };
    for (e, x) in exact[..grouped]
        .chunks_exact(LANES)
        .zip(xs[..grouped].chunks_exact(LANES))
    {
        let four = f64_sample_errors::<LANES>(&m.fields, &m.n, &m.initial_integrals, e, x, ratio);
        for (errors, digits) in four {
            out.push(evaluated((errors, None, digits)));
        }
    }
    for (e, x) in exact[grouped..].iter().zip(&xs[grouped..]) {
        out.push(evaluated(measure_portable(m, e, x, ratio, snapshots)));
    }
}
