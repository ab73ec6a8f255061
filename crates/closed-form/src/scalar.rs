//! Scalars the closed form runs in: any [`Real`] that converts to and from MPFR, so that the
//! constants of a motion (roots, moduli, frequencies) are computed 64 bits beyond the working
//! precision and rounded once, and the phase u = u₀ + u̇t is reduced modulo the period in that
//! extra precision. Near Σ (roots nearly coincident) and at long times (t = 1e6) the working
//! precision is then not eroded by cancellation in the constants or by the size of u̇t.

use rsts_dynamics::Real;
use rug::Float;

/// Guard bits for the constants and the phase.
pub const GUARD_BITS: u32 = 64;

/// A [`Real`] that converts to and from `rug::Float`.
pub trait Scalar: Real {
    /// Round an MPFR number to this type at `bits` bits.
    fn from_mpfr(x: &Float, bits: u32) -> Self;
    /// The exact value as an MPFR number of `bits` bits.
    fn to_mpfr(&self, bits: u32) -> Float;
}

impl Scalar for f64 {
    fn from_mpfr(x: &Float, _bits: u32) -> Self {
        x.to_f64()
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, *self)
    }
}

impl Scalar for Float {
    fn from_mpfr(x: &Float, bits: u32) -> Self {
        Float::with_val(bits, x)
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, self)
    }
}
