//! Identify a state: (ω, α, β) with the fields (a, b) → (m, h, camera, torus, ψ₁, ψ₂), the
//! inverse of the closed form (issue 11), in any [`Scalar`] (f64 or `rug::Float` at D digits).
//!
//! 1. h = H, m = (2G − p²H)/r⁴ (regular everywhere; equal to the partial integral M on N).
//! 2. The separated variables from the state, with no division that degenerates where s₁
//!    passes through infinity. From eqs. (1.3), (1.4), (2.5) in x = 1/s₁, with D = 1 − x s₂,
//!    W = Ψ* + i F₁* F₂ (|W| = 2D), χ = ξ₁ + iξ₂, η = (aα₁ + bβ₂) + i(aα₂ − bβ₁):
//!
//!    ```text
//!      D = r²/(a(a − bγ₃)),   χ = −r² x W/(2D²),   η = W (2s₂ − p²x − 2i G₁* G₂)/(2D²),
//!      Z = w² + χ = r²m W²/(4D²)        (Q = Z χ̄/χ = r²m on N)
//!    ```
//!
//!    so e^{iθ} = W/|W| is known up to its sign σ from Z (or from χ/|χ| when r²|m| is small),
//!    and then x = −D Re(χ e^{−iθ})/r², s₂ = (D Re(η e^{−iθ}) + p²x)/2. The sign σ and the
//!    signs of the four radicals are those of the candidate whose formula state is nearest.
//! 3. Each variable's parameter u from (v, F, G) ([`SeparatedVariable::u_of`]); a constant sign
//!    that differs from torus 0's picks the other torus of that variable (the tori are numbered by
//!    these signs, [`crate::TorusChoice`]); ψᵢ = 2π uᵢ / Pᵢ.
//! 4. Gauss–Newton on ψ minimising |state − closed form(ψ)| (Jacobian by dual numbers): the
//!    phases of a state off N are those of the nearest point of its own torus.

use std::fmt;

use rsts_dynamics::dual::Dual;
use rsts_dynamics::state::DIM;
use rsts_dynamics::{Fields, Real, State};

use crate::camera::Camera;
use crate::constants::IntegralConstants;
use crate::error::ClosedFormError;
use crate::formulas::{explicit_state, SeparatedCoordinates};
use crate::manifold::distance::{distance, DistanceFromN};
use crate::manifold::relations::m_of_integrals;
use crate::manifold::torus_map::{
    formula_constants, gauss_newton_step, max_gap, phase_vector, seeded, TorusMap,
};
use crate::motion::{ExplicitMotion, TorusChoice};
use crate::scalar::Scalar;
use crate::separated::{SeparatedPoint, SeparatedVariable};

/// What [`identify`] found.
#[derive(Clone, Debug)]
pub struct Identified<T> {
    /// m = (2G − p²H)/r⁴ and h = H of the state.
    pub m: T,
    pub h: T,
    pub camera: Camera,
    /// Number of tori of the integral manifold (m, h) and the state's torus (0-based).
    pub tori: usize,
    pub torus: usize,
    /// The angles (ψ₁, ψ₂) ∈ [0, 2π)² on the torus: the closed form at these angles is the state
    /// (for a state off N: the nearest point of the torus). Same convention as
    /// [`crate::TorusChoice`]: ψᵢ(t) = ψᵢ⁰ + νᵢ t.
    pub phases: [T; 2],
    /// d(x) = |X_Φ(x)|, absolute and relative ([`crate::manifold::distance`]).
    pub distance: DistanceFromN<T>,
    /// max over the nine components of |state − closed form(m, h, torus, ψ₁, ψ₂)|.
    pub residual: T,
}

/// Why a state could not be identified.
#[derive(Clone, Debug, PartialEq)]
pub enum IdentifyError {
    /// a, b or the state are not acceptable (non-finite, a ≤ b, b ≤ 0, |α|, |β| ≠ 1, α·β ≠ 0).
    Input(String),
    /// (m, h) of the state has no torus of N: outside the admissible region or on Σ. The
    /// distance from N is given: a state far from N has (m, h) anywhere.
    NoTorus {
        m: f64,
        h: f64,
        distance: f64,
        reason: ClosedFormError,
    },
}

impl fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentifyError::Input(s) => f.write_str(s),
            IdentifyError::NoTorus {
                m,
                h,
                distance,
                reason,
            } => write!(
                f,
                "the state's (m, h) = ({m}, {h}) has no torus of N (relative distance from N {distance:e}): {reason}"
            ),
        }
    }
}

