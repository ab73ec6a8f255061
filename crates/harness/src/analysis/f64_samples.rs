//! The analysis of f64 data kept in f64 (`rsts check` of an f64 file): no MPFR number per
//! value. The exact state comes from the closed form in double-double, and everything measured
//! against it — the errors, H, K, G, the correct digits, the geometry's clock — is computed in
//! double-double (106 bits, 53 beyond the data; docs/closed-form.md, "Why the reported error of
//! f64 data is still the data's"). The report is that of [`Analysis::sample_all`] of the same
//! samples widened to MPFR, but for a value within 2⁻¹⁰⁰ of an f64 rounding boundary.

use rug::Float;

use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::state::DIM;
use rsts_dynamics::State;

use super::f64_errors::f64_sample_errors;
use super::{Analysis, DdMeasure, Evaluated, Observer};
use crate::geometry::WarmStart;
use crate::metrics::{sample_errors, SampleErrors, StateSnapshot};
use crate::HarnessError;

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
            return Err(HarnessError::Case(format!(
                "{} times and {} states",
                times.len(),
                states.len()
            )));
        }
        if self.dd.is_none() || self.dd_measure.is_none() {
            let bits = self.bits;
            let wide = |x: &f64| Float::with_val(bits, *x);
            let t: Vec<Float> = times.iter().map(wide).collect();
            let s: Vec<State<Float>> = states
                .iter()
                .map(|x| State::from_slice(&x.each_ref().map(wide)))
                .collect();
            return self.sample_all(&t, &s, observer);
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
                // The projector of each sample starts from the one before (the first: cold).
                let mut warm = WarmStart::default();
                out.extend(
                    ts.iter()
                        .zip(xs)
                        .zip(exact)
                        .map(|((t, x), e)| me.evaluate_f64(m, *t, x, e, wanted, &mut warm)),
                );
            },
            |t, _| (*t, None),
            super::CHUNK,
        )
    }

    /// What an f64 sample's errors are, in double-double, apart from the samples before it
    /// (`exact`: its state from
    /// [`crate::rounded_reference::DdReference::states`]).
    fn evaluate_f64(
        &self,
        m: &DdMeasure,
        t: f64,
        x: &[f64; DIM],
        exact: State<DoubleDouble>,
        snapshots: bool,
        warm: &mut WarmStart,
    ) -> Evaluated {
        let (errors, snapshots, digits) = measure(m, &exact, x, self.digits.ratio(), snapshots);
        let geometry = self
            .geometry
            .as_ref()
            .and_then(|g| g.evaluate_f64(t, x, &exact, warm));
        Evaluated {
            exact: None,
            errors,
            digits,
            snapshots,
            geometry,
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

/// [`sample_errors`] and [`crate::digits::sample_errors_dd`] of one f64 sample: the one kernel
/// of [`f64_sample_errors`] (the snapshots, when asked, from the general code).
#[inline(always)]
pub(super) fn measure_portable(
    m: &DdMeasure,
    exact: &State<DoubleDouble>,
    x: &[f64; DIM],
    ratio: f64,
    snapshots: bool,
) -> Measured {
    let (errors, d) = f64_sample_errors(&m.fields, &m.n, &m.initial_integrals, exact, x);
    let digits = crate::digits::of_differences(&d, &exact.to_array(), ratio);
    let snapshots = if snapshots {
        let state = State::from_slice(&x.map(DoubleDouble::from_f64_exact));
        let (_, s) = sample_errors(&m.fields, &m.n, &m.initial_integrals, exact, &state, true);
        s.map(Box::new)
    } else {
        None
    };
    (errors, snapshots, digits)
}
