//! The seed's explicit formulas, rewritten in x = 1/s₁, F₁* = F₁/s₁, G₁* = G₁/s₁ (the device of
//! eq. 3.2): multiply numerator and denominator of each formula by the power of x that makes it
//! polynomial. With D = 1 − x s₂ (so s₁ − s₂ = D/x; D ≥ 1 − b/a > 0) and
//! Ψ* = xΨ = 4ms₂ − 2ℓ(1 + xs₂) + 2(p²m + h)x, nothing is singular when s₁ passes through ∞
//! and nothing divides by m. Each function names the equation it implements; every formula is
//! checked against the Euler–Poisson equations in the tests (see docs/closed-form.md for the
//! corrections to the printed text).

use rsts_dynamics::vec3::{Mat3, Vec3};
use rsts_dynamics::Real;

use crate::separated::SeparatedPoint;

/// The constants the formulas use, in the evaluation scalar.
#[derive(Clone, Debug)]
pub struct FormulaConstants<S> {
    pub a: S,
    pub b: S,
    pub m: S,
    pub ell: S,
    pub r: S,
    /// p²m + h.
    pub pmh: S,
}

impl<S> FormulaConstants<S> {
    /// The same constants in another scalar (each number mapped by `g`).
    pub(crate) fn map<U>(&self, g: impl Fn(&S) -> U) -> FormulaConstants<U> {
        FormulaConstants {
            a: g(&self.a),
            b: g(&self.b),
            m: g(&self.m),
            ell: g(&self.ell),
            r: g(&self.r),
            pmh: g(&self.pmh),
        }
    }
}

/// The products of the constants that every point uses (a², b², ab, 2m, 4m, 2ℓ, 2(p²m + h)),
/// formed once per motion ([`body_state_with`]): the numbers each point formed before, so the
/// state is the same bit for bit.
#[derive(Clone, Debug)]
pub struct ConstantProducts<S> {
    a2: S,
    b2: S,
    ab: S,
    two_m: S,
    four_m: S,
    two_ell: S,
    two_pmh: S,
}

impl<S> ConstantProducts<S> {
    /// The same products in another scalar (each number mapped by `g`).
    pub(crate) fn map<U>(&self, g: impl Fn(&S) -> U) -> ConstantProducts<U> {
        ConstantProducts {
            a2: g(&self.a2),
            b2: g(&self.b2),
            ab: g(&self.ab),
            two_m: g(&self.two_m),
            four_m: g(&self.four_m),
            two_ell: g(&self.two_ell),
            two_pmh: g(&self.two_pmh),
        }
    }
}

impl<S: Real> ConstantProducts<S> {
    pub fn new(c: &FormulaConstants<S>) -> Self {
        let two_m = twice(&c.m);
        Self {
            a2: c.a.square(),
            b2: c.b.square(),
            ab: c.a.clone() * &c.b,
            four_m: twice(&two_m),
            two_m,
            two_ell: twice(&c.ell),
            two_pmh: twice(&c.pmh),
        }
    }
}

/// The point (x, s₂, F₁*, G₁*, F₂, G₂) of N in separated variables.
#[derive(Clone, Debug)]
pub struct SeparatedCoordinates<S> {
    pub x: S,
    pub s2: S,
    pub f1: S,
    pub g1: S,
    pub f2: S,
    pub g2: S,
}

impl<S: Real> SeparatedCoordinates<S> {
    #[inline(always)]
    pub fn new(first: SeparatedPoint<S>, second: SeparatedPoint<S>) -> Self {
        Self {
            x: first.v,
            f1: first.f,
            g1: first.g,
            s2: second.v,
            f2: second.f,
            g2: second.g,
        }
    }
}

/// Everything the closed form gives at one point.
#[derive(Clone, Debug)]
pub struct ExplicitState<S> {
    pub coords: SeparatedCoordinates<S>,
    /// ω (eq. 1.4).
    pub omega: Vec3<S>,
    /// α (eq. 1.3).
    pub alpha: Vec3<S>,
    /// β (eq. 1.3).
    pub beta: Vec3<S>,
    /// γ (eq. 2.5, with the corrected γ₃).
    pub gamma: Vec3<S>,
    /// Ω (eq. 3.1).
    pub omega_fixed: Vec3<S>,
    /// Q′ (sec. 2).
    pub q_prime: Mat3<S>,
    /// Q″ (sec. 2).
    pub q_second: Mat3<S>,
    /// ω′ (eq. 2.6).
    pub omega_prime: Vec3<S>,
    /// ω″₍₁₎ (eq. 2.8).
    pub omega_second_1: Vec3<S>,
    /// ω″₍₂₎ (eq. 2.8).
    pub omega_second_2: Vec3<S>,
}

impl<S: Real> ExplicitState<S> {
    /// Q with rows α, β, γ.
    pub fn orientation(&self) -> Mat3<S> {
        [self.alpha.clone(), self.beta.clone(), self.gamma.clone()]
    }
}

