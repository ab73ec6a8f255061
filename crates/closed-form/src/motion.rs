//! A motion on a Liouville torus of N: the two separated variables with the torus's signs, angle
//! coordinates (ψ₁, ψ₂) that are linear in time, and the state at any time.

use rsts_dynamics::dual::Dual;
use rsts_dynamics::Real;
use rug::Float;
use serde::Serialize;

use crate::camera::Camera;
use crate::constants::IntegralConstants;
use crate::elliptic::EllipticModulus;
use crate::error::ClosedFormError;
use crate::formulas::{
    body_state_with, explicit_state, BodyState, ConstantProducts, ExplicitState, FormulaConstants,
    SeparatedCoordinates,
};
use crate::roots::Root;
use crate::scalar::{Scalar, GUARD_BITS};
use crate::separated::{segments, SeparatedVariable};

mod fast;
mod lanes;
mod phase;
pub mod symmetry;
mod value;
pub use fast::DdPath;
pub use lanes::BatchPath;
use phase::PhaseClock;
pub use phase::F64_CLOCK_MAX_T;
pub use value::{binary, decimal, InputError, Motion};

/// Which torus and where on it the motion starts.
///
/// Torus numbering: for each free constant sign (the radical that keeps its sign on the torus,
/// see [`SeparatedVariable::free_sign`]) bit 0 is the sign for x = 1/s₁ and the next bit the sign
/// for s₂ (bit clear: +, set: −). Torus 0 has all free radicals positive.
///
/// Phases: ψᵢ ∈ [0, 2π) is the angle on the torus, ψᵢ = ψᵢ⁰ + νᵢ t; ψᵢ = 0 puts the variable at
/// the lower end λ of its segment in the coordinate x = 1/s₁ (first) and s₂ (second). The
/// defaults are torus 0 and ψ = (0, 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct TorusChoice {
    pub torus: usize,
    pub phase1: f64,
    pub phase2: f64,
}

/// The closed-form motion on one torus.
#[derive(Clone, Debug)]
pub struct ExplicitMotion<T> {
    pub constants: IntegralConstants<T>,
    pub camera: Camera,
    /// Number of Liouville tori of the integral manifold.
    pub tori: usize,
    pub choice: TorusChoice,
    /// x = 1/s₁ with (F₁*, G₁*).
    pub first: SeparatedVariable<T>,
    /// s₂ with (F₂, G₂).
    pub second: SeparatedVariable<T>,
    /// u at t = 0 for each variable.
    u0: [T; 2],
    formula: FormulaConstants<T>,
    /// Products of the formula's constants, formed once.
    products: ConstantProducts<T>,
    /// The phase in extra precision (absent in the internal high-precision build).
    clock: Option<PhaseClock>,
}

type Segment<T> = (Root<T>, Root<T>);

fn free_sign_of<T: Real>(
    name: &'static str,
    f: &crate::separated::Radicand<T>,
    g: &crate::separated::Radicand<T>,
    seg: &Segment<T>,
    eps: i32,
) -> Result<bool, ClosedFormError> {
    Ok(SeparatedVariable::new(name, f, g, seg.clone(), eps, 1)?.free_sign)
}

impl<T: Scalar> ExplicitMotion<T> {
    /// The motion for (a, b, m, h) on the chosen torus, in the precision of `a`. The constants
    /// are computed [`GUARD_BITS`] beyond it and rounded once. The phase is exact to the working
    /// precision for |t| up to [`valid_until`](Self::valid_until) (|u̇|·t below 2^(GUARD_BITS − 8),
    /// ~1e17 periods); [`new_until`](Self::new_until) builds a clock for longer times.
    pub fn new(a: T, b: T, m: T, h: T, choice: TorusChoice) -> Result<Self, ClosedFormError> {
        Self::with_clock_bits(a, b, m, h, choice, 0)
    }

