//! The integral constants (m, h) of the invariant manifold N, the admissible region, the
//! bifurcation diagram Σ and the roots of the separated polynomials (seed sec. 1 and 3).

use rsts_dynamics::Real;
use serde::Serialize;

use crate::error::ClosedFormError;
use crate::roots::{Root, RootLabel};
use crate::separated::Radicand;

/// a, b, m, h and the quantities derived from them.
#[derive(Clone, Debug)]
pub struct IntegralConstants<T> {
    pub a: T,
    pub b: T,
    pub m: T,
    pub h: T,
    /// p² = a² + b².
    pub p2: T,
    /// r² = a² − b².
    pub r2: T,
    /// r = √(a² − b²).
    pub r: T,
    /// ℓ ≥ 0, ℓ² = 2p²m² + 2hm + 1 (eq. 1.2).
    pub ell: T,
    /// p²m + h = (ℓ² − 1)/(2m), computed without dividing by m.
    pub pmh: T,
}

/// One curve of the bifurcation diagram Σ (seed sec. 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum SigmaCurve {
    /// h = r²m − 2a (outer boundary, a root of Φ at ±a).
    OuterA,
    /// h = −r²m − 2b (outer boundary, a root of Φ at ±b).
    OuterB,
    /// 2p²m² + 2hm + 1 = 0, m < 0 (ℓ = 0: θ₁ = −θ₂; beyond it ℓ is not real).
    Hyperbola,
    /// h = r²m + 2a (inside, a root of Φ at ±a).
    InnerA,
    /// h = −r²m + 2b (inside, a root of Φ at ±b).
    InnerB,
}

impl SigmaCurve {
    pub const ALL: [SigmaCurve; 5] = [
        SigmaCurve::OuterA,
        SigmaCurve::OuterB,
        SigmaCurve::Hyperbola,
        SigmaCurve::InnerA,
        SigmaCurve::InnerB,
    ];

    pub fn equation(&self) -> &'static str {
        match self {
            SigmaCurve::OuterA => "h = r²m − 2a",
            SigmaCurve::OuterB => "h = −r²m − 2b",
            SigmaCurve::Hyperbola => "2p²m² + 2hm + 1 = 0 (ℓ = 0)",
            SigmaCurve::InnerA => "h = r²m + 2a",
            SigmaCurve::InnerB => "h = −r²m + 2b",
        }
    }
}

impl<T: Real> IntegralConstants<T> {
    /// Checked constants: a > b > 0, (m, h) admissible and not on Σ.
    pub fn new(a: T, b: T, m: T, h: T) -> Result<Self, ClosedFormError> {
        for (name, v) in [("a", &a), ("b", &b), ("m", &m), ("h", &h)] {
            if !v.is_finite() {
                return Err(ClosedFormError::Parameters(format!(
                    "{name} is not a finite number"
                )));
            }
        }
        let zero = a.zero_like();
        if !(b > zero && a > b) {
            return Err(ClosedFormError::Parameters(format!(
                "the closed form needs a > b > 0 (got a = {}, b = {}); b = 0 (Kovalevskaya) and b = a (Yehia) are reducible cases without the manifold N of this solution",
                a.to_f64(),
                b.to_f64()
            )));
        }
        let c = Self::unchecked(a, b, m, h);
        c.check_admissible()?;
        c.check_off_sigma()?;
        Ok(c)
    }

    /// The same constants in another scalar (each stored number mapped).
    pub fn map<U: Real>(&self, f: &impl Fn(&T) -> U) -> IntegralConstants<U> {
        IntegralConstants {
            a: f(&self.a),
            b: f(&self.b),
            m: f(&self.m),
            h: f(&self.h),
            p2: f(&self.p2),
            r2: f(&self.r2),
            r: f(&self.r),
            ell: f(&self.ell),
            pmh: f(&self.pmh),
        }
    }

    /// The derived quantities without checks (for drawing the diagram).
    pub fn unchecked(a: T, b: T, m: T, h: T) -> Self {
        let p2 = a.square() + b.square();
        let r2 = a.square() - b.square();
        let ell2 = Self::ell2_of(&p2, &m, &h);
        let ell = ell2.max_of(a.zero_like()).sqrt();
        let pmh = p2.clone() * &m + &h;
        Self {
            r: r2.sqrt(),
            a,
            b,
            m,
            h,
            p2,
            r2,
            ell,
            pmh,
        }
    }

    fn ell2_of(p2: &T, m: &T, h: &T) -> T {
        let two = m.lit(2.0);
        two.clone() * p2 * m * m + two * h * m + m.one_like()
    }

    /// ℓ² = 2p²m² + 2hm + 1.
    pub fn ell2(&self) -> T {
        Self::ell2_of(&self.p2, &self.m, &self.h)
    }