/// The state of the body alone: ω, α, β (eqs. 1.3, 1.4) — what a row of the reference needs
/// (γ = α × β; H, K, G are constants of the motion).
#[derive(Clone, Debug)]
pub struct BodyState<S> {
    pub omega: Vec3<S>,
    pub alpha: Vec3<S>,
    pub beta: Vec3<S>,
}

/// The pieces the formulas share: powers of the constants, the reciprocals of the
/// denominators and the products of the radicals.
///
/// Every formula divides by one of d, 2d, ad, bd, abd, 2ad², 2bd², 2abd² (d = 1 − xs₂ > 0,
/// a > b > 0): one division q = 1/(abd) gives all of them as products, so the ~33 quotients
/// of the formulas are multiplications (a few ulp of extra rounding; the cost of a state in
/// MPFR and f64 is dominated by divisions otherwise).
struct Shared<S> {
    one: S,
    a2: S,
    b2: S,
    inv_abd: S,
    inv_ad: S,
    inv_bd: S,
    inv_d: S,
    inv_two_d: S,
    inv_two_a_d2: S,
    inv_two_b_d2: S,
    two_m: S,
    /// Ψ* = 4ms₂ − 2ℓ(1 + xs₂) + 2(p²m + h)x
    psi: S,
    g1g2: S,
    f1f2: S,
    f1g2: S,
    f2g1: S,
    rg1: S,
    /// α₃ = Q″₁₃ and β₃ = Q″₂₃.
    alpha3: S,
    beta3: S,
    f1g2_f2g1: S,
}

/// 2v exactly, by an addition (cheaper than a multiplication in MPFR).
#[inline(always)]
fn twice<S: Real>(v: &S) -> S {
    v.clone() + v
}

impl<S: Real> Shared<S> {
    #[inline(always)]
    fn new(c: &FormulaConstants<S>, k: &ConstantProducts<S>, p: &SeparatedCoordinates<S>) -> Self {
        let one = p.x.one_like();
        let half = one.lit(0.5);
        let (a, b, r) = (&c.a, &c.b, &c.r);
        let (x, s2, f1, g1, f2, g2) = (&p.x, &p.s2, &p.f1, &p.g1, &p.f2, &p.g2);
        let (a2, b2, ab) = (k.a2.clone(), k.b2.clone(), &k.ab);
        let xs2 = x.clone() * s2;
        let d = one.clone() - &xs2;
        // Reciprocals of the denominators from q = 1/(abd).
        let inv_abd = one.clone() / (ab.clone() * &d);
        let inv_ad = inv_abd.clone() * b;
        let inv_bd = inv_abd.clone() * a;
        let inv_d = inv_abd.clone() * ab;
        let inv_two_d = inv_d.clone() * &half;
        let inv_two_a_d2 = inv_ad.clone() * &inv_two_d;
        let inv_two_b_d2 = inv_bd.clone() * &inv_two_d;
        let two_m = k.two_m.clone();
        let psi = k.four_m.clone() * s2 - k.two_ell.clone() * (one.clone() + &xs2)
            + k.two_pmh.clone() * x;
        let f1g2 = f1.clone() * g2;
        let f2g1 = f2.clone() * g1;
        let rg1 = r.clone() * g1;
        let alpha3 = rg1.clone() * &inv_ad;
        let beta3 = r.clone() * x * g2 * &inv_bd;
        Self {
            a2,
            b2,
            inv_abd,
            inv_ad,
            inv_bd,
            inv_d,
            inv_two_d,
            inv_two_a_d2,
            inv_two_b_d2,
            two_m,
            psi,
            g1g2: g1.clone() * g2,
            f1f2: f1.clone() * f2,
            f1g2_f2g1: f1g2.clone() + &f2g1,
            f1g2,
            f2g1,
            rg1,
            alpha3,
            beta3,
            one,
        }
    }

    /// ω (eq. 1.4), α and β (eq. 1.3).
    #[inline(always)]
    fn body(&self, c: &FormulaConstants<S>, p: &SeparatedCoordinates<S>) -> BodyState<S> {
        let (ell, r) = (&c.ell, &c.r);
        let (x, s2, f1, f2) = (&p.x, &p.s2, &p.f1, &p.f2);
        let (psi, f1f2) = (&self.psi, &self.f1f2);
        let gf = self.g1g2.clone() * f1f2;
        let pg = psi.clone() * &self.g1g2;
        let sa = s2.clone() - self.a2.clone() * x; // (s₁s₂ − a²)·x
        let sb = s2.clone() - self.b2.clone() * x; // (s₁s₂ − b²)·x
        BodyState {
            alpha: [
                (sa.clone() * psi + &gf) * &self.inv_two_a_d2,
                (sa * f1f2 - &pg) * &self.inv_two_a_d2,
                self.alpha3.clone(),
            ],
            beta: [
                (pg - sb.clone() * f1f2) * &self.inv_two_b_d2,
                (sb * psi + &gf) * &self.inv_two_b_d2,
                self.beta3.clone(),
            ],
            omega: [
                r.clone() * (ell.clone() * x - &self.two_m) * f2 * &self.inv_two_d,
                r.clone() * (ell.clone() - self.two_m.clone() * s2) * f1 * &self.inv_two_d,
                -(self.f1g2_f2g1.clone()) * &self.inv_d,
            ],
        }
    }
}