    /// [`new`](Self::new) with a phase clock exact to the working precision for every |t| ≤
    /// `t_max`: the constants of the clock (u₀, u̇, 4K) are computed with as many more bits as
    /// log₂(|u̇|·t_max) needs (about 1000 more for t = 1e300), so the state at any finite time is
    /// that of the motion, not of a phase that lost its digits.
    pub fn new_until(
        a: T,
        b: T,
        m: T,
        h: T,
        choice: TorusChoice,
        t_max: f64,
    ) -> Result<Self, ClosedFormError> {
        let motion = Self::new(a.clone(), b.clone(), m.clone(), h.clone(), choice)?;
        let u_dot = motion
            .vars()
            .iter()
            .map(|v| v.u_dot.to_f64().abs())
            .fold(0.0, f64::max);
        let reach = (u_dot * t_max.abs()).max(1.0).log2().ceil();
        let spare = f64::from(GUARD_BITS - 8);
        if reach.is_nan() || reach <= spare {
            return Ok(motion);
        }
        let extra = (reach - spare) as u32 + 8;
        Self::with_clock_bits(a, b, m, h, choice, extra)
    }

    /// The largest |t| at which the phase is still exact to the working precision.
    pub fn valid_until(&self) -> f64 {
        let Some(clock) = &self.clock else {
            return f64::INFINITY;
        };
        let spare = clock.bits() - self.constants.a.prec().max(53) - 8;
        let u_dot = clock
            .u_dot()
            .iter()
            .map(|u| u.to_f64().abs())
            .fold(0.0, f64::max);
        2f64.powi(spare as i32) / u_dot.max(f64::MIN_POSITIVE)
    }

    fn with_clock_bits(
        a: T,
        b: T,
        m: T,
        h: T,
        choice: TorusChoice,
        extra: u32,
    ) -> Result<Self, ClosedFormError> {
        let bits = a.prec();
        let hi = bits.max(53) + GUARD_BITS + extra;
        let up = |x: &T| x.to_mpfr(hi);
        let phases = [choice.phase1, choice.phase2].map(|p| Float::with_val(hi, p));
        Self::from_exact(bits, [up(&a), up(&b), up(&m), up(&h)], phases, choice)
    }

    /// The motion from its inputs given at the high precision of the build (a, b, m, h and the
    /// phases each rounded once from what the user wrote), rounded once to `bits`.
    pub(crate) fn from_exact(
        bits: u32,
        [a, b, m, h]: [Float; 4],
        phases: [Float; 2],
        choice: TorusChoice,
    ) -> Result<Self, ClosedFormError> {
        let exact = ExplicitMotion::<Float>::build(a, b, m, h, choice.torus, phases)?;
        Ok(Self::from_built(bits, &exact, choice))
    }

    /// The motion rounded once to `bits` from its build at a higher precision, with the phase
    /// clock of that precision.
    pub(crate) fn from_built(
        bits: u32,
        exact: &ExplicitMotion<Float>,
        choice: TorusChoice,
    ) -> Self {
        let hi = exact.constants.a.prec();
        let down = |x: &Float| T::from_mpfr(x, bits);
        let vars = [&exact.first, &exact.second];
        let clock = PhaseClock::new(
            hi,
            exact.u0.clone(),
            vars.map(|v| v.u_dot.clone()),
            vars.map(|v| v.modulus.big_k.clone() * 4u32),
        );
        let formula = FormulaConstants {
            a: down(&exact.formula.a),
            b: down(&exact.formula.b),
            m: down(&exact.formula.m),
            ell: down(&exact.formula.ell),
            r: down(&exact.formula.r),
            pmh: down(&exact.formula.pmh),
        };
        Self {
            constants: exact.constants.map(&down),
            camera: exact.camera,
            tori: exact.tori,
            choice,
            first: exact.first.map(&down),
            second: exact.second.map(&down),
            u0: exact.u0.clone().map(|x| down(&x)),
            products: ConstantProducts::new(&formula),
            formula,
            clock: Some(clock),
        }
    }

