//! The double-double state of four samples at once: [`ExplicitMotion::body_at_f64`] of four
//! f64 times in the lanes of [`DoubleDouble4`] — the phases in turns, sin and cos of them, the
//! sn : cn recursion of each variable, the separated points and ω, α, β from the same generic
//! formulas — compiled with AVX2 and FMA (one 256-bit register holds a number of the four
//! samples) where the CPU has them, for any x86-64 otherwise. Every lane performs the scalar
//! path's operations, so the states are the scalar ones bit for bit (tested). A sample that
//! leaves the common case (a time beyond the clock's range, a phase within 1e-30 of a zero of
//! sin: the Landen branch) is computed alone by the scalar path.

use rsts_dynamics::scalar::{every_lane, DoubleDouble, DoubleDouble4, LANES};
use rsts_dynamics::Real;

use super::phase::turns_at4;
use super::ExplicitMotion;
use crate::elliptic::EllipticModulus;
use crate::formulas::{body_state_with, BodyState, SeparatedCoordinates};

/// A build of the batch of states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BatchPath {
    /// Four samples per AVX2 register, with FMA (x86-64 CPUs from 2013 on).
    Avx2Fma,
    /// The same code for any CPU the build targets.
    Portable,
}

impl BatchPath {
    /// Can this CPU run the path?
    pub fn available(self) -> bool {
        match self {
            BatchPath::Portable => true,
            #[cfg(target_arch = "x86_64")]
            BatchPath::Avx2Fma => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            BatchPath::Avx2Fma => false,
        }
    }

    /// The fastest path of this CPU.
    pub fn detect() -> Self {
        if BatchPath::Avx2Fma.available() {
            BatchPath::Avx2Fma
        } else {
            BatchPath::Portable
        }
    }
}

impl ExplicitMotion<DoubleDouble> {
    /// ω, α, β at each f64 time of `ts`, appended to `out`: [`Self::body_at_f64`] of each
    /// time bit for bit, four at a time on the fastest path of this CPU.
    pub fn bodies_at_f64(&self, ts: &[f64], out: &mut Vec<BodyState<DoubleDouble>>) {
        self.bodies_at_f64_on(BatchPath::detect(), ts, out);
    }

    /// [`Self::bodies_at_f64`] on a given path; false (and nothing appended) when this CPU
    /// lacks it.
    pub fn bodies_at_f64_on(
        &self,
        path: BatchPath,
        ts: &[f64],
        out: &mut Vec<BodyState<DoubleDouble>>,
    ) -> bool {
        if !path.available() {
            return false;
        }
        match path {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            BatchPath::Avx2Fma => unsafe { bodies_avx2(self, ts, out) },
            _ => bodies_portable(self, ts, out),
        }
        true
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn bodies_avx2(
    m: &ExplicitMotion<DoubleDouble>,
    ts: &[f64],
    out: &mut Vec<BodyState<DoubleDouble>>,
) {
    bodies(m, ts, out)
}

fn bodies_portable(
    m: &ExplicitMotion<DoubleDouble>,
    ts: &[f64],
    out: &mut Vec<BodyState<DoubleDouble>>,
) {
    bodies(m, ts, out)
}

/// Groups of four times, then the rest one by one.
#[inline(always)]
fn bodies(m: &ExplicitMotion<DoubleDouble>, ts: &[f64], out: &mut Vec<BodyState<DoubleDouble>>) {
    out.reserve(ts.len());
    let mut groups = ts.chunks_exact(LANES);
    for g in &mut groups {
        let [a, b, c, d] = body4(m, [g[0], g[1], g[2], g[3]]);
        out.push(a);
        out.push(b);
        out.push(c);
        out.push(d);
    }
    for &t in groups.remainder() {
        out.push(alone(m, t));
    }
}

/// One sample by the scalar path (out of line: the batch's code is large already).
#[inline(never)]
fn alone(m: &ExplicitMotion<DoubleDouble>, t: f64) -> BodyState<DoubleDouble> {
    m.body_at_f64(t)
}

/// The states of four times (the body of [`super::fast`]'s `body_in_turns` in four lanes).
#[inline(always)]
fn body4(m: &ExplicitMotion<DoubleDouble>, ts: [f64; LANES]) -> [BodyState<DoubleDouble>; LANES] {
    let Some([k1, k2]) = m.clock.as_ref().and_then(|c| c.turns()) else {
        return ts.map(|t| alone(m, t));
    };
    // Lanes the scalar path takes elsewhere get a harmless phase here and their state alone.
    let (phi1, none1) = turns_at4(k1, ts);
    let (phi2, none2) = turns_at4(k2, ts);
    let mut lone: [bool; LANES] = std::array::from_fn(|i| none1[i] | none2[i]);
    let (s1, c1) = phi1.sin_cos_turns();
    let (s2, c2) = phi2.sin_cos_turns();
    for (i, lone) in lone.iter_mut().enumerate() {
        let (a, b) = (Real::to_f64(&s1.lane(i)), Real::to_f64(&s2.lane(i)));
        *lone |= (a.abs() < 1e-30) | (b.abs() < 1e-30);
    }
    if every_lane(lone) {
        return ts.map(|t| alone(m, t));
    }
    let (v1, v2) = (&m.first, &m.second);
    let ((q1, p1), (q2, p2)) =
        EllipticModulus::sn_cn_ratio_pair4(&v1.modulus, (s1, c1), &v2.modulus, (s2, c2));
    let x1 = v1.eval::<DoubleDouble4>(&q1, &p1);
    let x2 = v2.eval::<DoubleDouble4>(&q2, &p2);
    let point = SeparatedCoordinates::new(x1, x2);
    let formula = m.formula.map(|x| DoubleDouble4::splat(*x));
    let products = m.products.map(|x| DoubleDouble4::splat(*x));
    let b = body_state_with(&formula, &products, &point);
    std::array::from_fn(|i| {
        if lone[i] {
            alone(m, ts[i])
        } else {
            BodyState {
                omega: b.omega.map(|x| x.lane(i)),
                alpha: b.alpha.map(|x| x.lane(i)),
                beta: b.beta.map(|x| x.lane(i)),
            }
        }
    })
}

#[cfg(test)]
mod tests;