/// ω, α, β at a point: the part of [`explicit_state`] a state of the body needs (about half
/// its products).
#[inline(always)]
pub fn body_state<S: Real>(c: &FormulaConstants<S>, p: &SeparatedCoordinates<S>) -> BodyState<S> {
    body_state_with(c, &ConstantProducts::new(c), p)
}

/// [`body_state`] with the products of the constants formed beforehand.
#[inline(always)]
pub fn body_state_with<S: Real>(
    c: &FormulaConstants<S>,
    k: &ConstantProducts<S>,
    p: &SeparatedCoordinates<S>,
) -> BodyState<S> {
    Shared::new(c, k, p).body(c, p)
}

/// Evaluate all formulas at a point.
#[inline(always)]
pub fn explicit_state<S: Real>(
    c: &FormulaConstants<S>,
    p: SeparatedCoordinates<S>,
) -> ExplicitState<S> {
    let sh = Shared::new(c, &ConstantProducts::new(c), &p);
    let BodyState { omega, alpha, beta } = sh.body(c, &p);
    let one = sh.one.clone();
    let two = one.lit(2.0);
    let (a2, b2, r) = (&sh.a2, &sh.b2, &c.r);
    let (x, s2, f1, g1, f2, g2) = (&p.x, &p.s2, &p.f1, &p.g1, &p.f2, &p.g2);
    let (psi, g1g2, f1f2) = (&sh.psi, &sh.g1g2, &sh.f1f2);
    let (inv_abd, inv_ad, inv_bd, inv_two_d) = (&sh.inv_abd, &sh.inv_ad, &sh.inv_bd, &sh.inv_two_d);
    let inv_two_ab_d2 = inv_abd.clone() * inv_two_d;
    let a2s2x = a2.clone() * s2 * x;
    // Entries that occur twice below (γ₃ = Q″₃₃, −Ψ*/2d).
    let gamma3 = (b2.clone() - &a2s2x) * inv_abd;
    let psi_2d = -(psi.clone()) * inv_two_d;
    // eq. (2.5)
    let gamma = [
        -(r.clone() * (s2.clone() * g1 * psi + g2.clone() * f1f2)) * &inv_two_ab_d2,
        -(r.clone() * (s2.clone() * g1 * f1f2 - g2.clone() * psi)) * &inv_two_ab_d2,
        // Printed with 2ab(s₁ − s₂) in the denominator: a typo, γ₃ = α₁β₂ − α₂β₁ needs ab(s₁ − s₂)
        // (docs/closed-form.md, correction 1).
        gamma3.clone(),
    ];
    // eq. (3.1)
    let omega_fixed = [
        -(r.clone() * (g1.clone() * f1 * g2 - (a2.clone() * x * x + s2.clone() * x - &two) * f2))
            * &sh.inv_two_a_d2,
        -(r.clone() * (x.clone() * g1g2 * f2 + ((b2.clone() - twice(s2) * s2) * x + s2) * f1))
            * &sh.inv_two_b_d2,
        -((b2.clone() + a2.clone() * (one.clone() - twice(s2) * x)) * f1 * g2
            - (a2s2x - b2.clone() * (two.clone() - s2.clone() * x)) * g1 * f2)
            * &inv_two_ab_d2,
    ];
    // Q′ and Q″ (sec. 2)
    let zero = one.zero_like();
    let f1f2_2d = f1f2.clone() * inv_two_d;
    let q_prime = [
        [psi_2d.clone(), -(f1f2_2d.clone()), zero.clone()],
        [f1f2_2d, psi_2d, zero.clone()],
        [zero.clone(), zero.clone(), one.clone()],
    ];
    // b·X/(abd) = X/(ad), a·X/(abd) = X/(bd).
    let q_second = [
        [
            (a2.clone() * x - s2) * inv_ad,
            g1g2.clone() * inv_ad,
            sh.alpha3.clone(),
        ],
        [
            -(g1g2.clone() * inv_bd),
            (b2.clone() * x - s2) * inv_bd,
            sh.beta3.clone(),
        ],
        [
            sh.rg1.clone() * s2 * inv_abd,
            -(r.clone() * g2) * inv_abd,
            gamma3,
        ],
    ];
    // eqs. (2.6), (2.8)
    let omega_prime = [
        zero.clone(),
        zero.clone(),
        -(sh.f1g2_f2g1.clone()) * inv_two_d,
    ];
    let omega_second_1 = [
        zero.clone(),
        r.clone() * f1 * inv_two_d,
        -(sh.f1g2.clone()) * inv_two_d,
    ];
    let omega_second_2 = [
        -(f2.clone() * r * x) * inv_two_d,
        zero,
        -(sh.f2g1.clone()) * inv_two_d,
    ];
    ExplicitState {
        coords: p,
        omega,
        alpha,
        beta,
        gamma,
        omega_fixed,
        q_prime,
        q_second,
        omega_prime,
        omega_second_1,
        omega_second_2,
    }
}