    /// The parameters u₁, u₂ of the elliptic functions at time t, reduced modulo 4K with
    /// [`GUARD_BITS`] extra bits: from f64 expansions at f64 precision (bit for bit the MPFR
    /// reduction, see `motion/phase.rs`) and in double-double (for an f64 time), in MPFR
    /// otherwise.
    #[inline(always)]
    fn u_at(&self, t: &T) -> [T; 2] {
        match &self.clock {
            Some(clock) => {
                let bits = self.constants.a.prec();
                if let Some(tf) = t.dd_clock_time() {
                    if let (Some(u1), Some(u2)) = (clock.reduced_dd(0, tf), clock.reduced_dd(1, tf))
                    {
                        return [T::from_dd(u1, bits), T::from_dd(u2, bits)];
                    }
                }
                if bits <= 53 {
                    // t has at most 53 bits: it is the f64 t.to_f64().
                    let tf = t.to_f64();
                    if let (Some(u1), Some(u2)) =
                        (clock.reduced_f64(0, tf), clock.reduced_f64(1, tf))
                    {
                        return [T::from_f64(u1, bits), T::from_f64(u2, bits)];
                    }
                }
                let tt = t.to_mpfr(clock.bits());
                std::array::from_fn(|i| T::from_mpfr(&clock.reduced(i, &tt), bits))
            }
            None => {
                let vars = self.vars();
                std::array::from_fn(|i| {
                    let u = self.u0[i].clone() + vars[i].u_dot.clone() * t;
                    let four_k = vars[i].modulus.big_k.clone() * u.lit(4.0);
                    let n = (u.clone() / &four_k).floor();
                    u - n * &four_k
                })
            }
        }
    }

    /// The times t in (t0, t1] at which separated variable `i` (0: x = 1/s₁, 1: s₂) is at a
    /// turning point, in time order, each with `true` at the lower end λ (sn u = 0, u = 2jK) and
    /// `false` at the upper end μ (cn u = 0, u = (2j+1)K): t = (jK − u₀)/u̇, computed with the
    /// clock's guard bits. At most `limit` times (`None` beyond).
    pub fn turning_times(&self, i: usize, t0: &T, t1: &T, limit: usize) -> Option<Vec<(T, bool)>> {
        let bits = self.constants.a.prec();
        let w = self.turning_window(i, t0, t1);
        let span = Float::with_val(w.hi, &w.j1 - &w.j0).to_f64();
        if !(span.is_finite() && span <= limit as f64 + 2.0) {
            return None;
        }
        let mut out = Vec::new();
        let mut j = w.j0;
        while j <= w.j1 {
            let t = (Float::with_val(w.hi, &j * &w.big_k) - &w.u0) / &w.u_dot;
            if t > w.a && t <= w.b {
                let even = Float::with_val(w.hi, &j / 2u32).is_integer();
                out.push((T::from_mpfr(&t, bits), even));
            }
            j += 1u32;
        }
        if w.u_dot < 0 {
            out.reverse();
        }
        (out.len() <= limit).then_some(out)
    }

    /// How many turning points of separated variable `i` [`Self::turning_times`] may find in
    /// (t0, t1] (at most two more than it finds), without listing them.
    pub fn turning_count(&self, i: usize, t0: &T, t1: &T) -> f64 {
        let w = self.turning_window(i, t0, t1);
        Float::with_val(w.hi, &w.j1 - &w.j0).to_f64() + 1.0
    }

    /// The range of j with jK in u((t0, t1]) for separated variable `i`.
    fn turning_window(&self, i: usize, t0: &T, t1: &T) -> TurningWindow {
        let bits = self.constants.a.prec();
        let (hi, u0, u_dot, big_k) = match &self.clock {
            Some(clock) => {
                let (u0, four_k) = clock.u0_four_k();
                let k = Float::with_val(clock.bits(), &four_k[i] / 4u32);
                (clock.bits(), u0[i].clone(), clock.u_dot()[i].clone(), k)
            }
            None => {
                let hi = bits.max(53);
                let v = self.vars()[i];
                (
                    hi,
                    self.u0[i].to_mpfr(hi),
                    v.u_dot.to_mpfr(hi),
                    v.modulus.big_k.to_mpfr(hi),
                )
            }
        };
        let (a, b) = (t0.to_mpfr(hi), t1.to_mpfr(hi));
        // j K ranges over u(t) for t in [t0, t1]: u = u₀ + u̇ t.
        let ua = Float::with_val(hi, &u_dot * &a) + &u0;
        let ub = Float::with_val(hi, &u_dot * &b) + &u0;
        let (lo, up) = if ua <= ub { (ua, ub) } else { (ub, ua) };
        let j0 = Float::with_val(hi, &lo / &big_k).floor();
        let j1 = Float::with_val(hi, &up / &big_k).ceil();
        TurningWindow {
            hi,
            u0,
            u_dot,
            big_k,
            a,
            b,
            j0,
            j1,
        }
    }