impl std::error::Error for IdentifyError {}

/// √max(0, y).
fn root<T: Real>(y: T) -> T {
    let zero = y.zero_like();
    y.max_of(zero).sqrt()
}

/// The two candidates (σ = ±1) for (x, s₂) of a state (module docs, step 2).
fn separated_estimates<T: Real>(c: &IntegralConstants<T>, s: &State<T>) -> [(T, T); 2] {
    let (a, b) = (&c.a, &c.b);
    let [w1, w2, _] = &s.omega;
    let gamma3 = s.alpha[0].clone() * &s.beta[1] - s.alpha[1].clone() * &s.beta[0];
    let xi = [
        a.clone() * &s.alpha[0] - b.clone() * &s.beta[1],
        a.clone() * &s.alpha[1] + b.clone() * &s.beta[0],
    ];
    let eta = [
        a.clone() * &s.alpha[0] + b.clone() * &s.beta[1],
        a.clone() * &s.alpha[1] - b.clone() * &s.beta[0],
    ];
    let d = c.r2.clone() / (a.clone() * (a.clone() - b.clone() * &gamma3));
    let rho = (xi[0].square() + xi[1].square()).sqrt();
    let z = [
        w1.square() - w2.square() + &xi[0],
        w1.lit(2.0) * w1 * w2 + &xi[1],
    ];
    // e^{2iθ} from Z = r²m e^{2iθ}, or from χ² = |χ|² e^{2iθ}: whichever is larger relative to
    // the round-off of its terms.
    let w_size = a.one_like() + w1.square() + w2.square();
    let from_z = c.r2.clone() * c.m.abs() / &w_size >= rho.clone() / a;
    let (c2, s2) = if from_z {
        let sign = if c.m < c.m.zero_like() { -1.0 } else { 1.0 };
        (z[0].clone() * a.lit(sign), z[1].clone() * a.lit(sign))
    } else {
        (
            xi[0].square() - xi[1].square(),
            a.lit(2.0) * &xi[0] * &xi[1],
        )
    };
    let theta = s2.atan2(&c2) / a.lit(2.0);
    let e = [theta.cos(), theta.sin()];
    [1.0, -1.0].map(|sigma| {
        let (er, ei) = (e[0].clone() * a.lit(sigma), e[1].clone() * a.lit(sigma));
        let chi_e = xi[0].clone() * &er + xi[1].clone() * &ei;
        let eta_e = eta[0].clone() * &er + eta[1].clone() * &ei;
        let x = -(d.clone() * chi_e) / &c.r2;
        let s2 = (d.clone() * eta_e + c.p2.clone() * &x) / a.lit(2.0);
        (x, s2)
    })
}

/// The separated coordinates (with the signs of the radicals) whose formula state is nearest to
/// `s`, on the segments of `motion` (module docs, step 2).
fn separated_coordinates<T: Real>(
    motion: &ExplicitMotion<T>,
    s: &State<T>,
) -> SeparatedCoordinates<T> {
    let c = &motion.constants;
    let (f1r, g1r) = c.radicands_x();
    let (f2r, g2r) = c.radicands_s2();
    let (l1, m1) = motion.first.segment();
    let (l2, m2) = motion.second.segment();
    let target = s.to_array();
    let formula = formula_constants(c);
    let mut best: Option<(T, SeparatedCoordinates<T>)> = None;
    for (x, s2) in separated_estimates(c, s) {
        let x = x.max_of(l1.clone()).min_of(m1.clone());
        let s2 = s2.max_of(l2.clone()).min_of(m2.clone());
        let mags = [
            root(f1r.at(&x)),
            root(g1r.at(&x)),
            root(f2r.at(&s2)),
            root(g2r.at(&s2)),
        ];
        for signs in 0..16u32 {
            let signed: [T; 4] = std::array::from_fn(|k| {
                if signs & (1 << k) != 0 {
                    -mags[k].clone()
                } else {
                    mags[k].clone()
                }
            });
            let [f1, g1, f2, g2] = signed;
            let coords = SeparatedCoordinates {
                x: x.clone(),
                s2: s2.clone(),
                f1,
                g1,
                f2,
                g2,
            };
            let y = phase_vector(&explicit_state(&formula, coords.clone()));
            let err = max_gap(&y, &target);
            if best.as_ref().is_none_or(|(e, _)| err < *e) {
                best = Some((err, coords));
            }
        }
    }
    best.expect("32 candidates").1
}