    /// Signed residual of each curve of Σ at (m, h) (zero on the curve).
    pub fn sigma_residual(&self, curve: SigmaCurve) -> T {
        let two = self.a.lit(2.0);
        let rm = self.r2.clone() * &self.m;
        match curve {
            SigmaCurve::OuterA => self.h.clone() - (rm - two * &self.a),
            SigmaCurve::OuterB => self.h.clone() + rm + two * &self.b,
            SigmaCurve::Hyperbola => self.ell2(),
            SigmaCurve::InnerA => self.h.clone() - rm - two * &self.a,
            SigmaCurve::InnerB => self.h.clone() + rm - two * &self.b,
        }
    }

    /// Scale of the terms of each residual, for a relative test.
    fn sigma_scale(&self) -> T {
        let two = self.a.lit(2.0);
        self.h.abs()
            + self.r2.clone() * self.m.abs()
            + two * &self.a
            + self.p2.clone() * self.m.square()
            + self.a.one_like()
    }

    fn check_admissible(&self) -> Result<(), ClosedFormError> {
        let zero = self.a.zero_like();
        let (m, h) = (self.m.to_f64(), self.h.to_f64());
        if self.ell2() < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "ℓ² = 2p²m² + 2hm + 1 = {:e} < 0 at m = {m}, h = {h}: beyond the hyperbola 2p²m² + 2hm + 1 = 0",
                self.ell2().to_f64()
            )));
        }
        if self.sigma_residual(SigmaCurve::OuterA) < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "h = {h} is below the boundary line h = r²m − 2a = {} at m = {m}",
                (self.r2.clone() * &self.m - self.a.lit(2.0) * &self.a).to_f64()
            )));
        }
        if self.sigma_residual(SigmaCurve::OuterB) < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "h = {h} is below the boundary line h = −r²m − 2b = {} at m = {m}",
                (-(self.r2.clone() * &self.m) - self.b.lit(2.0) * &self.b).to_f64()
            )));
        }
        Ok(())
    }

    fn check_off_sigma(&self) -> Result<(), ClosedFormError> {
        let tol = self.a.epsilon() * self.a.lit(16.0) * self.sigma_scale();
        for curve in SigmaCurve::ALL {
            if self.sigma_residual(curve).abs() <= tol {
                return Err(ClosedFormError::OnSigma(format!(
                    "the curve {} (residual {:e})",
                    curve.equation(),
                    self.sigma_residual(curve).to_f64()
                )));
            }
        }
        Ok(())
    }

    /// θ₁ = (ℓ − 1)/(2m) = (p²m + h)/(ℓ + 1) and θ₂ = (ℓ + 1)/(2m), the roots of Φ (sec. 3), in
    /// homogeneous form [n : d].
    pub fn thetas(&self) -> [(T, T); 2] {
        let one = self.a.one_like();
        let l1 = self.ell.clone() + &one;
        [
            (self.pmh.clone(), l1.clone()),
            (l1, self.m.clone() * one.lit(2.0)),
        ]
    }

    /// The radicands (F₁*², G₁*²) of x = 1/s₁: −Φ*(x) = −(2/(ℓ+1))·L_{1/θ₁}(x)·L_{1/θ₂}(x) and
    /// 1 − a²x² = −(ax − 1)(ax + 1).
    pub fn radicands_x(&self) -> (Radicand<T>, Radicand<T>) {
        let one = self.a.one_like();
        let [(t1n, t1d), (t2n, t2d)] = self.thetas();
        let f = Radicand {
            name: "F1*",
            c: -(one.lit(2.0) / (self.ell.clone() + &one)),
            roots: [
                Root::new(RootLabel::Theta1, t1d, t1n),
                Root::new(RootLabel::Theta2, t2d, t2n),
            ],
        };
        let g = Radicand {
            name: "G1*",
            c: -one.clone(),
            roots: [
                Root::new(RootLabel::PlusA, one.clone(), self.a.clone()),
                Root::new(RootLabel::MinusA, -one, self.a.clone()),
            ],
        };
        (f, g)
    }

    /// The radicands (F₂², G₂²) of s₂: Φ(s) = (2/(ℓ+1))·L_{θ₁}(s)·L_{θ₂}(s) and
    /// b² − s² = −(s − b)(s + b).
    pub fn radicands_s2(&self) -> (Radicand<T>, Radicand<T>) {
        let one = self.a.one_like();
        let [(t1n, t1d), (t2n, t2d)] = self.thetas();
        let f = Radicand {
            name: "F2",
            c: one.lit(2.0) / (self.ell.clone() + &one),
            roots: [
                Root::new(RootLabel::Theta1, t1n, t1d),
                Root::new(RootLabel::Theta2, t2n, t2d),
            ],
        };
        let g = Radicand {
            name: "G2",
            c: -one.clone(),
            roots: [
                Root::new(RootLabel::PlusB, self.b.clone(), one.clone()),
                Root::new(RootLabel::MinusB, -self.b.clone(), one),
            ],
        };
        (f, g)
    }
}
