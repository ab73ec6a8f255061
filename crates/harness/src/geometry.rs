//! The geometry of the error (issue 11): at every sample, the integrated state's nearest point
//! on N ([`rsts_closed_form::manifold::Projector`]) splits the state error into
//!
//! - the **departure from N**, |x − nearest point| (in the units of the state, max-norm): what
//!   the integrals cannot see, growing like e^{λt} where N is normally hyperbolic;
//! - the **drift along N**, |nearest point − exact state|: a phase error (Δψ₁, Δψ₂ of the nearest
//!   point against the exact angles ψ⁰ + νt) and a shift of the torus (δm, δh, the drift of the
//!   on-N integral relations), typically growing like t or t².
//!
//! The regular distance |X_Φ| of [`rsts_closed_form::manifold::distance`] is logged beside it.
//! The computation runs in the integrator's precision: f64 for the f64 methods (about a µs per
//! sample, on the projector's tabulated torus), MPFR at the integrator's digits + 32 bits
//! otherwise (docs/stability.md says how, docs/benchmarks.md what it costs). The f64 samples of a
//! chunk ([`Geometry::evaluate_f64`]) start each projection from the sample before
//! ([`WarmStart`]): one evaluation of the torus with its derivatives per sample near N.

use rsts_closed_form::manifold::distance::{field_norm, gain};
use rsts_closed_form::manifold::{normal_type, Projector};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::{bits_for_digits, DoubleDouble};
use rsts_dynamics::state::DIM;
use rsts_dynamics::{Fields, Real, State};
use rug::Float;
use serde::Serialize;

use crate::growth;
use crate::HarnessError;

mod summary;
use summary::split;
pub use summary::{
    ErrorSplit, GeometrySummary, GrowthSummary, MaxFinal, NormalSummary, PhaseErrorSummary,
};

/// The geometry of the error at one sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SampleGeometry {
    /// max-norm distance of the integrated state from its nearest point on N (state units).
    pub distance_from_n: f64,
    /// |X_Φ| at the integrated state (the regular, integral-derived measure of the departure).
    pub x_phi: f64,
    /// max-norm distance of the nearest point on N from the exact state (drift along N).
    pub along_n: f64,
    /// ψᵢ(nearest point) − ψᵢ(exact) in (−π, π]; `None` when no nearest point was found (a
    /// state far from the torus, after the error saturated).
    pub phase_error: Option<[f64; 2]>,
    /// The nearest point's (m, h) minus the motion's.
    pub dm: f64,
    pub dh: f64,
}

/// The projection in one scalar.
struct Inner<T> {
    projector: Projector<T>,
    fields: Fields<T>,
    bits: u32,
}

impl<T: Scalar> Inner<T> {
    fn new(motion: &ExplicitMotion<Float>, bits: u32) -> Result<Self, HarnessError> {
        let c = &motion.constants;
        let down = |x: &Float| T::from_mpfr(x, bits);
        let choice = TorusChoice {
            torus: motion.choice.torus,
            phase1: 0.0,
            phase2: 0.0,
        };
        let own = ExplicitMotion::new(down(&c.a), down(&c.b), down(&c.m), down(&c.h), choice)?;
        Ok(Self {
            projector: Projector::new(&own)?,
            fields: Fields {
                a: down(&c.a),
                b: down(&c.b),
            },
            bits,
        })
    }

    fn sample(
        &self,
        state: &State<Float>,
        exact: &State<Float>,
        psi_exact: &[Float; 2],
    ) -> SampleGeometry {
        let down = |x: &Float| T::from_mpfr(x, self.bits);
        let exact = exact.to_array();
        self.sample_in(
            state.map(down),
            std::array::from_fn(|k| down(&exact[k])),
            psi_exact.clone().map(|p| down(&p)),
            &state.map(|c| c.to_f64()),
            None,
        )
    }

