//! A torus of N as a map (ψ₁, ψ₂) → (ω, α, β), its derivative by dual numbers, its inverse on
//! separated coordinates and the nearest point of it to a state (Gauss–Newton).

use rsts_dynamics::dual::Dual;
use rsts_dynamics::jet::Jet;
use rsts_dynamics::state::DIM;
use rsts_dynamics::Real;

use crate::constants::IntegralConstants;
use crate::error::ClosedFormError;
use crate::formulas::{explicit_state, ExplicitState, FormulaConstants, SeparatedCoordinates};
use crate::motion::ExplicitMotion;
use crate::separated::{SeparatedPoint, SeparatedVariable};

/// A torus of N as a map (ψ₁, ψ₂) → state, with its derivative.
#[derive(Clone, Debug)]
pub struct TorusMap<T> {
    formula: FormulaConstants<T>,
    pub vars: [SeparatedVariable<T>; 2],
}

impl<T: Real> TorusMap<T> {
    /// The torus of a closed-form motion.
    pub fn of_motion(motion: &ExplicitMotion<T>) -> Self {
        Self::new(
            &motion.constants,
            [motion.first.clone(), motion.second.clone()],
        )
    }

    pub(crate) fn new(c: &IntegralConstants<T>, vars: [SeparatedVariable<T>; 2]) -> Self {
        Self {
            formula: formula_constants(c),
            vars,
        }
    }

    fn two_pi(&self) -> T {
        T::pi(self.formula.a.prec()) * self.formula.a.lit(2.0)
    }

    /// The formula constants of the torus.
    pub(crate) fn formula(&self) -> &FormulaConstants<T> {
        &self.formula
    }

    /// The point (v, F, G) of separated variable `i` at its angle ψᵢ.
    pub fn point(&self, i: usize, psi: &T) -> SeparatedPoint<T> {
        let v = &self.vars[i];
        let u = psi.clone() * v.period_u() / &self.two_pi();
        let (sn, cn) = v.modulus.sn_cn(&u);
        v.eval::<T>(&sn, &cn)
    }

    /// The phase vector (ω, α, β) at the angles (ψ₁, ψ₂).
    pub fn state_at(&self, psi: &[T; 2]) -> [T; DIM] {
        let two_pi = self.two_pi();
        let points: [SeparatedPoint<T>; 2] = std::array::from_fn(|i| {
            let v = &self.vars[i];
            let u = psi[i].clone() * v.period_u() / &two_pi;
            let (sn, cn) = v.modulus.sn_cn(&u);
            v.eval::<T>(&sn, &cn)
        });
        let [p1, p2] = points;
        phase_vector(&explicit_state(
            &self.formula,
            SeparatedCoordinates::new(p1, p2),
        ))
    }

    /// The state at (ψ₁, ψ₂) and its derivatives ∂/∂ψ₁, ∂/∂ψ₂ (dual numbers through sn, cn).
    pub fn state_and_jacobian(&self, psi: &[T; 2]) -> ([T; DIM], [[T; DIM]; 2]) {
        let two_pi = self.two_pi();
        let parts: [(T, T, T, T); 2] = std::array::from_fn(|i| {
            let v = &self.vars[i];
            let du = v.period_u() / &two_pi;
            let (sn, cn, dn) = v.modulus.sn_cn_dn(&(psi[i].clone() * &du));
            (sn, cn, dn, du)
        });
        let fc = self.formula.map(|x| Dual::constant(x.clone()));
        let column = |k: usize| -> [Dual<T>; DIM] {
            let points: [SeparatedPoint<Dual<T>>; 2] = std::array::from_fn(|i| {
                let (sn, cn, dn, du) = &parts[i];
                let zero = sn.zero_like();
                let (dsn, dcn) = if i == k {
                    (cn.clone() * dn * du, -(sn.clone() * dn * du))
                } else {
                    (zero.clone(), zero)
                };
                self.vars[i]
                    .eval::<Dual<T>>(&Dual::new(sn.clone(), dsn), &Dual::new(cn.clone(), dcn))
            });
            let [p1, p2] = points;
            phase_vector(&explicit_state(&fc, SeparatedCoordinates::new(p1, p2)))
        };
        let c0 = column(0);
        let c1 = column(1);
        (
            std::array::from_fn(|j| c0[j].re.clone()),
            [
                std::array::from_fn(|j| c0[j].eps.clone()),
                std::array::from_fn(|j| c1[j].eps.clone()),
            ],
        )
    }

