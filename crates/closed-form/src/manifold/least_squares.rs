//! The Gauss–Newton step of the projector in f64, factored once per Jacobian (stop 29): the
//! normal equations JᵀJ·δ = −Jᵀr eliminated with partial pivoting, the elimination kept so
//! that a chord step (the same Jacobian, a new residual) costs the right-hand side alone. The
//! arithmetic is that of the generic [`gauss_newton_step`], operation for operation, so a step
//! is the same bit for bit (test below).
//!
//! The Jacobian is held by rows (stop 31): row k is (∂C_k/∂ψ₁, ∂C_k/∂ψ₂, ∂C_k/∂m, ∂C_k/∂h), the
//! four derivative lanes of the jet the table evaluates ([`TorusTable::state_and_rows`]), one
//! AVX2 register. JᵀJ is then the sum over k of the outer products of the rows and Jᵀr that of
//! the rows times r_k, each entry summed in the order of the generic step's dot products (from
//! 0, k = 0 … 8): the same numbers, four entries per vector operation.
//!
//! [`gauss_newton_step`]: super::torus_map::gauss_newton_step
//! [`TorusTable::state_and_rows`]: super::torus_table::TorusTable

use rsts_dynamics::state::DIM;

/// The Jacobian by rows: ∂C_k/∂(ψ₁, ψ₂, m, h) for each component k of the state.
pub(crate) type Rows = [[f64; 4]; DIM];

/// Four Jacobian columns (held by rows) and the elimination of their normal matrix.
#[derive(Clone, Debug)]
pub(crate) struct LeastSquares {
    rows: Rows,
    /// The upper triangle after elimination.
    upper: [[f64; 4]; 4],
    /// The row swapped into place at each column, and the multipliers of each row.
    pivots: [usize; 4],
    factors: [[f64; 4]; 4],
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
    /// The elimination for the Jacobian `rows`, or `None` when JᵀJ is singular.
    #[allow(clippy::needless_range_loop)] // the index ranges are the elimination's
    #[inline(always)]
    pub(crate) fn new(rows: &Rows) -> Option<Self> {
        // (JᵀJ)ᵢⱼ = Σₖ Jₖᵢ·Jₖⱼ in order of k, from 0 (uₖvₖ = vₖuₖ in floating point: the
        // matrix is symmetric bit for bit).
        let mut a = [[0.0; 4]; 4];
        for row in rows {
            for i in 0..4 {
                for j in 0..4 {
                    a[i][j] += row[i] * row[j];
                }
            }
        }
        let mut pivots = [0; 4];
        let mut factors = [[0.0; 4]; 4];
        for col in 0..4 {
            // The first row of largest |a[·][col]| at or below col (as max_by keeps the last of
            // equal maxima: the generic step's choice).
            let mut pivot = col;
            for row in col + 1..4 {
                if a[row][col].abs() >= a[pivot][col].abs() {
                    pivot = row;
                }
            }
            if a[pivot][col].abs().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            a.swap(col, pivot);
            pivots[col] = pivot;
            for row in col + 1..4 {
                let f = a[row][col] / a[col][col];
                factors[col][row] = f;
                for k in col..4 {
                    a[row][k] -= f * a[col][k];
                }
            }
        }
        Some(Self {
            rows: *rows,
            upper: a,
            pivots,
            factors,
        })
    }

    /// The step δ for the residual r.
    #[inline(always)]
    pub(crate) fn step(&self, r: &[f64; DIM]) -> [f64; 4] {
        // −(Jᵀr)ᵢ = −Σₖ Jₖᵢ·rₖ in order of k, from 0.
        let mut jtr = [0.0; 4];
        for (row, rk) in self.rows.iter().zip(r) {
            for (y, j) in jtr.iter_mut().zip(row) {
                *y += j * rk;
            }
        }
        let mut y = jtr.map(|v| -v);
        for col in 0..4 {
            y.swap(col, self.pivots[col]);
            for row in col + 1..4 {
                y[row] -= self.factors[col][row] * y[col];
            }
        }
        let a = &self.upper;
        let mut x = y;
        for row in (0..4).rev() {
            let mut v = y[row];
            for k in row + 1..4 {
                v -= a[row][k] * x[k];
            }
            x[row] = v / a[row][row];
        }
        x
    }

    /// The Jacobian the elimination is of, by rows.
    #[inline(always)]
    pub(crate) fn rows(&self) -> &Rows {
        &self.rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifold::torus_map::gauss_newton_step;

    /// The same step as the generic one, bit for bit, on random and on rank-deficient systems.
    #[test]
    fn the_step_is_the_generic_step_bit_for_bit() {
        let mut seed = 29u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
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
                (Some(g), Some(o)) => assert_eq!(g.map(f64::to_bits), o.map(f64::to_bits)),
                (None, None) => {}
                (g, o) => panic!("case {case}: generic {g:?}, own {o:?}"),
            }
        }
    }
}