/// Check a, b and the state (finite, a > b > 0 within the documented ranges of a and b/a,
/// |α| = |β| = 1 and α·β = 0 within 1e-9).
fn check_input<T: Real>(a: &T, b: &T, s: &State<T>) -> Result<(), IdentifyError> {
    for (name, v) in [("a", a), ("b", b)] {
        if !v.is_finite() {
            return Err(IdentifyError::Input(format!(
                "{name} is not a finite number"
            )));
        }
    }
    if !(*b > b.zero_like() && a > b) {
        return Err(IdentifyError::Input(format!(
            "identifying a state needs a > b > 0 (got a = {}, b = {})",
            a.to_f64(),
            b.to_f64()
        )));
    }
    // The documented ranges of a and b/a, as for every other use of the closed form (beyond
    // them the search for the torus ran for minutes: a = 1e300).
    crate::constants::check_ranges(a, b, &a.zero_like(), &a.zero_like())
        .map_err(|e| IdentifyError::Input(e.to_string()))?;
    s.validate()
        .map_err(|e| IdentifyError::Input(e.to_string()))
}

/// Identify the state `s` for the fields (a, b): its (m, h), camera, torus and angles, the
/// distance from N and the residual of the closed form at what was found. Works in the precision
/// of the inputs (f64, or `rug::Float` at any number of bits).
///
/// Errors: [`IdentifyError::Input`] for non-finite numbers, a ≤ b or b ≤ 0, a or b/a outside
/// the documented ranges ([`crate::check_ranges`]), or a state off the
/// constraints |α| = |β| = 1, α·β = 0 (1e-9); [`IdentifyError::NoTorus`] when (m, h) is outside
/// the admissible region or on Σ (with the distance from N: a state far from N lands anywhere).
pub fn identify<T: Scalar>(a: &T, b: &T, s: &State<T>) -> Result<Identified<T>, IdentifyError> {
    check_input(a, b, s)?;
    let fields = Fields {
        a: a.clone(),
        b: b.clone(),
    };
    let h = rsts_dynamics::integrals::energy(&fields, s);
    let m = m_of_integrals(&fields, s);
    let dist = distance(&fields, s);
    let motion = ExplicitMotion::new(
        a.clone(),
        b.clone(),
        m.clone(),
        h.clone(),
        TorusChoice::default(),
    )
    .map_err(|reason| IdentifyError::NoTorus {
        m: m.to_f64(),
        h: h.to_f64(),
        distance: dist.relative.to_f64(),
        reason,
    })?;
    let coords = separated_coordinates(&motion, s);
    let (torus, map) = torus_of(&motion, &coords).map_err(|reason| IdentifyError::NoTorus {
        m: m.to_f64(),
        h: h.to_f64(),
        distance: dist.relative.to_f64(),
        reason,
    })?;
    let guess = map
        .angles_of(&coords)
        .expect("torus_of picked the torus whose signs these are");
    // The torus's own closed form (constants with guard bits, as every other use of it).
    let map = if torus == 0 {
        TorusMap::of_motion(&motion)
    } else {
        let choice = TorusChoice {
            torus,
            phase1: 0.0,
            phase2: 0.0,
        };
        let own = ExplicitMotion::new(a.clone(), b.clone(), m.clone(), h.clone(), choice).map_err(
            |reason| IdentifyError::NoTorus {
                m: m.to_f64(),
                h: h.to_f64(),
                distance: dist.relative.to_f64(),
                reason,
            },
        )?;
        TorusMap::of_motion(&own)
    };
    let target = s.to_array();
    let (phases, residual) = map.nearest(&target, &guess);
    let start = Nearest {
        m,
        h,
        phases,
        residual,
    };
    let best = nearest_on_n(a, b, torus, map, start, &target);
    Ok(Identified {
        m: best.m,
        h: best.h,
        camera: motion.camera,
        tori: motion.tori,
        torus,
        phases: best.phases,
        distance: dist,
        residual: best.residual,
    })
}

/// A point of N as (m, h, ψ₁, ψ₂) on a given torus, with its max-norm distance to the target.
#[derive(Clone, Debug)]
struct Nearest<T> {
    m: T,
    h: T,
    phases: [T; 2],
    residual: T,
}

