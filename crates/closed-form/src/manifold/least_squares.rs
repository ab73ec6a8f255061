//! The Gauss–Newton step of the projector in f64, factored once per Jacobian (stop 29): the
//! normal equations JᵀJ·δ = −Jᵀr eliminated with partial pivoting, the elimination kept so
//! that a chord step (the same Jacobian, a new residual) costs the right-hand side alone. The
//! arithmetic is that of the generic [`gauss_newton_step`], operation for operation, so a step
//! is the same bit for bit (test below).
//!
//! [`gauss_newton_step`]: super::torus_map::gauss_newton_step

use rsts_dynamics::state::DIM;

/// Four Jacobian columns and the elimination of their normal matrix.
#[derive(Clone, Debug)]
pub(crate) struct LeastSquares {
    columns: [[f64; DIM]; 4],
    /// The upper triangle after elimination.
    upper: [[f64; 4]; 4],
    /// The row swapped into place at each column, and the multipliers of each row.
    pivots: [usize; 4],
    factors: [[f64; 4]; 4],
}

/// Σ uₖvₖ in order, from 0 (as the generic step adds).
#[inline(always)]
fn dot(u: &[f64; DIM], v: &[f64; DIM]) -> f64 {
    let mut acc = 0.0;
    for k in 0..DIM {
        acc += u[k] * v[k];
    }
    acc
}

impl LeastSquares {
    /// The elimination for the columns, or `None` when JᵀJ is singular.
    #[allow(clippy::needless_range_loop)] // the index ranges are the elimination's
    pub(crate) fn new(columns: &[[f64; DIM]; 4]) -> Option<Self> {
        // Symmetric (uₖvₖ = vₖuₖ in floating point): the upper triangle mirrored.
        let mut a = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in i..4 {
                a[i][j] = dot(&columns[i], &columns[j]);
                a[j][i] = a[i][j];
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
            columns: *columns,
            upper: a,
            pivots,
            factors,
        })
    }

    /// The step δ for the residual r.
    pub(crate) fn step(&self, r: &[f64; DIM]) -> [f64; 4] {
        let mut y: [f64; 4] = std::array::from_fn(|i| -dot(&self.columns[i], r));
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

    /// The columns the elimination is of.
    pub(crate) fn columns(&self) -> &[[f64; DIM]; 4] {
        &self.columns
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
            let own = LeastSquares::new(&columns).map(|l| l.step(&r));
            match (generic, own) {
                (Some(g), Some(o)) => assert_eq!(g.map(f64::to_bits), o.map(f64::to_bits)),
                (None, None) => {}
                (g, o) => panic!("case {case}: generic {g:?}, own {o:?}"),
            }
        }
    }
}