    /// The state at time t.
    #[inline(always)]
    pub fn at(&self, t: &T) -> ExplicitState<T> {
        let [u1, u2] = self.u_at(t);
        self.at_u(&u1, &u2)
    }

    /// ω, α, β at time t (the state of [`Self::at`] without γ, Ω, Q′, Q″, ω′, ω″).
    #[inline(always)]
    pub fn body_at(&self, t: &T) -> BodyState<T> {
        let [u1, u2] = self.u_at(t);
        let ((sn1, cn1), (sn2, cn2)) =
            EllipticModulus::sn_cn_pair(&self.first.modulus, &u1, &self.second.modulus, &u2);
        let p1 = self.first.eval::<T>(&sn1, &cn1);
        let p2 = self.second.eval::<T>(&sn2, &cn2);
        body_state_with(
            &self.formula,
            &self.products,
            &SeparatedCoordinates::new(p1, p2),
        )
    }

    /// The state at time t with its time derivative (dual parts), by the chain rule through the
    /// separated variables: d sn/dt = u̇ cn dn, d cn/dt = −u̇ sn dn.
    pub fn at_with_derivative(&self, t: &T) -> ExplicitState<Dual<T>> {
        let [u1, u2] = self.u_at(t);
        let point = |var: &SeparatedVariable<T>, u: &T| {
            let (sn, cn, dn) = var.modulus.sn_cn_dn(u);
            let sn_d = Dual::new(sn.clone(), var.u_dot.clone() * &cn * &dn);
            let cn_d = Dual::new(cn, -(var.u_dot.clone() * &sn * &dn));
            var.eval::<Dual<T>>(&sn_d, &cn_d)
        };
        let p1 = point(&self.first, &u1);
        let p2 = point(&self.second, &u2);
        let f = &self.formula;
        let fc = f.map(|x| Dual::constant(x.clone()));
        explicit_state(&fc, SeparatedCoordinates::new(p1, p2))
    }
}

