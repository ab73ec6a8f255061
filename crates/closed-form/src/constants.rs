//! The integral constants (m, h) of the invariant manifold N, the admissible region, the
//! bifurcation diagram Σ and the roots of the separated polynomials (seed sec. 1 and 3).

use rsts_dynamics::Real;
use serde::Serialize;

use crate::error::ClosedFormError;
use crate::roots::{Root, RootLabel};
use crate::separated::Radicand;

/// Smallest and largest field strength a accepted.
pub const A_RANGE: (f64, f64) = (1e-6, 1e6);
/// b/a must lie in [B_OVER_A_MIN, 1 − B_OVER_A_MIN]: b → 0 (Kowalevski) and b → a (Yehia) are the
/// reducible limits without N, and near them r² = a² − b² or b loses the digits of the inputs.
pub const B_OVER_A_MIN: f64 = 1e-6;
/// |m|·p and |h|/p (p = √(a² + b²), the dimensionless values: m scales like 1/p and h like p)
/// must not exceed this. Measured: at |m|·p = 10⁶ the closed form still agrees with dop853 to
/// 1e-13 over short times; beyond, the invariants (of size (p m)²) lose their digits in f64.
pub const MH_SCALE_MAX: f64 = 1e6;

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

/// The documented ranges of a, b, m, h ([`A_RANGE`], [`B_OVER_A_MIN`], [`MH_SCALE_MAX`]), checked
/// after a > b > 0 (pass m = h = 0 to check the fields alone).
pub fn check_ranges<T: Real>(a: &T, b: &T, m: &T, h: &T) -> Result<(), ClosedFormError> {
    let short = rsts_dynamics::short;
    let (a, b, m, h) = (a.to_f64(), b.to_f64(), m.to_f64(), h.to_f64());
    let (lo, hi) = A_RANGE;
    if !(lo..=hi).contains(&a) {
        return Err(ClosedFormError::Range(
            "a",
            format!(
                "a = {} is outside [{}, {}] (the problem scales: a = 1 loses nothing)",
                short(a),
                short(lo),
                short(hi)
            ),
        ));
    }
    let ratio = b / a;
    if !(B_OVER_A_MIN..=1.0 - B_OVER_A_MIN).contains(&ratio) {
        return Err(ClosedFormError::Range(
            "b",
            format!(
                "b/a = {} is outside [{}, 1 − {}]: too close to b = 0 (Kowalevski) or b = a \
                 (Yehia) for the digits of f64",
                short(ratio),
                short(B_OVER_A_MIN),
                short(B_OVER_A_MIN)
            ),
        ));
    }
    let p = (a * a + b * b).sqrt();
    let m_max = MH_SCALE_MAX / p;
    if m.is_nan() || m.abs() > m_max {
        return Err(ClosedFormError::Range(
            "m",
            format!(
                "|m| = {} exceeds {} (|m|·p ≤ {} with p = √(a² + b²) = {})",
                short(m.abs()),
                short(m_max),
                short(MH_SCALE_MAX),
                short(p)
            ),
        ));
    }
    let h_max = MH_SCALE_MAX * p;
    if h.is_nan() || h.abs() > h_max {
        return Err(ClosedFormError::Range(
            "h",
            format!(
                "|h| = {} exceeds {} (|h| ≤ {}·p with p = √(a² + b²) = {})",
                short(h.abs()),
                short(h_max),
                short(MH_SCALE_MAX),
                short(p)
            ),
        ));
    }
    Ok(())
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
                rsts_dynamics::short(a.to_f64()),
                rsts_dynamics::short(b.to_f64())
            )));
        }
        check_ranges(&a, &b, &m, &h)?;
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

    /// Scale of the terms of the residual of `curve` (the sum of their magnitudes), for a
    /// relative test.
    fn sigma_scale(&self, curve: SigmaCurve) -> T {
        let two = self.a.lit(2.0);
        let line = self.h.abs() + self.r2.clone() * self.m.abs();
        match curve {
            SigmaCurve::OuterA | SigmaCurve::InnerA => line + two * &self.a,
            SigmaCurve::OuterB | SigmaCurve::InnerB => line + two * &self.b,
            SigmaCurve::Hyperbola => {
                two.clone() * &self.p2 * self.m.square()
                    + two * (self.h.clone() * &self.m).abs()
                    + self.a.one_like()
            }
        }
    }

    /// Relative size of the rounding the inputs carry: that of f64 when a, b, m, h are all f64
    /// numbers (they were typed as decimals and rounded to f64, even when the computation runs
    /// in more bits), else that of the scalar.
    fn input_epsilon(&self) -> T {
        let is_f64 = |x: &T| {
            let y = x.lit(x.to_f64());
            (x.clone() - &y).abs() <= x.zero_like()
        };
        let eps = self.a.epsilon();
        if [&self.a, &self.b, &self.m, &self.h].into_iter().all(is_f64) {
            eps.max_of(self.a.lit(f64::EPSILON))
        } else {
            eps
        }
    }

    fn check_admissible(&self) -> Result<(), ClosedFormError> {
        let zero = self.a.zero_like();
        let short = |x: &T| rsts_dynamics::short(x.to_f64());
        let (m, h) = (short(&self.m), short(&self.h));
        if self.ell2() < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "ℓ² = 2p²m² + 2hm + 1 = {} < 0 at m = {m}, h = {h}: beyond the hyperbola 2p²m² + 2hm + 1 = 0",
                short(&self.ell2())
            )));
        }
        if self.sigma_residual(SigmaCurve::OuterA) < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "h = {h} is below the boundary line h = r²m − 2a = {} at m = {m}",
                short(&(self.r2.clone() * &self.m - self.a.lit(2.0) * &self.a))
            )));
        }
        if self.sigma_residual(SigmaCurve::OuterB) < zero {
            return Err(ClosedFormError::NotAdmissible(format!(
                "h = {h} is below the boundary line h = −r²m − 2b = {} at m = {m}",
                short(&(-(self.r2.clone() * &self.m) - self.b.lit(2.0) * &self.b))
            )));
        }
        Ok(())
    }

    /// A point within rounding of the inputs of a curve of Σ is on Σ: |residual| ≤ 16·ε·scale,
    /// with ε the relative rounding of the inputs ([`Self::input_epsilon`]) and scale the sum
    /// of the magnitudes of the curve's terms. Every curve the point is on is named.
    fn check_off_sigma(&self) -> Result<(), ClosedFormError> {
        let eps = self.input_epsilon() * self.a.lit(16.0);
        let on: Vec<String> = SigmaCurve::ALL
            .into_iter()
            .filter_map(|curve| {
                let r = self.sigma_residual(curve);
                let tol = eps.clone() * self.sigma_scale(curve);
                (r.abs() <= tol).then(|| {
                    format!(
                        "{} {} (residual {}, within the rounding of the inputs: {})",
                        if curve == SigmaCurve::Hyperbola {
                            "the hyperbola"
                        } else {
                            "the line"
                        },
                        curve.equation(),
                        rsts_dynamics::short(r.to_f64()),
                        rsts_dynamics::short(tol.to_f64())
                    )
                })
            })
            .collect();
        if on.is_empty() {
            Ok(())
        } else {
            Err(ClosedFormError::OnSigma(on.join(" and ")))
        }
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
