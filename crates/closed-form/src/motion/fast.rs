//! The double-double state at an f64 time compiled twice and chosen at run time: once with the
//! FMA instructions (`#[target_feature(enable = "fma")]`), once for any x86-64 (what the build
//! targets). The generic evaluation (phase, sn cn, the radicals, ω α β and every double-double
//! operation) is `#[inline(always)]`, so all of it is instantiated inside each entry point and
//! every `f64::mul_add` of the error-free products becomes one instruction on the FMA path
//! (on the portable path, a call of the library's `fma`). Both round once per `mul_add`, so
//! both paths give the same bits (tested).

use rsts_dynamics::scalar::DoubleDouble;

use super::phase::turns_at;
use super::ExplicitMotion;
use crate::elliptic::EllipticModulus;
use crate::formulas::{body_state_with, BodyState, ExplicitState, SeparatedCoordinates};

/// A build of the double-double state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DdPath {
    /// Compiled with FMA (x86-64 CPUs from 2013 on).
    Fma,
    /// For any CPU the build targets.
    Portable,
}

impl DdPath {
    /// Can this CPU run the path?
    pub fn available(self) -> bool {
        match self {
            DdPath::Portable => true,
            #[cfg(target_arch = "x86_64")]
            DdPath::Fma => std::arch::is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            DdPath::Fma => false,
        }
    }

    /// The fastest path of this CPU.
    #[inline]
    pub fn detect() -> Self {
        if DdPath::Fma.available() {
            DdPath::Fma
        } else {
            DdPath::Portable
        }
    }
}

impl ExplicitMotion<DoubleDouble> {
    /// ω, α, β at the f64 time `t` on the fastest path of this CPU.
    #[inline]
    pub fn body_at_f64(&self, t: f64) -> BodyState<DoubleDouble> {
        self.on_path(DdPath::detect(), t, body_fma, body_portable)
    }

    /// The whole state at the f64 time `t` on the fastest path of this CPU.
    #[inline]
    pub fn at_f64(&self, t: f64) -> ExplicitState<DoubleDouble> {
        self.on_path(DdPath::detect(), t, state_fma, state_portable)
    }

    /// [`Self::body_at_f64`] on a given path; `None` when this CPU lacks it.
    pub fn body_at_f64_on(&self, path: DdPath, t: f64) -> Option<BodyState<DoubleDouble>> {
        path.available()
            .then(|| self.on_path(path, t, body_fma, body_portable))
    }

    /// `fma` or `portable` of the motion at `t` by `path`, which this CPU must have.
    #[inline(always)]
    fn on_path<R>(
        &self,
        path: DdPath,
        t: f64,
        #[allow(unused_variables)] fma: unsafe fn(&Self, f64) -> R,
        portable: fn(&Self, f64) -> R,
    ) -> R {
        match path {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the callers pass DdPath::Fma only when the CPU has FMA (detected).
            DdPath::Fma => unsafe { fma(self, t) },
            _ => portable(self, t),
        }
    }
}

