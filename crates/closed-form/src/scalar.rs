//! Scalars the closed form runs in: any [`Real`] that converts to and from MPFR, so that the
//! constants of a motion (roots, moduli, frequencies) are computed 64 bits beyond the working
//! precision and rounded once, and the phase u = u₀ + u̇t is reduced modulo the period in that
//! extra precision. Near Σ (roots nearly coincident) and at long times (t = 1e6) the working
//! precision is then not eroded by cancellation in the constants or by the size of u̇t.
//!
//! Three scalars: `f64`, the double-double of rsts-dynamics (106 bits, the fast exact-enough
//! reference of f64 data, see [`crate::rounded`]) and `rug::Float` at any precision.

use rsts_dynamics::scalar::DoubleDouble;
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
    /// The time `self` as an f64 when the phase of this type is reduced by the double-double
    /// clock (f64 expansions, no MPFR) and `self` is an f64 exactly; `None`: reduce in MPFR.
    fn dd_clock_time(&self) -> Option<f64> {
        None
    }
    /// A phase from the double-double clock (only called when [`Self::dd_clock_time`] is
    /// `Some`).
    fn from_dd(x: DoubleDouble, bits: u32) -> Self {
        Self::from_mpfr(&x.to_float(bits.max(128)), bits)
    }
}

impl Scalar for f64 {
    fn from_mpfr(x: &Float, _bits: u32) -> Self {
        x.to_f64()
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, *self)
    }
}

impl Scalar for DoubleDouble {
    fn from_mpfr(x: &Float, _bits: u32) -> Self {
        DoubleDouble::from_float(x)
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        self.to_float(bits)
    }
    fn dd_clock_time(&self) -> Option<f64> {
        (self.lo == 0.0).then_some(self.hi)
    }
    fn from_dd(x: DoubleDouble, _bits: u32) -> Self {
        x
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
