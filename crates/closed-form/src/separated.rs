//! One separated variable and its two radicals: the oscillation segment, the elliptic
//! parametrisation and the radicals as analytic functions of the angle on the torus.
//!
//! A separated variable v (v = x = 1/s₁ for the first one — the seed's device of eq. (3.2), which
//! keeps v bounded when s₁ passes through infinity — and v = s₂ for the second) obeys
//! `2v̇ = ε·F·G`, with ε = −1 for x and +1 for s₂, where F² and G² are quadratics in v:
//!
//! ```text
//!   x = 1/s₁:  F₁*² = −Φ*(x) = −(4m − 4ℓx + 2(p²m+h)x²),  G₁*² = 1 − a²x²        (F₁* = F₁/s₁, G₁* = G₁/s₁)
//!   s₂:        F₂²  =  Φ(s₂) = 4ms₂² − 4ℓs₂ + 2(p²m+h),   G₂²  = b² − s₂²
//! ```
//!
//! (eq. 1.5 and the definitions of sec. 1, with (ℓ²−1)/m rewritten as 2p²m + 2h so nothing is
//! divided by m). v oscillates on a segment [λ, μ] between two adjacent roots of Q = F²G², and
//! the two other roots ν (next after μ on the projective line) and κ (before λ) are passive.
//! The Möbius map w = (v−λ)(μ−κ)/((v−κ)(μ−λ)) brings 4v̇² = Q(v) to Legendre form with
//! w = sn²(u), u = u̇·t + u₀, and
//!
//! ```text
//!   k²  = (ν−κ)(μ−λ)/((ν−λ)(μ−κ)),   k′² = (ν−μ)(λ−κ)/((ν−λ)(μ−κ)),   u̇² = K̃ (μ−κ)(ν−λ)/16,
//! ```
//!
//! where Q(v) = K̃ (v−λ)(μ−v)(ν−v)(v−κ) (all in homogeneous form, see [`crate::roots`]). Then
//! v = (λ L_κ(μ) cn² + μ L_κ(λ) sn²)/(L_κ(μ) cn² + L_κ(λ) sn²) is a positive-weight average, and
//! √(v−λ) ∝ sn u, √(μ−v) ∝ cn u: the sign changes of the radicals at the turning points come out
//! of the parametrisation, with no event detection.

use rsts_dynamics::Real;

use crate::elliptic::EllipticModulus;
use crate::error::ClosedFormError;
use crate::roots::{Root, RootLabel};

/// A radicand R² = c·L₁(v)·L₂(v) with its two roots.
#[derive(Clone, Debug)]
pub struct Radicand<T> {
    pub name: &'static str,
    pub c: T,
    pub roots: [Root<T>; 2],
}

impl<T: Real> Radicand<T> {
    pub fn at(&self, v: &T) -> T {
        self.c.clone() * self.roots[0].lin(v) * self.roots[1].lin(v)
    }
}

/// How one linear factor of a radical is evaluated along the segment.
#[derive(Clone, Debug)]
enum Factor<T> {
    /// The factor vanishing at λ: |L(v)| = coef·L_κ(λ)·sn²/den, sign carried by sn.
    Lambda { coef: T },
    /// The factor vanishing at μ: |L(v)| = coef·L_κ(μ)·cn²/den, sign carried by cn.
    Mu { coef: T },
    /// A passive factor: L(v) = (L(λ)·L_κ(μ)cn² + L(μ)·L_κ(λ)sn²)/den, never zero on the segment.
    Passive { at_lambda: T, at_mu: T },
}

#[derive(Clone, Debug)]
struct RadicalShape<T> {
    /// |c|·Π over the active factors of coef·|L_κ(λ or μ)|: the constant part of R² times den².
    scale: T,
    /// √scale when both factors are active (the radical then needs no square root).
    root_scale: Option<T>,
    factors: [Factor<T>; 2],
    /// Constant sign σ of the radical (±1).
    sigma: T,
}