    /// [`Inner::sample`] of the state `x`, the exact state and ψ(exact) in `T` (`state`: `x` in
    /// f64), the projection started from ψ(exact) or from a [`WarmStart`]'s `start`.
    fn sample_in(
        &self,
        x: State<T>,
        exact: [T; DIM],
        guess: [T; 2],
        state: &State<f64>,
        start: Option<([f64; 2], [f64; 2])>,
    ) -> SampleGeometry {
        let x_phi = field_norm(&self.fields, &x).to_f64();
        let target = x.to_array();
        let (from, shift) = match start {
            Some((offset, shift)) => (
                std::array::from_fn(|i| guess[i].clone() + T::from_f64(offset[i], self.bits)),
                shift,
            ),
            None => (guess.clone(), [0.0; 2]),
        };
        // The first-order model in (δm, δh) holds for small shifts of the torus only: beyond
        // 1e-2 (an error that has saturated) there is no nearest point near the exact one.
        match self
            .projector
            .project_from(&target, &from, shift, MAX_SHIFT)
        {
            Some(p) => {
                let pi = std::f64::consts::PI;
                let phase_error = std::array::from_fn(|i| {
                    // (ψ − ψ_exact) in (−π, π], in T then f64.
                    let two_pi = T::pi(self.bits) * T::from_f64(2.0, self.bits);
                    let d = p.phases[i].clone() - &guess[i];
                    let turns = (d.clone() / &two_pi + T::from_f64(0.5, self.bits)).floor();
                    let w = (d - turns * two_pi).to_f64();
                    if w <= -pi {
                        w + 2.0 * pi
                    } else {
                        w
                    }
                });
                let along_n = (0..DIM)
                    .map(|k| (p.point[k].clone() - &exact[k]).abs().to_f64())
                    .fold(0.0, f64::max);
                SampleGeometry {
                    distance_from_n: p.departure.to_f64(),
                    x_phi,
                    along_n,
                    phase_error: Some(phase_error),
                    dm: p.dm.to_f64(),
                    dh: p.dh.to_f64(),
                }
            }
            None => {
                // No nearest point near the exact one: the distance in state units from the
                // gain of X_Φ at the state.
                let g = gain(&self.fields_f64(), state);
                SampleGeometry {
                    distance_from_n: if g > 0.0 { x_phi / g } else { f64::NAN },
                    x_phi,
                    along_n: f64::NAN,
                    phase_error: None,
                    dm: f64::NAN,
                    dh: f64::NAN,
                }
            }
        }
    }

    fn fields_f64(&self) -> Fields<f64> {
        Fields {
            a: self.fields.a.to_f64(),
            b: self.fields.b.to_f64(),
        }
    }
}

/// Largest |δm|, |δh| of a nearest point found by the first-order projection.
const MAX_SHIFT: f64 = 1e-2;

enum Precision {
    F64(Box<Inner<f64>>),
    Mp(Box<Inner<Float>>),
}

/// At most this many samples are kept for the growth fits (beyond it every other one is
/// dropped and the stride doubles): bounded memory on runs of millions of samples.
const MAX_KEPT: usize = 1 << 16;

/// The series the growth fits need, decimated to at most [`MAX_KEPT`] points.
#[derive(Default)]
struct Series {
    stride: usize,
    seen: usize,
    t: Vec<f64>,
    state_error: Vec<f64>,
    distance: Vec<f64>,
    along: Vec<f64>,
    phase: Vec<f64>,
}

impl Series {
    fn push(&mut self, t: f64, state_error: f64, g: &SampleGeometry) {
        let stride = self.stride.max(1);
        self.seen += 1;
        if !(self.seen - 1).is_multiple_of(stride) {
            return;
        }
        self.t.push(t);
        self.state_error.push(state_error);
        self.distance.push(g.distance_from_n);
        self.along.push(g.along_n);
        self.phase.push(
            g.phase_error
                .map_or(f64::NAN, |[p, q]| p.abs().max(q.abs())),
        );
        if self.t.len() >= MAX_KEPT {
            for v in [
                &mut self.t,
                &mut self.state_error,
                &mut self.distance,
                &mut self.along,
                &mut self.phase,
            ] {
                let kept: Vec<f64> = v.iter().step_by(2).copied().collect();
                *v = kept;
            }
            self.stride = stride * 2;
        }
    }
}

