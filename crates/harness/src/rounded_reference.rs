//! The reference of f64 data in double-double: the state (ω, α, β) from the closed form in
//! [`DoubleDouble`], each value rounded to f64 when Ziv's test decides it
//! ([`rsts_closed_form::rounded`]), the state otherwise recomputed in MPFR by the caller. The
//! result is the MPFR state rounded to f64, bit for bit (tests/harness/rounded_reference.rs), at about
//! a fifth of its cost. H, K, G are constants on N ([`integrals_on_n`]), rounded once.

use rug::Float;

use rsts_closed_form::rounded::{calibration_times, RoundingBounds};
use rsts_closed_form::{BatchPath, BodyState, DdPath, ExplicitMotion};
use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::{Real, State};

use crate::case::Case;

/// The values of a state: ω, α, β.
pub const VALUES: usize = 9;

/// H, K, G on N correctly rounded to f64: H = h, K = r⁴m², G = (p²h + r⁴m)/2 (seed sec. 1;
/// `rsts_dynamics::integrals`), computed exactly ([`integrals_on_n_exact`]) and rounded once —
/// so K = 0 when m = 0, and a value halfway between two f64 goes to the even one, where a
/// state's H, K, G rounded from MPFR carry the noise of its last bits.
pub fn integrals_on_n(case: &Case) -> [f64; 3] {
    integrals_on_n_exact(case).map(|x| x.to_f64())
}

/// H, K, G on N from the decimals at 1024 bits (exact for inputs that are f64 values: 1024 bits
/// hold every product of them; within 2⁻¹⁰⁰⁰ relative for other decimals).
pub fn integrals_on_n_exact(case: &Case) -> [Float; 3] {
    let motion = &case.motion;
    let f = |x: &rsts_closed_form::Decimal| x.to_float(1024);
    let (a2, b2) = (f(&motion.a).square(), f(&motion.b).square());
    let r2 = Float::with_val(1024, &a2 - &b2);
    let p2 = a2 + b2;
    let r4 = r2.square();
    let r4m = r4 * f(&motion.m);
    let k = Float::with_val(1024, &r4m * f(&motion.m));
    let g = (p2 * f(&motion.h) + r4m) / 2u32;
    [f(&motion.h), k, g]
}

/// The closed form of a case in double-double with the calibrated bounds of its state.
#[derive(Clone, Debug)]
pub struct DdReference {
    motion: ExplicitMotion<DoubleDouble>,
    bounds: RoundingBounds<VALUES>,
}

impl DdReference {
    /// The motion of `case` in double-double with its phase clock built for |t| ≤ `t_max`, its
    /// bounds calibrated against `mpfr` (the state at the reference precision). `None`
    /// when the motion cannot be built in double-double (the caller stays with MPFR).
    pub fn new(case: &Case, t_max: f64, mpfr: impl Fn(f64) -> [Float; VALUES]) -> Option<Self> {
        let bits = DoubleDouble::from_f64_exact(0.0).prec();
        let motion = case.motion.explicit::<DoubleDouble>(bits, t_max).ok()?;
        let times = calibration_times(motion.periods().map(|p| p.to_f64()));
        let mut me = Self {
            motion,
            bounds: RoundingBounds {
                bounds: [0.0; VALUES],
            },
        };
        me.bounds = RoundingBounds::calibrate(&times, |t| me.values(t), mpfr);
        Some(me)
    }

    /// The state at time t in double-double, as 9 values.
    pub fn values(&self, t: f64) -> [DoubleDouble; VALUES] {
        self.state(t).to_array()
    }

    /// The state at time t in double-double (on the FMA build where the CPU has it).
    pub fn state(&self, t: f64) -> State<DoubleDouble> {
        body(self.motion.body_at_f64(t))
    }

    /// The states at the times `ts` in double-double: [`Self::state`] of each, bit for bit,
    /// four at a time (AVX2 and FMA where the CPU has them; [`ExplicitMotion::bodies_at_f64`]).
    pub fn states(&self, ts: &[f64]) -> Vec<State<DoubleDouble>> {
        let mut bodies = Vec::with_capacity(ts.len());
        self.motion.bodies_at_f64(ts, &mut bodies);
        bodies.into_iter().map(body).collect()
    }

    /// [`Self::states`] on a given build ([`BatchPath`]), `None` when this CPU lacks it.
    pub fn states_on(&self, path: BatchPath, ts: &[f64]) -> Option<Vec<State<DoubleDouble>>> {
        let mut bodies = Vec::with_capacity(ts.len());
        self.motion
            .bodies_at_f64_on(path, ts, &mut bodies)
            .then(|| bodies.into_iter().map(body).collect())
    }

    /// [`Self::values`] on a given build of the double-double state ([`DdPath`]), `None` when
    /// this CPU lacks it.
    pub fn values_on(&self, path: DdPath, t: f64) -> Option<[DoubleDouble; VALUES]> {
        Some(body(self.motion.body_at_f64_on(path, t)?).to_array())
    }

    /// [`Self::rounded`] on a given build of the double-double state; `None` when this CPU
    /// lacks it.
    pub fn rounded_on(&self, path: DdPath, t: f64) -> Option<Option<[f64; VALUES]>> {
        Some(self.bounds.round(&self.values_on(path, t)?))
    }

    /// The state at time t correctly rounded to f64, or `None` where Ziv's test cannot
    /// decide one of them (then compute the row in MPFR).
    pub fn rounded(&self, t: f64) -> Option<[f64; VALUES]> {
        self.bounds.round(&self.values(t))
    }

    /// The largest |t| at which the phase is exact to double-double.
    pub fn valid_until(&self) -> f64 {
        self.motion.valid_until()
    }

    /// The calibrated absolute error bound of each value.
    pub fn bounds(&self) -> &[f64; VALUES] {
        &self.bounds.bounds
    }
}

/// ω, α, β as a state.
fn body(b: BodyState<DoubleDouble>) -> State<DoubleDouble> {
    State {
        omega: b.omega,
        alpha: b.alpha,
        beta: b.beta,
    }
}