    /// The angles of the point of this torus nearest to `target`, by Gauss–Newton from `guess`,
    /// reduced to [0, 2π); with the max-norm residual |target − state(ψ)|.
    pub fn nearest(&self, target: &[T; DIM], guess: &[T; 2]) -> ([T; 2], T) {
        let eps = target[0].epsilon();
        let mut psi = guess.clone();
        let mut best = (psi.clone(), max_gap(&self.state_at(&psi), target));
        for _ in 0..12 {
            let (x, jac) = self.state_and_jacobian(&psi);
            let r: [T; DIM] = std::array::from_fn(|k| x[k].clone() - &target[k]);
            let Some([d1, d2]) = gauss_newton_step([&jac[0], &jac[1]], &r) else {
                break;
            };
            let step = d1.abs().max_of(d2.abs());
            psi = [psi[0].clone() + d1, psi[1].clone() + d2];
            let res = max_gap(&self.state_at(&psi), target);
            // Less than halved: the residual is at its floor, the target's own distance from
            // the torus (more steps only refine angles that distance already blurs, at a cost
            // that grows with the digits).
            let stalled = res.clone() * res.lit(2.0) > best.1;
            if res < best.1 {
                best = (psi.clone(), res);
            }
            if step <= eps.clone() * eps.lit(4.0) || stalled {
                break;
            }
        }
        let two_pi = self.two_pi();
        let (psi, res) = best;
        (psi.map(|p| wrap(p, &two_pi)), res)
    }

    /// The angles of a point of the torus given in separated coordinates (exact inverse of the
    /// parametrisation), or None when its constant signs are another torus's.
    pub(crate) fn angles_of(&self, p: &SeparatedCoordinates<T>) -> Option<[T; 2]> {
        let two_pi = self.two_pi();
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
        let u0 = self.vars[0].u_of(&points[0])?;
        let u1 = self.vars[1].u_of(&points[1])?;
        Some([
            u0 * &two_pi / self.vars[0].period_u(),
            u1 * &two_pi / self.vars[1].period_u(),
        ])
    }
}

/// x reduced to [0, period).
pub(crate) fn wrap<T: Real>(x: T, period: &T) -> T {
    let n = (x.clone() / period).floor();
    let y = x - n * period;
    if y >= *period || y < y.zero_like() {
        y.zero_like()
    } else {
        y
    }
}

pub(crate) fn formula_constants<T: Real>(c: &IntegralConstants<T>) -> FormulaConstants<T> {
    FormulaConstants {
        a: c.a.clone(),
        b: c.b.clone(),
        m: c.m.clone(),
        ell: c.ell.clone(),
        r: c.r.clone(),
        pmh: c.pmh.clone(),
    }
}

pub(crate) fn phase_vector<S: Real>(s: &ExplicitState<S>) -> [S; DIM] {
    let v = [&s.omega, &s.alpha, &s.beta];
    std::array::from_fn(|k| v[k / 3][k % 3].clone())
}

/// max over the components of |x − y|.
pub(crate) fn max_gap<T: Real>(x: &[T; DIM], y: &[T; DIM]) -> T {
    (0..DIM).fold(x[0].zero_like(), |acc, k| {
        acc.max_of((x[k].clone() - &y[k]).abs())
    })
}

/// One Gauss–Newton step for the residual r with Jacobian columns `cols`: the least-squares
/// solution of J·δ = −r by the normal equations (None: J is rank-deficient).
pub(crate) fn gauss_newton_step<T: Real, const N: usize>(
    cols: [&[T; DIM]; N],
    r: &[T; DIM],
) -> Option<[T; N]> {
    let dotn = |u: &[T; DIM], v: &[T; DIM]| {
        (0..DIM).fold(r[0].zero_like(), |acc, k| acc + u[k].clone() * &v[k])
    };
    let normal: [[T; N]; N] =
        std::array::from_fn(|i| std::array::from_fn(|j| dotn(cols[i], cols[j])));
    let rhs: [T; N] = std::array::from_fn(|i| -dotn(cols[i], r));
    solve(normal, rhs)
}