/// Where the projection of the next f64 sample of a chunk starts ([`Geometry::evaluate_f64`]):
/// the phase error and the shift (δm, δh) of the sample before, when it had a nearest point
/// within [`WARM_PHASE`] and [`WARM_SHIFT`] (its phase error added to the next sample's exact
/// angles is within ~1e-10 of the next nearest point on the default case: one evaluation with
/// derivatives and a chord step instead of two and one). The default: a cold start from the
/// exact angles.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarmStart(Option<([f64; 2], [f64; 2])>);

/// A warm start follows a phase error of at most this (radians) and a shift of the torus of at
/// most [`WARM_SHIFT`]: where the cold start from the exact angles surely finds the same nearest
/// point. Beyond, after an error has saturated, a warm start may follow another local nearest
/// point than the cold one (on camera V's dopri5 run of scripts/bench_check_f64.sh from a phase
/// error of 0.27 rad on: 3171 of 10⁵ samples would change whether they have a nearest point).
const WARM_PHASE: f64 = 1e-2;
const WARM_SHIFT: f64 = 1e-4;

impl WarmStart {
    /// Whether the next projection starts warm.
    pub fn is_warm(&self) -> bool {
        self.0.is_some()
    }

    /// The start of the sample after one of geometry `g`.
    fn after(g: &SampleGeometry) -> Self {
        let small = |p: &[f64; 2]| {
            p[0].abs().max(p[1].abs()) <= WARM_PHASE && g.dm.abs().max(g.dh.abs()) <= WARM_SHIFT
        };
        Self(g.phase_error.filter(small).map(|p| (p, [g.dm, g.dh])))
    }
}

/// ψ⁰, ν of the exact motion and 2π in double-double.
struct PhaseClockDd {
    psi0: [DoubleDouble; 2],
    nu: [DoubleDouble; 2],
    two_pi: DoubleDouble,
}

impl PhaseClockDd {
    /// ψ(exact) at the f64 time `t`: ψ⁰ + νt reduced mod 2π in double-double, with the fused
    /// multiply-add of the processor where it has one (the same numbers: an FMA rounds once
    /// either way; without it each `mul_add` of double-double is a call to the library's).
    fn angles(&self, t: f64) -> [f64; 2] {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the processor has FMA (checked just above).
            return unsafe { self.angles_fma(t) };
        }
        self.angles_portable(t)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "fma")]
    unsafe fn angles_fma(&self, t: f64) -> [f64; 2] {
        self.angles_portable(t)
    }

    /// Both angles written out, no closure: a closure (`array::from_fn`'s) is compiled apart
    /// from the FMA build, and its `mul_add`s became calls to the library's `fma` (2 % of a
    /// check of camera V's dopri5 run).
    #[inline(always)]
    fn angles_portable(&self, t: f64) -> [f64; 2] {
        let t = DoubleDouble::from_f64_exact(t);
        [self.angle(0, t), self.angle(1, t)]
    }

    /// ψᵢ⁰ + νᵢt reduced mod 2π.
    #[inline(always)]
    fn angle(&self, i: usize, t: DoubleDouble) -> f64 {
        let p = self.nu[i] * t + self.psi0[i];
        let turns = (p / self.two_pi).floor();
        (p - turns * self.two_pi).to_f64()
    }
}

/// Tracks the geometry of the error along a run.
pub struct Geometry {
    precision: Precision,
    /// ψ⁰ and ν of the exact motion, at the reference precision.
    psi0: [Float; 2],
    nu: [Float; 2],
    two_pi: Float,
    /// ψ⁰, ν and 2π in double-double: the clock of f64 samples ([`Geometry::evaluate_f64`]).
    clock_dd: PhaseClockDd,
    normal: NormalSummary,
    phase: PhaseErrorSummary,
    series: Series,
    /// Samples seen, and the last one if it was skipped.
    index: usize,
    skipped: Option<(Float, State<Float>, State<Float>, f64)>,
}

