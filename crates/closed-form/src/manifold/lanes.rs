//! Six f64 values, one per direction of the gain (stop 31): [`super::field_derivative`] computes
//! the derivative of X_Φ along the gain's six directions lane by lane, each lane the operations
//! of the one-direction formulas in the same order (so the same bits), written so that the
//! compiler keeps the six lanes in vector registers.

use std::ops::{Add, Mul, Neg, Sub};

/// One value per direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes(pub [f64; 6]);

impl Lanes {
    /// The same value in every lane.
    #[inline(always)]
    pub fn splat(x: f64) -> Self {
        Self([x; 6])
    }
}

impl Add for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn add(self, o: Lanes) -> Lanes {
        Lanes(std::array::from_fn(|j| self.0[j] + o.0[j]))
    }
}

impl Sub for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn sub(self, o: Lanes) -> Lanes {
        Lanes(std::array::from_fn(|j| self.0[j] - o.0[j]))
    }
}

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        Lanes(self.0.map(|x| -x))
    }
}

impl Mul for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn mul(self, o: Lanes) -> Lanes {
        Lanes(std::array::from_fn(|j| self.0[j] * o.0[j]))
    }
}

/// Lanes × a scalar (a product is the same bits in either order).
impl Mul<f64> for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn mul(self, s: f64) -> Lanes {
        Lanes(self.0.map(|x| x * s))
    }
}

impl Mul<Lanes> for f64 {
    type Output = Lanes;
    #[inline(always)]
    fn mul(self, l: Lanes) -> Lanes {
        l * self
    }
}

/// u·v (left to right, as `rsts_dynamics::vec3::dot`).
#[inline(always)]
pub fn dot<A: Copy + Mul<B, Output = Lanes>, B: Copy>(u: &[A; 3], v: &[B; 3]) -> Lanes {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// u×v (as `rsts_dynamics::vec3::cross`).
#[inline(always)]
pub fn cross<A: Copy + Mul<B, Output = Lanes>, B: Copy>(u: &[A; 3], v: &[B; 3]) -> [Lanes; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}