/// ∂(state)/∂m or ∂/∂h at fixed angles.
fn derivative_in<T: Real>(
    a: &T,
    b: &T,
    p: &Nearest<T>,
    torus: usize,
    seed_m: bool,
) -> Option<[T; DIM]> {
    let map = seeded([a, b, &p.m, &p.h], torus, seed_m).ok()?;
    let x = map.state_at(&p.phases.clone().map(Dual::constant));
    Some(std::array::from_fn(|k| x[k].eps.clone()))
}

/// Gauss–Newton over (m, h, ψ₁, ψ₂) from `start` on the torus `torus`: the point of N nearest to
/// the target (its own (m, h) need not be the integrals' values when the state is not exactly on
/// N: near Σ a rounding of the state moves them by much more than it moves the state).
fn nearest_on_n<T: Scalar>(
    a: &T,
    b: &T,
    torus: usize,
    map: TorusMap<T>,
    start: Nearest<T>,
    target: &[T; DIM],
) -> Nearest<T> {
    let eps = a.epsilon();
    let mut best = start;
    let mut map = map;
    for _ in 0..6 {
        if best.residual <= eps.clone() * a.lit(2.0) {
            break;
        }
        let (x, jac) = map.state_and_jacobian(&best.phases);
        let (Some(jm), Some(jh)) = (
            derivative_in(a, b, &best, torus, true),
            derivative_in(a, b, &best, torus, false),
        ) else {
            break;
        };
        let r: [T; DIM] = std::array::from_fn(|k| x[k].clone() - &target[k]);
        let Some(step) = gauss_newton_step([&jac[0], &jac[1], &jm, &jh], &r) else {
            break;
        };
        let [d1, d2, dm, dh] = step;
        let trial_m = best.m.clone() + dm;
        let trial_h = best.h.clone() + dh;
        let Ok(motion) = ExplicitMotion::new(
            a.clone(),
            b.clone(),
            trial_m.clone(),
            trial_h.clone(),
            TorusChoice {
                torus,
                phase1: 0.0,
                phase2: 0.0,
            },
        ) else {
            break;
        };
        let trial_map = TorusMap::of_motion(&motion);
        let guess = [best.phases[0].clone() + d1, best.phases[1].clone() + d2];
        let (phases, residual) = trial_map.nearest(target, &guess);
        if residual >= best.residual {
            break;
        }
        // Less than halved: at the floor of the state's distance from N (see `nearest`).
        let stalled = residual.clone() * a.lit(2.0) > best.residual;
        best = Nearest {
            m: trial_m,
            h: trial_h,
            phases,
            residual,
        };
        map = trial_map;
        if stalled {
            break;
        }
    }
    best
}

/// The torus whose constant signs are those of `p`, as (index, map). Torus numbering as in
/// [`ExplicitMotion`]: bit 0 the free sign of x = 1/s₁, the next bit that of s₂ (set: −).
fn torus_of<T: Real>(
    motion: &ExplicitMotion<T>,
    p: &SeparatedCoordinates<T>,
) -> Result<(usize, TorusMap<T>), ClosedFormError> {
    let c = &motion.constants;
    let (f1r, g1r) = c.radicands_x();
    let (f2r, g2r) = c.radicands_s2();
    let n1 = if motion.first.free_sign { 2 } else { 1 };
    let n2 = if motion.second.free_sign { 2 } else { 1 };
    if n1 * n2 != motion.tori {
        return Err(ClosedFormError::Internal(format!(
            "{} tori but {n1}×{n2} sign choices",
            motion.tori
        )));
    }
    let points = [
        SeparatedPoint {
            v: p.x.clone(),
            f: p.f1.clone(),
            g: p.g1.clone(),
        },
        SeparatedPoint {
            v: p.s2.clone(),
            f: p.f2.clone(),
            g: p.g2.clone(),
        },
    ];
    let pick = |var: &SeparatedVariable<T>,
                point: &SeparatedPoint<T>,
                f: &crate::separated::Radicand<T>,
                g: &crate::separated::Radicand<T>,
                eps: i32|
     -> Result<(usize, SeparatedVariable<T>), ClosedFormError> {
        if var.u_of(point).is_some() {
            return Ok((0, var.clone()));
        }
        let other = SeparatedVariable::new(
            var.name,
            f,
            g,
            (var.lambda.clone(), var.mu.clone()),
            eps,
            -1,
        )?;
        Ok((1, other))
    };
    let (j1, v1) = pick(&motion.first, &points[0], &f1r, &g1r, -1)?;
    let (j2, v2) = pick(&motion.second, &points[1], &f2r, &g2r, 1)?;
    Ok((j1 + n1 * j2, TorusMap::new(c, [v1, v2])))
}