impl Geometry {
    /// For the exact `motion` (at the reference precision) and an integrator carrying `digits`
    /// decimal digits (≤ 16: f64).
    pub fn new(motion: &ExplicitMotion<Float>, digits: u32) -> Result<Self, HarnessError> {
        let precision = if digits <= 16 {
            Precision::F64(Box::new(Inner::new(motion, 53)?))
        } else {
            let bits = (bits_for_digits(digits) + 32).min(motion.constants.a.prec());
            Precision::Mp(Box::new(Inner::new(motion, bits)?))
        };
        let bits = motion.constants.a.prec();
        let n = normal_type(&motion.constants);
        let psi0 = [motion.choice.phase1, motion.choice.phase2].map(|p| Float::with_val(bits, p));
        let nu = motion.frequencies();
        let two_pi = Float::with_val(bits, rug::float::Constant::Pi) * 2u32;
        let dd = DoubleDouble::from_float;
        let clock_dd = PhaseClockDd {
            psi0: psi0.each_ref().map(dd),
            nu: nu.each_ref().map(dd),
            two_pi: dd(&two_pi),
        };
        Ok(Self {
            precision,
            psi0,
            nu,
            two_pi,
            clock_dd,
            normal: NormalSummary {
                kind: n.kind,
                lambda2: n.lambda2.to_f64(),
                distance_from_n: MaxFinal::default(),
                x_phi: MaxFinal::default(),
                growth: None,
            },
            phase: PhaseErrorSummary::default(),
            series: Series::default(),
            index: 0,
            skipped: None,
        })
    }

    /// The geometry of the integrated `state` at time `t` against the `exact` state (samples
    /// in time order). `None` for the samples an MPFR run skips ([`Geometry::wanted`]).
    pub fn sample(
        &mut self,
        t: &Float,
        state: &State<Float>,
        exact: &State<Float>,
        state_error: f64,
    ) -> Option<SampleGeometry> {
        let index = self.index;
        self.index += 1;
        if !self.wanted(index) {
            self.skipped = Some((t.clone(), state.clone(), exact.clone(), state_error));
            return None;
        }
        self.skipped = None;
        Some(self.compute(t, state, exact, state_error))
    }

    /// Every sample in f64; in MPFR (about two closed-form evaluations and a gradient of Φ per
    /// sample in the working precision) the first 32, then 16 per doubling of the index (every
    /// 2nd in 32..64, every 4th in 64..128, …), and the last one: log-spaced samples for the
    /// growth fits at a bounded cost.
    fn wanted(&self, index: usize) -> bool {
        match self.precision {
            Precision::F64(_) => true,
            Precision::Mp(_) => {
                index < 32 || {
                    let level = usize::BITS - 1 - index.leading_zeros();
                    index.is_multiple_of(1usize << (level - 4))
                }
            }
        }
    }

    fn compute(
        &mut self,
        t: &Float,
        state: &State<Float>,
        exact: &State<Float>,
        state_error: f64,
    ) -> SampleGeometry {
        let g = self.geometry_of(t, state, exact);
        self.absorb(t.to_f64(), &g, state_error);
        g
    }

    /// The geometry of a sample, not yet recorded.
    fn geometry_of(&self, t: &Float, state: &State<Float>, exact: &State<Float>) -> SampleGeometry {
        let psi_exact: [Float; 2] = std::array::from_fn(|i| {
            let p = self.nu[i].clone() * t + &self.psi0[i];
            let turns = (p.clone() / &self.two_pi).floor();
            p - turns * &self.two_pi
        });
        match &self.precision {
            Precision::F64(inner) => inner.sample(state, exact, &psi_exact),
            Precision::Mp(inner) => inner.sample(state, exact, &psi_exact),
        }
    }