/// ω, α, β at an f64 time from the phases in turns ([`turns_at`]): sin and cos of a_N·u =
/// 2π·u/4K without a reduction by π ([`DoubleDouble::sin_cos_turns`]), then Bulirsch's
/// recursion to the ratio sn : cn, which the separated variables take as it is (their values
/// are homogeneous of degree 0 in sn, cn). `None` where the clock has no turns (t beyond its
/// range): then [`ExplicitMotion::body_at`], kept out of line (the code of one state is larger
/// than the instruction cache already).
#[inline(always)]
fn body_in_turns(m: &ExplicitMotion<DoubleDouble>, t: f64) -> Option<BodyState<DoubleDouble>> {
    // (No closures here: they would not inherit the FMA build of the caller.)
    let turns = match &m.clock {
        Some(clock) => clock.turns(),
        None => None,
    };
    let [c1, c2] = turns?;
    let (Some(phi1), Some(phi2)) = (turns_at(c1, t), turns_at(c2, t)) else {
        return None;
    };
    let (v1, v2) = (&m.first, &m.second);
    let ((q1, p1), (q2, p2)) = EllipticModulus::sn_cn_ratio_pair(
        &v1.modulus,
        phi1.sin_cos_turns(),
        || phi1 * v1.modulus.big_k.mul_f64(4.0),
        &v2.modulus,
        phi2.sin_cos_turns(),
        || phi2 * v2.modulus.big_k.mul_f64(4.0),
    );
    let x1 = v1.eval::<DoubleDouble>(&q1, &p1);
    let x2 = v2.eval::<DoubleDouble>(&q2, &p2);
    let point = SeparatedCoordinates::new(x1, x2);
    Some(body_state_with(&m.formula, &m.products, &point))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn body_fma(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    match body_in_turns(m, t) {
        Some(b) => b,
        None => body_by_u_fma(m, t),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
#[inline(never)]
#[cold]
unsafe fn body_by_u_fma(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    m.body_at(&DoubleDouble::from_f64_exact(t))
}

fn body_portable(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    match body_in_turns(m, t) {
        Some(b) => b,
        None => body_by_u_portable(m, t),
    }
}

#[inline(never)]
#[cold]
fn body_by_u_portable(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    m.body_at(&DoubleDouble::from_f64_exact(t))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn state_fma(m: &ExplicitMotion<DoubleDouble>, t: f64) -> ExplicitState<DoubleDouble> {
    m.at(&DoubleDouble::from_f64_exact(t))
}

fn state_portable(m: &ExplicitMotion<DoubleDouble>, t: f64) -> ExplicitState<DoubleDouble> {
    m.at(&DoubleDouble::from_f64_exact(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TorusChoice;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rug::Float;

    /// The state from the phases in turns is the closed form's to a few units of 2⁻¹⁰⁶ of each
    /// value's scale, against 40 digits in MPFR, over the nine cameras: random times up to 1e9,
    /// times at the turning points of either variable (sin a_N·u = 0 exactly: the Landen
    /// branch at t = 0 with phases 0), and times beyond the clock's f64 range (the phase u by
    /// the other reduction).
    #[test]
    fn state_in_turns_is_the_closed_form_to_106_bits() {
        let bits = 136;
        let phased = TorusChoice {
            torus: 0,
            phase1: 0.7,
            phase2: 2.1,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        let cases = crate::EXAMPLE_POINTS_A1_B05
            .iter()
            .flat_map(|&p| [(p, phased), (p, TorusChoice::default())]);
        for ((camera, m, h), choice) in cases {
            let d = DoubleDouble::from_f64_exact;
            let dd = ExplicitMotion::new_until(d(1.0), d(0.5), d(m), d(h), choice, 1e13).unwrap();
            let f = |x: f64| Float::with_val(bits, x);
            let mp = ExplicitMotion::new_until(f(1.0), f(0.5), f(m), f(h), choice, 1e13).unwrap();
            let mut times: Vec<f64> = (0..150)
                .map(|k| match k % 3 {
                    0 => rng.gen_range(0.0..1e9),
                    1 => rng.gen_range(-1e3..1e3),
                    _ => 1e9 * rng.gen::<f64>().powi(8),
                })
                .collect();
            for i in 0..2 {
                let turns = dd.turning_times(i, &d(0.0), &d(50.0), 100).unwrap();
                times.extend(turns.iter().take(3).map(|(t, _)| t.hi));
            }
            times.extend([0.0, 2e12, -3e12]);
            let (mut err, mut scale) = ([0f64; 9], [0f64; 9]);
            for &t in &times {
                let a = dd.body_at_f64(t);
                let b = mp.body_at(&f(t));
                let xs = a.omega.iter().chain(&a.alpha).chain(&a.beta);
                let ys = b.omega.iter().chain(&b.alpha).chain(&b.beta);
                for (j, (x, y)) in xs.zip(ys).enumerate() {
                    let diff = Float::with_val(bits, &x.to_float(bits) - y);
                    err[j] = err[j].max(diff.to_f64().abs());
                    scale[j] = scale[j].max(y.to_f64().abs());
                }
            }
            for j in 0..9 {
                let units = err[j] / scale[j] / 2f64.powi(-106);
                assert!(
                    units < 200.0,
                    "{camera:?} value {j}: {units:.1} units of 2⁻¹⁰⁶"
                );
            }
        }
    }
}
