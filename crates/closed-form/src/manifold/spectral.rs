//! The largest eigenvalue of a small symmetric matrix without a full eigen-decomposition (the
//! gain of X_Φ at every saturated sample of `rsts check`, stop 28): Householder reduction to a
//! tridiagonal T (orthogonal, so T has the eigenvalues of the matrix up to a few ulps of its
//! norm), then Newton's method on det(T − x) from Gershgorin's upper bound. The determinant of
//! a real-rooted polynomial is convex above its largest root, so Newton decreases monotonically
//! to it (quadratically for a simple root, halving the gap for a double one); det and its
//! derivative come from the three-term recurrence of T's leading minors, which is backward
//! stable, so the root is found to a few ulps of the norm.

/// The largest eigenvalue of the symmetric N×N matrix `a` (its upper triangle is ignored).
#[allow(clippy::needless_range_loop)] // the index ranges are the algorithm's
pub fn largest_eigenvalue<const N: usize>(mut a: [[f64; N]; N]) -> f64 {
    // Householder: zero column k below the subdiagonal, A ← HAH on the trailing block.
    for k in 0..N.saturating_sub(2) {
        let norm = (k + 1..N).map(|i| a[i][k] * a[i][k]).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        let alpha = if a[k + 1][k] > 0.0 { -norm } else { norm };
        let mut v = [0.0; N];
        for i in k + 1..N {
            v[i] = a[i][k];
        }
        v[k + 1] -= alpha;
        let vv: f64 = (k + 1..N).map(|i| v[i] * v[i]).sum();
        if vv == 0.0 {
            continue;
        }
        let beta = 2.0 / vv;
        // p = βAv, q = p − (βvᵀp/2)v, A ← A − vqᵀ − qvᵀ (rows and columns k+1..N).
        let mut p = [0.0; N];
        for i in k + 1..N {
            p[i] = beta * (k + 1..N).map(|j| sym(&a, i, j) * v[j]).sum::<f64>();
        }
        let c = 0.5 * beta * (k + 1..N).map(|i| v[i] * p[i]).sum::<f64>();
        for i in k + 1..N {
            p[i] -= c * v[i];
        }
        for i in k + 1..N {
            for j in k + 1..=i {
                a[i][j] -= v[i] * p[j] + p[i] * v[j];
            }
        }
        a[k + 1][k] = alpha;
    }
    let d: [f64; N] = std::array::from_fn(|i| a[i][i]);
    let e: [f64; N] = std::array::from_fn(|i| if i + 1 < N { a[i + 1][i] } else { 0.0 });
    // Gershgorin's upper bound, and the scale that keeps det(T − x) within range.
    let bound = (0..N)
        .map(|i| d[i] + e[i].abs() + if i > 0 { e[i - 1].abs() } else { 0.0 })
        .fold(f64::NEG_INFINITY, f64::max);
    let scale = (0..N).map(|i| d[i].abs() + e[i].abs()).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return if scale == 0.0 { 0.0 } else { f64::NAN };
    }
    let (d, e) = (d.map(|x| x / scale), e.map(|x| x / scale));
    let mut x = bound / scale;
    for _ in 0..200 {
        // det(T − x) and its derivative by the recurrence of the leading minors.
        let (mut f0, mut f1, mut g0, mut g1) = (1.0, d[0] - x, 0.0, -1.0);
        for i in 1..N {
            let e2 = e[i - 1] * e[i - 1];
            let f2 = (d[i] - x) * f1 - e2 * f0;
            let g2 = (d[i] - x) * g1 - f1 - e2 * g0;
            (f0, f1, g0, g1) = (f1, f2, g1, g2);
        }
        let step = -f1 / g1;
        // Monotone from above: a step that does not decrease x is round-off.
        if step >= 0.0 || step.is_nan() {
            break;
        }
        x += step;
        if -step <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    x * scale
}

/// a[i][j] from the lower triangle.
fn sym<const N: usize>(a: &[[f64; N]; N], i: usize, j: usize) -> f64 {
    if i >= j {
        a[i][j]
    } else {
        a[j][i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against nalgebra's symmetric eigenvalues: random Gram matrices (rank 2 to 6, spread
    /// spectra), a double largest eigenvalue and diagonal ones, to a few ulps of the largest.
    #[test]
    fn largest_eigenvalue_of_gram_matrices() {
        let mut seed = 0x2028_u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut worst = 0.0f64;
        for case in 0..3000 {
            let rank = 2 + case % 5;
            let weights: [f64; 6] =
                std::array::from_fn(|k| 10f64.powf(-6.0 * next().abs() * k as f64 / 5.0));
            let cols: Vec<[f64; 9]> = (0..6).map(|_| std::array::from_fn(|_| next())).collect();
            let mut j = [[0.0; 6]; 9];
            for (r, row) in j.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate() {
                    // Column c: a mix of the first `rank` random columns.
                    *x = (0..rank)
                        .map(|k| cols[k][r] * weights[k] * cols[(k + c) % 6][k])
                        .sum();
                }
            }
            let mut g = [[0.0; 6]; 6];
            for p in 0..6 {
                for q in 0..6 {
                    g[p][q] = (0..9).map(|k| j[k][p] * j[k][q]).sum();
                }
            }
            let m = nalgebra::SMatrix::<f64, 6, 6>::from_fn(|p, q| g[p][q]);
            let exact = m.symmetric_eigenvalues().max();
            worst = worst.max((largest_eigenvalue(g) - exact).abs() / exact);
        }
        assert!(worst < 32.0 * f64::EPSILON, "relative error {worst:e}");
        // A double largest eigenvalue, and a diagonal matrix (no reduction needed).
        let double = [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((largest_eigenvalue(double) - 2.0).abs() < 1e-15);
        let r = std::f64::consts::FRAC_1_SQRT_2;
        // Q diag(3, 3, 1) Qᵀ for Q a rotation by π/4 in the (e₂, e₃) plane: 3 is double.
        let rotated = [
            [3.0, 0.0, 0.0],
            [0.0, 3.0 * r * r + r * r, 2.0 * r * r],
            [0.0, 2.0 * r * r, 3.0 * r * r + r * r],
        ];
        assert!(
            (largest_eigenvalue(rotated) - 3.0).abs() < 1e-14,
            "{}",
            largest_eigenvalue(rotated)
        );
    }
}