    fn absorb(&mut self, t: f64, g: &SampleGeometry, state_error: f64) {
        self.normal.distance_from_n.absorb(g.distance_from_n);
        self.normal.x_phi.absorb(g.x_phi);
        if let Some([p, q]) = g.phase_error {
            self.phase.psi1.absorb(p.abs());
            self.phase.psi2.absorb(q.abs());
            self.phase.dm = self.phase.dm.max(g.dm.abs());
            self.phase.dh = self.phase.dh.max(g.dh.abs());
        }
        self.series.push(t, state_error, g);
    }

    /// The geometry of a sample computed apart from the samples before it, for a parallel
    /// evaluation: `Some` in f64 (every sample is computed), `None` in MPFR (which samples are
    /// computed depends on their index: use [`Geometry::sample`]).
    pub fn evaluate(
        &self,
        t: &Float,
        state: &State<Float>,
        exact: &State<Float>,
    ) -> Option<SampleGeometry> {
        matches!(self.precision, Precision::F64(_)).then(|| self.geometry_of(t, state, exact))
    }

    /// [`Geometry::evaluate`] of an f64 sample (time `t`, state `x`) against the exact state in
    /// double-double: ψ(exact) = ψ⁰ + νt reduced mod 2π in double-double (106 bits; the MPFR
    /// clock's value rounded to f64 is the same but within 2⁻¹⁰⁰ of a rounding boundary).
    /// `None` when the geometry runs in MPFR. The projection starts from `warm` (the sample
    /// before in the same chunk; [`WarmStart::default`]: cold), which is then this sample's.
    pub fn evaluate_f64(
        &self,
        t: f64,
        x: &[f64; DIM],
        exact: &State<DoubleDouble>,
        warm: &mut WarmStart,
    ) -> Option<SampleGeometry> {
        let Precision::F64(inner) = &self.precision else {
            return None;
        };
        let psi_exact = self.clock_dd.angles(t);
        let exact = exact.to_array().map(|v| v.to_f64());
        let state = State::from_slice(x);
        let g = inner.sample_in(state.clone(), exact, psi_exact, &state, warm.0);
        *warm = WarmStart::after(&g);
        Some(g)
    }

    /// Record the next sample's geometry from [`Geometry::evaluate`] (what
    /// [`Geometry::sample`] does after computing it).
    pub fn record(&mut self, t: f64, g: &SampleGeometry, state_error: f64) {
        self.index += 1;
        self.skipped = None;
        self.absorb(t, g, state_error);
    }

    /// The summary: growth fits and what dominates the error.
    pub fn finish(mut self) -> GeometrySummary {
        // The last sample counts, skipped or not.
        if let Some((t, state, exact, e)) = self.skipped.take() {
            self.compute(&t, &state, &exact, e);
        }
        let s = &self.series;
        let mut normal = self.normal;
        normal.growth = GrowthSummary::of(&growth::fit(&s.t, &s.distance));
        let mut phase = self.phase;
        phase.growth = GrowthSummary::of(&growth::fit(&s.t, &s.phase));
        let error_split = split(s, &normal, &phase);
        GeometrySummary {
            normal,
            phase_error: phase,
            error_split,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The clock of f64 samples gives the same angles, bit for bit, with and without FMA.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn the_clock_is_the_same_with_and_without_fma() {
        if !std::arch::is_x86_feature_detected!("fma") {
            rsts_io::report_skip(
                "the_clock_is_the_same_with_and_without_fma",
                "this processor has no FMA",
            );
            return;
        }
        let dd = DoubleDouble::from_f64_exact;
        let c = PhaseClockDd {
            psi0: [dd(0.4), dd(1.3)],
            nu: [dd(1.234_567_890_123), dd(0.987_654_321_987)],
            two_pi: DoubleDouble::pi(106) * dd(2.0),
        };
        let mut seed = 30u64;
        for k in 0..20_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            let t = u * 10f64.powi(k % 10);
            // SAFETY: the processor has FMA (checked above).
            let fma = unsafe { c.angles_fma(t) };
            assert_eq!(
                fma.map(f64::to_bits),
                c.angles_portable(t).map(f64::to_bits),
                "t = {t}"
            );
        }
    }
}
