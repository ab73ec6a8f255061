//! The Gauss–Newton step of the projector in f64, factored once per Jacobian (stop 29): the
//! normal equations JᵀJ·δ = −Jᵀr, the factorisation kept so that a chord step (the same
//! Jacobian, a new residual) costs the right-hand side alone.
//!
//! The Jacobian is held by rows (stop 31): row k is (∂C_k/∂ψ₁, ∂C_k/∂ψ₂, ∂C_k/∂m, ∂C_k/∂h), the
//! four derivative lanes of the jet the table evaluates, one AVX2 register. JᵀJ is the sum over
//! k of the outer products of the rows and Jᵀr that of the rows times r_k (each entry summed
//! in order of k from 0, as the generic [`gauss_newton_step`]'s dot products: the same JᵀJ).
//!
//! JᵀJ is symmetric positive definite: it is factored as LDLᵀ (L unit lower triangular, D
//! diagonal; stop 31) without pivoting — backward stable for such matrices, like the partial
//! pivoting of the generic step — with the reciprocals of D kept, so that a step costs no
//! division. The step differs from the generic one by the rounding of two different
//! eliminations: both are within a few ulps × cond(JᵀJ) of the exact step (test below: within
//! 1e-12 relative on random systems). A pivot of D at or below [`SINGULAR`] times its diagonal
//! entry of JᵀJ (the column lost all but a few bits to the others) counts as singular; on the
//! tori of the README's default case and of camera V (2·10⁵ points each) dⱼ/(JᵀJ)ⱼⱼ ≥ 2.5e-4.
//!
//! [`gauss_newton_step`]: super::torus_map::gauss_newton_step

use rsts_dynamics::state::DIM;

/// The Jacobian by rows: ∂C_k/∂(ψ₁, ψ₂, m, h) for each component k of the state.
pub(crate) type Rows = [[f64; 4]; DIM];

/// A pivot dⱼ ≤ SINGULAR·(JᵀJ)ⱼⱼ is singular: column j lies within 2⁻²² rad of the span of the
/// ones before (cond(J) ≥ 4e6: the normal equations keep at most a few digits of δ).
const SINGULAR: f64 = 1.0 / (1u64 << 44) as f64;

/// Four Jacobian columns (held by rows) and the LDLᵀ factors of their normal matrix.
#[derive(Clone, Debug)]
pub(crate) struct LeastSquares {
    rows: Rows,
    /// L below the diagonal (lower[i][j], i > j), and 1/D.
    lower: [[f64; 4]; 4],
    inv_d: [f64; 4],
}

/// The rows of the Jacobian with columns `columns`.
pub(crate) fn rows_of(columns: &[[f64; DIM]; 4]) -> Rows {
    std::array::from_fn(|k| std::array::from_fn(|i| columns[i][k]))
}

/// The columns of the Jacobian with rows `rows`.
pub(crate) fn columns_of(rows: &Rows) -> [[f64; DIM]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|k| rows[k][i]))
}

impl LeastSquares {
    /// The factors for the Jacobian `rows`, or `None` when JᵀJ is singular.
    #[allow(clippy::needless_range_loop)] // the index ranges are the factorisation's
    #[inline(always)]
    pub(crate) fn new(rows: &Rows) -> Option<Self> {
        // (JᵀJ)ᵢⱼ = Σₖ Jₖᵢ·Jₖⱼ in order of k, from 0.
        let mut a = [[0.0; 4]; 4];
        for row in rows {
            for i in 0..4 {
                for j in 0..4 {
                    a[i][j] += row[i] * row[j];
                }
            }
        }
        let mut lower = [[0.0; 4]; 4];
        let mut d = [0.0; 4];
        let mut inv_d = [0.0; 4];
        for j in 0..4 {
            // (L·D)ⱼₖ for k < j.
            let ld: [f64; 4] =
                std::array::from_fn(|k| if k < j { lower[j][k] * d[k] } else { 0.0 });
            let mut dj = a[j][j];
            for k in 0..j {
                dj -= lower[j][k] * ld[k];
            }
            // Also singular: a NaN.
            if dj.partial_cmp(&(SINGULAR * a[j][j])) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            d[j] = dj;
            inv_d[j] = 1.0 / dj;
            for i in j + 1..4 {
                let mut v = a[i][j];
                for k in 0..j {
                    v -= lower[i][k] * ld[k];
                }
                lower[i][j] = v * inv_d[j];
            }
        }
        Some(Self {
            rows: *rows,
            lower,
            inv_d,
        })
    }

    /// The step δ for the residual r.
    #[allow(clippy::needless_range_loop)] // the index ranges are the substitutions'
    #[inline(always)]
    pub(crate) fn step(&self, r: &[f64; DIM]) -> [f64; 4] {
        // −(Jᵀr)ᵢ = −Σₖ Jₖᵢ·rₖ in order of k, from 0.
        let mut jtr = [0.0; 4];
        for (row, rk) in self.rows.iter().zip(r) {
            for (y, j) in jtr.iter_mut().zip(row) {
                *y += j * rk;
            }
        }
        let l = &self.lower;
        // L·y = −Jᵀr, then Lᵀ·x = D⁻¹·y.
        let mut y = jtr.map(|v| -v);
        for i in 1..4 {
            for k in 0..i {
                y[i] -= l[i][k] * y[k];
            }
        }
        let mut x: [f64; 4] = std::array::from_fn(|i| y[i] * self.inv_d[i]);
        for i in (0..3).rev() {
            for k in i + 1..4 {
                x[i] -= l[k][i] * x[k];
            }
        }
        x
    }

    /// The Jacobian the factors are of, by rows.
    #[inline(always)]
    pub(crate) fn rows(&self) -> &Rows {
        &self.rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifold::torus_map::gauss_newton_step;

    /// max |u − v| / max |v|.
    fn relative(u: &[f64; 4], v: &[f64; 4]) -> f64 {
        let gap = (0..4).map(|i| (u[i] - v[i]).abs()).fold(0.0, f64::max);
        gap / v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
    }

    /// The step is the generic step to the rounding of the eliminations on random systems, and
    /// both find the rank-deficient ones singular.
    #[test]
    fn the_step_is_the_generic_step_to_the_rounding() {
        let mut seed = 29u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut worst = 0.0f64;
        for case in 0..2000 {
            let mut columns: [[f64; DIM]; 4] =
                std::array::from_fn(|_| std::array::from_fn(|_| next()));
            if case % 7 == 0 {
                columns[3] = columns[1];
            }
            let r: [f64; DIM] = std::array::from_fn(|_| next() * 1e-3);
            let generic = gauss_newton_step(columns.each_ref(), &r);
            let own = LeastSquares::new(&rows_of(&columns)).map(|l| l.step(&r));
            match (generic, own) {
                (Some(g), Some(o)) => worst = worst.max(relative(&o, &g)),
                (None, None) => {}
                (g, o) => panic!("case {case}: generic {g:?}, own {o:?}"),
            }
        }
        assert!(worst < 1e-12, "{worst:e}");
    }
}
