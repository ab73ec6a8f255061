//! The tori of one (m, h) are images of one another under symmetries of the Euler–Poisson
//! equations (docs/closed-form.md, "The tori are mirror images").
//!
//! Two sign changes of the state (ω, α, β) map solutions to solutions, forward in time:
//!
//! ```text
//!   S_x  = (ω₁, −ω₂, −ω₃, α₁, −α₂, −α₃, −β₁, β₂, β₃)    (the top half a turn about its axis e₁,
//!   S_s2 = (−ω₁, ω₂, −ω₃, α₁, −α₂, α₃, −β₁, β₂, −β₃)     the whole half a turn about a field)
//! ```
//!
//! (each term of the equations changes sign with its left-hand side). In the explicit solution
//! S_x is the sign change of both radicals (F₁*, G₁*) of x = 1/s₁, S_s2 that of (F₂, G₂): the
//! torus whose free sign of x (of s₂) is − is the image under S_x (S_s2) of the one where it is
//! +, at the same angles (ψ₁, ψ₂) and the same time. H, K, G are unchanged.

use super::ExplicitMotion;
use crate::scalar::Scalar;

/// S_x: the signs of (ω, α, β) that flip the free sign of x = 1/s₁.
pub const MIRROR_X: [i8; 9] = [1, -1, -1, 1, -1, -1, -1, 1, 1];
/// S_s2: the signs of (ω, α, β) that flip the free sign of s₂.
pub const MIRROR_S2: [i8; 9] = [-1, 1, -1, 1, -1, 1, -1, 1, -1];

/// The constant signs of the free radicals (x, s₂) of torus `j` of a pair of segments: bit 0 is
/// the sign of x when x has a free sign, the next bit that of s₂ (bit clear: +, set: −).
pub(crate) fn free_signs(j: usize, free1: bool, free2: bool) -> (i32, i32) {
    let n1 = if free1 { 2 } else { 1 };
    let n2 = if free2 { 2 } else { 1 };
    (
        if j % n1 == 1 { -1 } else { 1 },
        if (j / n1) % n2 == 1 { -1 } else { 1 },
    )
}

impl<T: Scalar> ExplicitMotion<T> {
    /// The signs (ω, α, β) that map the state of torus 0 onto this motion's torus at the same
    /// angles and time: S_x when its free sign of x is −, S_s2 when that of s₂ is −, both
    /// composed, or all + (torus 0).
    pub fn torus_image_signs(&self) -> [i8; 9] {
        let (f1, f2) = (self.first.free_sign, self.second.free_sign);
        let pairs = if f1 { 2 } else { 1 } * if f2 { 2 } else { 1 };
        let (sign1, sign2) = free_signs(self.choice.torus % pairs, f1, f2);
        std::array::from_fn(|k| {
            let x = if sign1 < 0 { MIRROR_X[k] } else { 1 };
            let s = if sign2 < 0 { MIRROR_S2[k] } else { 1 };
            x * s
        })
    }
}