/// A separated variable on its oscillation segment, with the torus's sign choice made.
#[derive(Clone, Debug)]
pub struct SeparatedVariable<T> {
    /// "x = 1/s1" or "s2".
    pub name: &'static str,
    pub lambda: Root<T>,
    pub mu: Root<T>,
    pub nu: Root<T>,
    pub kappa: Root<T>,
    lambda_v: T,
    mu_v: T,
    lk_lambda: T,
    lk_mu: T,
    shapes: [RadicalShape<T>; 2],
    pub modulus: EllipticModulus<T>,
    /// du/dt.
    pub u_dot: T,
    /// Whether one radical holds both turning points, so the other one has a free constant sign
    /// (two tori from this variable) and the state has period 2K in u instead of 4K.
    pub free_sign: bool,
}

/// The values at one point: v and the two radicals (F, G).
#[derive(Clone, Debug)]
pub struct SeparatedPoint<S> {
    pub v: S,
    pub f: S,
    pub g: S,
}

/// Candidate oscillation segments of a variable: bounded intervals between consecutive finite
/// roots on which both radicands are positive.
pub fn segments<T: Real>(f: &Radicand<T>, g: &Radicand<T>) -> Vec<(Root<T>, Root<T>)> {
    let mut finite: Vec<Root<T>> = f
        .roots
        .iter()
        .chain(g.roots.iter())
        .filter(|r| !r.is_infinite())
        .cloned()
        .collect();
    finite.sort_by(|p, q| {
        p.value()
            .partial_cmp(&q.value())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut out = Vec::new();
    for w in finite.windows(2) {
        let (lo, hi) = (w[0].value(), w[1].value());
        if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
            continue;
        }
        let mid = (lo + &hi) / hi.lit(2.0);
        let zero = mid.zero_like();
        if f.at(&mid) > zero && g.at(&mid) > zero {
            out.push((w[0].clone(), w[1].clone()));
        }
    }
    out
}

impl<T: Real> SeparatedVariable<T> {
    /// Build the parametrisation for the segment [λ, μ] of the radicands (F, G) with
    /// 2v̇ = ε·F·G (`epsilon` = ±1). `sign_choice` picks the free constant sign (+1 or −1) when
    /// there is one and is ignored otherwise.
    pub fn new(
        name: &'static str,
        f: &Radicand<T>,
        g: &Radicand<T>,
        segment: (Root<T>, Root<T>),
        epsilon: i32,
        sign_choice: i32,
    ) -> Result<Self, ClosedFormError> {
        let (lambda, mu) = segment;
        let is = |r: &Root<T>, l: RootLabel| r.label == l;
        let passive: Vec<Root<T>> = f
            .roots
            .iter()
            .chain(g.roots.iter())
            .filter(|r| !is(r, lambda.label) && !is(r, mu.label))
            .cloned()
            .collect();
        if passive.len() != 2 {
            return Err(ClosedFormError::Internal(format!(
                "{name}: expected two passive roots, got {}",
                passive.len()
            )));
        }
        let lambda_v = lambda.value();
        let mu_v = mu.value();
        // Cyclic order from μ upwards: roots above μ first (increasing), then ∞, then those below λ.
        let key = |r: &Root<T>| -> (u8, f64) {
            if r.is_infinite() {
                (1, 0.0)
            } else if r.above(&mu_v) {
                (0, r.value_f64())
            } else {
                (2, r.value_f64())
            }
        };
        let (nu, kappa) = {
            let (p, q) = (passive[0].clone(), passive[1].clone());
            let (kp, kq) = (key(&p), key(&q));
            let p_first = if kp.0 != kq.0 {
                kp.0 < kq.0
            } else {
                p.value() <= q.value()
            };
            if p_first {
                (p, q)
            } else {
                (q, p)
            }
        };
        let lk_lambda = kappa.lin(&lambda_v);
        let lk_mu = kappa.lin(&mu_v);
        let ln_lambda = nu.lin(&lambda_v);
        let ln_mu = nu.lin(&mu_v);
        let width = mu_v.clone() - &lambda_v;
        let nu_minus_kappa = nu.n.clone() * &kappa.d - kappa.n.clone() * &nu.d;
        let denom = -(ln_lambda.clone()) * &lk_mu;
        let k2 = nu_minus_kappa * &width / &denom;
        let kc2 = -(ln_mu) * &lk_lambda / &denom;
        let zero = k2.zero_like();
        let one = k2.one_like();
        if !(k2 >= zero && kc2 > zero && k2 < one) {
            return Err(ClosedFormError::Internal(format!(
                "{name}: modulus out of range (k² = {}, k′² = {})",
                k2.to_f64(),
                kc2.to_f64()
            )));
        }
        let modulus = EllipticModulus::new(k2, kc2);

        let shape = |r: &Radicand<T>| -> [Factor<T>; 2] {
            std::array::from_fn(|j| {
                let root = &r.roots[j];
                if root.label == lambda.label {
                    Factor::Lambda {
                        coef: root.d.abs() * &width,
                    }
                } else if root.label == mu.label {
                    Factor::Mu {
                        coef: root.d.abs() * &width,
                    }
                } else {
                    Factor::Passive {
                        at_lambda: root.lin(&lambda_v),
                        at_mu: root.lin(&mu_v),
                    }
                }
            })
        };
        let actives = |fs: &[Factor<T>; 2]| {
            fs.iter()
                .filter(|x| !matches!(x, Factor::Passive { .. }))
                .count()
        };
        let (ff, gf) = (shape(f), shape(g));
        let free_sign = actives(&ff) == 2 || actives(&gf) == 2;
        // σ_F σ_G = ε (sign of 2v̇ = ε F G against sn·cn); the free sign sits on the radical without
        // turning points.
        let (sf, sg) = if !free_sign {
            (1, epsilon)
        } else if actives(&ff) == 0 {
            (sign_choice, epsilon * sign_choice)
        } else {
            (epsilon * sign_choice, sign_choice)
        };
        // u̇² = K̃·L_κ(μ)·(−L_ν(λ))/16, K̃ = c_F c_G d_λ d_μ.
        let k_tilde = f.c.clone() * &g.c * &lambda.d * &mu.d;
        let u_dot2 = k_tilde * &lk_mu * (-(ln_lambda)) / one.lit(16.0);
        if u_dot2.partial_cmp(&zero) != Some(std::cmp::Ordering::Greater) {
            return Err(ClosedFormError::Internal(format!(
                "{name}: non-positive frequency² {}",
                u_dot2.to_f64()
            )));
        }
        let u_dot = u_dot2.sqrt();
        let radical_shape = |c: &T, factors: [Factor<T>; 2], sigma: i32| {
            let mut scale = c.abs();
            for fac in &factors {
                match fac {
                    Factor::Lambda { coef } => scale *= coef.clone() * lk_lambda.abs(),
                    Factor::Mu { coef } => scale *= coef.clone() * lk_mu.abs(),
                    Factor::Passive { .. } => {}
                }
            }
            let root_scale = (actives(&factors) == 2).then(|| scale.sqrt());
            RadicalShape {
                scale,
                root_scale,
                factors,
                sigma: one.lit(f64::from(sigma)),
            }
        };
        let shapes = [radical_shape(&f.c, ff, sf), radical_shape(&g.c, gf, sg)];
        Ok(Self {
            name,
            lambda,
            mu,
            nu,
            kappa,
            lambda_v,
            mu_v,
            lk_lambda,
            lk_mu,
            shapes,
            modulus,
            u_dot,
            free_sign,
        })
    }

    /// The same variable in another scalar (each stored number mapped).
    pub fn map<U: Real>(&self, f: &impl Fn(&T) -> U) -> SeparatedVariable<U> {
        let factor = |x: &Factor<T>| match x {
            Factor::Lambda { coef } => Factor::Lambda { coef: f(coef) },
            Factor::Mu { coef } => Factor::Mu { coef: f(coef) },
            Factor::Passive { at_lambda, at_mu } => Factor::Passive {
                at_lambda: f(at_lambda),
                at_mu: f(at_mu),
            },
        };
        let shape = |s: &RadicalShape<T>| RadicalShape {
            scale: f(&s.scale),
            root_scale: s.root_scale.as_ref().map(f),
            factors: [factor(&s.factors[0]), factor(&s.factors[1])],
            sigma: f(&s.sigma),
        };
        SeparatedVariable {
            name: self.name,
            lambda: self.lambda.map(f),
            mu: self.mu.map(f),
            nu: self.nu.map(f),
            kappa: self.kappa.map(f),
            lambda_v: f(&self.lambda_v),
            mu_v: f(&self.mu_v),
            lk_lambda: f(&self.lk_lambda),
            lk_mu: f(&self.lk_mu),
            shapes: [shape(&self.shapes[0]), shape(&self.shapes[1])],
            modulus: self.modulus.map(f),
            u_dot: f(&self.u_dot),
            free_sign: self.free_sign,
        }
    }

    /// Period in u of the state along this variable: 2K when one radical holds both turning
    /// points (the state depends on sn·cn and sn², cn² only), 4K otherwise.
    pub fn period_u(&self) -> T {
        let k = self.modulus.big_k.clone();
        if self.free_sign {
            k.lit(2.0) * k
        } else {
            k.lit(4.0) * k
        }
    }

    /// The constant signs (σ_F, σ_G) in use.
    pub fn signs(&self) -> (i32, i32) {
        let s = |x: &T| if x.to_f64() > 0.0 { 1 } else { -1 };
        (s(&self.shapes[0].sigma), s(&self.shapes[1].sigma))
    }

    /// The segment [λ, μ] as values.
    pub fn segment(&self) -> (T, T) {
        (self.lambda_v.clone(), self.mu_v.clone())
    }

    /// The inverse of [`Self::eval`]: the parameter u ∈ [0, period_u) of the point (v, F, G), or
    /// `None` when a constant sign of the point differs from this torus's (the point lies on
    /// another torus). v is clamped to the segment; a radical's sign is read as + at 0.
    ///
    /// sn² u = L_κ(μ)(v − λ)/(L_κ(μ)(v − λ) + L_κ(λ)(μ − v)) and cn² u = 1 − sn² u invert the
    /// positive-weight average of [`Self::eval`]; the signs of sn and cn are those of the radicals
    /// that vanish at λ and at μ, divided by their constant signs σ.
    pub fn u_of(&self, p: &SeparatedPoint<T>) -> Option<T> {
        let zero = p.v.zero_like();
        let v =
            p.v.clone()
                .max_of(self.lambda_v.clone())
                .min_of(self.mu_v.clone());
        let wl = self.lk_mu.clone() * (v.clone() - &self.lambda_v);
        let wm = self.lk_lambda.clone() * (self.mu_v.clone() - &v);
        let den = wl.clone() + &wm;
        let sn_abs = (wl / &den).abs().sqrt();
        let cn_abs = (wm / &den).abs().sqrt();
        let sign = |x: &T| x.to_f64() >= 0.0;
        let mut sn_positive = true;
        let mut cn_positive = true;
        for (shape, value) in self.shapes.iter().zip([&p.f, &p.g]) {
            let s = sign(value) == sign(&shape.sigma);
            let has_lambda = shape
                .factors
                .iter()
                .any(|x| matches!(x, Factor::Lambda { .. }));
            let has_mu = shape.factors.iter().any(|x| matches!(x, Factor::Mu { .. }));
            match (has_lambda, has_mu) {
                (true, false) => sn_positive = s,
                (false, true) => cn_positive = s,
                // Both turning points in this radical: it carries sn·cn; take sn ≥ 0 (the state
                // has period 2K in u).
                (true, true) => cn_positive = s,
                (false, false) => {
                    if !s {
                        return None;
                    }
                }
            }
        }
        let sn = if sn_positive { sn_abs } else { -sn_abs };
        let cn = if cn_positive { cn_abs } else { -cn_abs };
        let u = self.modulus.u_of(&sn, &cn);
        let period = self.period_u();
        let u = if u >= period { u - &period } else { u };
        Some(u.max_of(zero))
    }

    /// v, F, G at a point of the parametrisation given by sn u and cn u, in any scalar `S` that
    /// embeds `T` (e.g. dual numbers for derivatives along the flow).
    ///
    /// With w_λ = L_κ(μ)cn², w_μ = L_κ(λ)sn² and den = w_λ + w_μ (never 0: the weights have one
    /// sign): v = (λw_λ + μw_μ)/den, and a radical R = σ·√(|c|·|L₁(v)|·|L₂(v)|) with each active
    /// factor |L| = coef·|L_κ|·(sn² or cn²)/|den| and each passive one |λ-value·w_λ + μ-value·w_μ|/|den|:
    /// R = σ·(sn or cn per active factor)·√(scale·Π|passive numerators|)/|den|, where the
    /// constant `scale` (and its root when both factors are active) is computed once with the
    /// motion. One division and at most one square root per radical.
    #[inline(always)]
    pub fn eval<S: Real + From<T>>(&self, sn: &S, cn: &S) -> SeparatedPoint<S> {
        let wl = up::<T, S>(&self.lk_mu) * cn * cn;
        let wm = up::<T, S>(&self.lk_lambda) * sn * sn;
        let den = wl.clone() + &wm;
        let inv_den = den.one_like() / &den;
        let v = (up::<T, S>(&self.lambda_v) * &wl + up::<T, S>(&self.mu_v) * &wm) * &inv_den;
        let inv_den = inv_den.abs();
        let w = Weights {
            sn,
            cn,
            wl: &wl,
            wm: &wm,
        };
        SeparatedPoint {
            f: radical(&self.shapes[0], &w) * &inv_den,
            g: radical(&self.shapes[1], &w) * &inv_den,
            v,
        }
    }
}

/// A constant of the motion in the evaluation scalar.
#[inline(always)]
fn up<T: Clone, S: From<T>>(x: &T) -> S {
    S::from(x.clone())
}

/// sn, cn and the weights w_λ, w_μ of a point (see [`SeparatedVariable::eval`]).
struct Weights<'a, S> {
    sn: &'a S,
    cn: &'a S,
    wl: &'a S,
    wm: &'a S,
}

/// A radical times |den|: σ·(sn or cn per active factor)·√(scale·Π|passive numerators|).
/// (A function, not a closure, so that it inlines into the FMA build of the state.)
#[inline(always)]
fn radical<T: Real, S: Real + From<T>>(shape: &RadicalShape<T>, w: &Weights<'_, S>) -> S {
    let mut sign = up::<T, S>(&shape.sigma);
    let mut passive: Option<S> = None;
    for fac in &shape.factors {
        match fac {
            Factor::Lambda { .. } => sign *= w.sn,
            Factor::Mu { .. } => sign *= w.cn,
            Factor::Passive { at_lambda, at_mu } => {
                let num = (up::<T, S>(at_lambda) * w.wl + up::<T, S>(at_mu) * w.wm).abs();
                passive = Some(match passive {
                    None => num,
                    Some(p) => p * num,
                });
            }
        }
    }
    let root = match (&shape.root_scale, passive) {
        (Some(r), _) => up::<T, S>(r),
        (None, Some(p)) => (p * up::<T, S>(&shape.scale)).sqrt(),
        (None, None) => up::<T, S>(&shape.scale).sqrt(),
    };
    sign * root
}