impl<T: Real> ExplicitMotion<T> {
    /// The motion computed directly in T, without guard digits.
    pub(crate) fn build(
        a: T,
        b: T,
        m: T,
        h: T,
        torus: usize,
        phases: [T; 2],
    ) -> Result<Self, ClosedFormError> {
        let choice = TorusChoice {
            torus,
            phase1: phases[0].to_f64(),
            phase2: phases[1].to_f64(),
        };
        for (name, v) in [("phase1", &phases[0]), ("phase2", &phases[1])] {
            if !v.is_finite() {
                return Err(ClosedFormError::Parameters(format!(
                    "{name} is not a finite number"
                )));
            }
        }
        let constants = IntegralConstants::new(a, b, m, h)?;
        let (f1, g1) = constants.radicands_x();
        let (f2, g2) = constants.radicands_s2();
        let seg1 = segments(&f1, &g1);
        let seg2 = segments(&f2, &g2);
        if seg1.is_empty() || seg2.is_empty() {
            return Err(ClosedFormError::NotAdmissible(format!(
                "no real motion: s1 has {} and s2 has {} oscillation segments",
                seg1.len(),
                seg2.len()
            )));
        }
        // Enumerate (segment of x, segment of s2, free signs) in a fixed order.
        let mut options = Vec::new();
        for s1 in &seg1 {
            let free1 = free_sign_of("x = 1/s1", &f1, &g1, s1, -1)?;
            for s2 in &seg2 {
                let free2 = free_sign_of("s2", &f2, &g2, s2, 1)?;
                let n1 = if free1 { 2 } else { 1 };
                let n2 = if free2 { 2 } else { 1 };
                for j in 0..n1 * n2 {
                    let (sign1, sign2) = symmetry::free_signs(j, free1, free2);
                    options.push((s1.clone(), s2.clone(), sign1, sign2));
                }
            }
        }
        let tori = options.len();
        let m_negative = constants.m < constants.m.zero_like();
        let camera = {
            let (s1, s2, _, _) = &options[0];
            Camera::from_segments(
                [s1.0.label, s1.1.label],
                [s2.0.label, s2.1.label],
                m_negative,
            )
            .ok_or_else(|| {
                ClosedFormError::Internal(format!(
                    "segments s1 ∈ [{}, {}], s2 ∈ [{}, {}] match no camera of Table 1",
                    s1.0.label, s1.1.label, s2.0.label, s2.1.label
                ))
            })?
        };
        let Some((s1, s2, sign1, sign2)) = options.get(choice.torus).cloned() else {
            return Err(ClosedFormError::NoSuchTorus {
                torus: choice.torus,
                camera: camera.label().to_string(),
                tori,
            });
        };
        let first = SeparatedVariable::new("x = 1/s1", &f1, &g1, s1, -1, sign1)?;
        let second = SeparatedVariable::new("s2", &f2, &g2, s2, 1, sign2)?;
        let formula = FormulaConstants {
            a: constants.a.clone(),
            b: constants.b.clone(),
            m: constants.m.clone(),
            ell: constants.ell.clone(),
            r: constants.r.clone(),
            pmh: constants.pmh.clone(),
        };
        let two_pi = T::pi(constants.a.prec()) * constants.a.lit(2.0);
        let [phase1, phase2] = phases;
        let u0 = [
            phase1 * first.period_u() / &two_pi,
            phase2 * second.period_u() / &two_pi,
        ];
        Ok(Self {
            constants,
            camera,
            tori,
            choice,
            first,
            second,
            u0,
            products: ConstantProducts::new(&formula),
            formula,
            clock: None,
        })
    }

    fn vars(&self) -> [&SeparatedVariable<T>; 2] {
        [&self.first, &self.second]
    }

    /// Angular frequencies νᵢ = dψᵢ/dt = 2π u̇ᵢ / Pᵢ.
    pub fn frequencies(&self) -> [T; 2] {
        let two_pi = T::pi(self.constants.a.prec()) * self.constants.a.lit(2.0);
        self.vars()
            .map(|v| two_pi.clone() * &v.u_dot / v.period_u())
    }

    /// Periods in time of the two angles, Pᵢ / u̇ᵢ.
    pub fn periods(&self) -> [T; 2] {
        self.vars().map(|v| v.period_u() / &v.u_dot)
    }

    /// Rotation number ν₁/ν₂ of the torus.
    pub fn rotation_number(&self) -> T {
        let [n1, n2] = self.frequencies();
        n1 / n2
    }

    /// The state at the angles (ψ₁, ψ₂) on the torus.
    pub fn at_angles(&self, psi1: &T, psi2: &T) -> ExplicitState<T> {
        let two_pi = T::pi(self.constants.a.prec()) * self.constants.a.lit(2.0);
        let u1 = psi1.clone() * self.first.period_u() / &two_pi;
        let u2 = psi2.clone() * self.second.period_u() / &two_pi;
        self.at_u(&u1, &u2)
    }

    #[inline(always)]
    fn at_u(&self, u1: &T, u2: &T) -> ExplicitState<T> {
        let (sn1, cn1) = self.first.modulus.sn_cn(u1);
        let (sn2, cn2) = self.second.modulus.sn_cn(u2);
        let p1 = self.first.eval::<T>(&sn1, &cn1);
        let p2 = self.second.eval::<T>(&sn2, &cn2);
        explicit_state(&self.formula, SeparatedCoordinates::new(p1, p2))
    }
}

/// The turning points of one separated variable in a window: u = u₀ + u̇ t, the quarter
/// period K, the window (a, b] and the range j0 ..= j1 of jK it covers, at `hi` bits.
struct TurningWindow {
    hi: u32,
    u0: Float,
    u_dot: Float,
    big_k: Float,
    a: Float,
    b: Float,
    j0: Float,
    j1: Float,
}