/// Solve the n×n system a·x = y by Gaussian elimination with partial pivoting (None: singular).
fn solve<T: Real, const N: usize>(mut a: [[T; N]; N], mut y: [T; N]) -> Option<[T; N]> {
    for col in 0..N {
        let pivot = (col..N).max_by(|&i, &j| {
            a[i][col]
                .abs()
                .partial_cmp(&a[j][col].abs())
                .unwrap_or(std::cmp::Ordering::Equal)
        })?;
        if a[pivot][col].abs().partial_cmp(&a[pivot][col].zero_like())
            != Some(std::cmp::Ordering::Greater)
        {
            return None;
        }
        a.swap(col, pivot);
        y.swap(col, pivot);
        for row in col + 1..N {
            let f = a[row][col].clone() / &a[col][col];
            let pivot_row = a[col].clone();
            for (x, p) in a[row].iter_mut().zip(&pivot_row).skip(col) {
                *x -= f.clone() * p;
            }
            let t = f * &y[col];
            y[row] -= t;
        }
    }
    let mut x = y.clone();
    for row in (0..N).rev() {
        let mut v = y[row].clone();
        for k in row + 1..N {
            v -= a[row][k].clone() * &x[k];
        }
        x[row] = v / &a[row][row];
    }
    Some(x)
}

/// The torus `torus` of (m, h) built over dual numbers with m (`seed_m`) or h seeded: its points'
/// dual parts are ∂(state)/∂m or ∂(state)/∂h at fixed angles.
pub(crate) fn seeded<T: Real>(
    [a, b, m, h]: [&T; 4],
    torus: usize,
    seed_m: bool,
) -> Result<TorusMap<Dual<T>>, ClosedFormError> {
    let (one, zero) = (a.one_like(), a.zero_like());
    let (dm, dh) = if seed_m {
        (one, zero.clone())
    } else {
        (zero.clone(), one)
    };
    let constant = |x: &T| Dual::constant(x.clone());
    let (m, h) = (Dual::new(m.clone(), dm), Dual::new(h.clone(), dh));
    torus_of([constant(a), constant(b), m, h], torus)
}

/// The torus `torus` of (m, h) over any scalar (seeded derivatives ride along).
fn torus_of<S: Real>([a, b, m, h]: [S; 4], torus: usize) -> Result<TorusMap<S>, ClosedFormError> {
    let zero = a.zero_like();
    Ok(TorusMap::of_motion(&ExplicitMotion::build(
        a,
        b,
        m,
        h,
        torus,
        [zero.clone(), zero],
    )?))
}

/// The torus `torus` of (m, h) built over jets seeded in m (direction 0) and h (direction 1): its
/// points' derivatives are ∂(state)/∂m and ∂(state)/∂h at fixed angles in one evaluation, each
/// bit for bit that of [`seeded`] (a jet's direction is its dual number).
pub(crate) fn seeded_mh<T: Real>(
    [a, b, m, h]: [&T; 4],
    torus: usize,
) -> Result<TorusMap<Jet<T, 2>>, ClosedFormError> {
    let constant = |x: &T| Jet::constant(x.clone());
    let (m, h) = (Jet::variable(m.clone(), 0), Jet::variable(h.clone(), 1));
    torus_of([constant(a), constant(b), m, h], torus)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The m and h columns of one jet evaluation are those of the two dual evaluations, bit for
    /// bit, on every torus of a camera with m > 0 and one with m < 0.
    #[test]
    fn jet_columns_are_the_dual_columns_bit_for_bit() {
        let mut compared = 0;
        for (m, h) in [(0.3, -0.375), (-0.2, 0.3), (0.5, 0.1), (-0.05, -0.3)] {
            for torus in 0..4 {
                let k = [&1.0, &0.6, &m, &h];
                let (Ok(jet), Ok(in_m), Ok(in_h)) = (
                    seeded_mh(k, torus),
                    seeded(k, torus, true),
                    seeded(k, torus, false),
                ) else {
                    continue;
                };
                for psi in [[0.1, 2.0], [3.0, 5.5], [6.0, 0.7]] {
                    let x = jet.state_at(&psi.map(Jet::constant));
                    let dm = in_m.state_at(&psi.map(Dual::constant));
                    let dh = in_h.state_at(&psi.map(Dual::constant));
                    for j in 0..DIM {
                        assert_eq!(x[j].eps[0].to_bits(), dm[j].eps.to_bits(), "∂/∂m {j}");
                        assert_eq!(x[j].eps[1].to_bits(), dh[j].eps.to_bits(), "∂/∂h {j}");
                        assert_eq!(x[j].re.to_bits(), dm[j].re.to_bits(), "value {j}");
                    }
                    compared += 1;
                }
            }
        }
        assert!(compared >= 12, "only {compared} points compared");
    }
}
