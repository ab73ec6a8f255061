//! The largest eigenvalue of a small symmetric matrix without a full eigen-decomposition (the
//! gain of X_Φ at every saturated sample of `rsts check`, stop 28): Householder reduction to a
//! tridiagonal T (orthogonal, so T has the eigenvalues of the matrix up to a few ulps of its
//! norm), then Laguerre's method on p(x) = det(T − x) from Gershgorin's upper bound:
//!
//! ```text
//!   x ← x − n / (G + √((n − 1)(nH − G²))),   G = p′/p = Σ 1/(x − λᵢ),  H = G² − p″/p = Σ 1/(x − λᵢ)²
//! ```
//!
//! For a polynomial with real roots only, started above them all, it decreases monotonically to
//! the largest (cubically for a simple root, linearly for a multiple one). Stop 30: 3.6 steps on
//! camera V's saturated samples where Newton's method took 7.2, the same eigenvalue to 1.8e-15
//! relative, ~10 % less time (the Householder reduction is now half of it). p, p′, p″ come from
//! the three-term recurrence of T's leading minors, which is backward stable, so the root is
//! found to a few ulps of the norm; the scaling that keeps them in range is a power of two.

/// The largest eigenvalue of the symmetric N×N matrix `lower` (its upper triangle is ignored).
pub fn largest_eigenvalue<const N: usize>(lower: [[f64; N]; N]) -> f64 {
    let (d, e) = tridiagonal(lower);
    largest_of_tridiagonal(&d, &e).0
}

/// The diagonal and the off-diagonal (e[i] = T[i+1][i]) of the Householder tridiagonal form of
/// the symmetric matrix `lower` (its upper triangle is ignored).
#[allow(clippy::needless_range_loop)] // the index ranges are the algorithm's
fn tridiagonal<const N: usize>(lower: [[f64; N]; N]) -> ([f64; N], [f64; N]) {
    // The full symmetric matrix: the reduction reads rows without branching on the triangle.
    let mut a: [[f64; N]; N] = std::array::from_fn(|i| {
        std::array::from_fn(|j| if i >= j { lower[i][j] } else { lower[j][i] })
    });
    // Householder: zero column k below the subdiagonal, A ← HAH on the trailing block. For the
    // 6×6 Gram matrix of the gain each step is inlined with its k (stop 31): its loops then have
    // fixed lengths, which the compiler unrolls (the same operations in the same order).
    if N == 6 {
        reflect(&mut a, 0);
        reflect(&mut a, 1);
        reflect(&mut a, 2);
        reflect(&mut a, 3);
    } else {
        for k in 0..N.saturating_sub(2) {
            reflect(&mut a, k);
        }
    }
    let d: [f64; N] = std::array::from_fn(|i| a[i][i]);
    let e: [f64; N] = std::array::from_fn(|i| if i + 1 < N { a[i + 1][i] } else { 0.0 });
    (d, e)
}

/// One Householder step of [`tridiagonal`]: column k zeroed below the subdiagonal.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // the index ranges are the algorithm's
fn reflect<const N: usize>(a: &mut [[f64; N]; N], k: usize) {
    let mut sum = 0.0;
    for i in k + 1..N {
        sum += a[i][k] * a[i][k];
    }
    let norm = sum.sqrt();
    if norm == 0.0 {
        return;
    }
    let alpha = if a[k + 1][k] > 0.0 { -norm } else { norm };
    let mut v = [0.0; N];
    for i in k + 1..N {
        v[i] = a[i][k];
    }
    v[k + 1] -= alpha;
    // vᵀv = |column|² − 2α·a[k+1][k] + α² = 2(α² − α·a[k+1][k]).
    let vv = 2.0 * (norm * norm - alpha * a[k + 1][k]);
    if vv == 0.0 {
        return;
    }
    let beta = 2.0 / vv;
    // p = βAv, q = p − (βvᵀp/2)v, A ← A − vqᵀ − qvᵀ (rows and columns k+1..N).
    let mut p = [0.0; N];
    for i in k + 1..N {
        let mut s = 0.0;
        for j in k + 1..N {
            s += a[i][j] * v[j];
        }
        p[i] = beta * s;
    }
    let mut vp = 0.0;
    for i in k + 1..N {
        vp += v[i] * p[i];
    }
    let c = 0.5 * beta * vp;
    for i in k + 1..N {
        p[i] -= c * v[i];
    }
    for i in k + 1..N {
        for j in k + 1..N {
            a[i][j] -= v[i] * p[j] + p[i] * v[j];
        }
    }
    a[k + 1][k] = alpha;
}

/// The largest eigenvalue of the symmetric tridiagonal T (diagonal `d`, off-diagonal `e`) and
/// the number of Laguerre steps it took.
fn largest_of_tridiagonal<const N: usize>(d: &[f64; N], e: &[f64; N]) -> (f64, usize) {
    // Gershgorin's upper bound, and a power of two that keeps det(T − x) within range (exact).
    let bound = (0..N)
        .map(|i| d[i] + e[i].abs() + if i > 0 { e[i - 1].abs() } else { 0.0 })
        .fold(f64::NEG_INFINITY, f64::max);
    let size = (0..N).map(|i| d[i].abs() + e[i].abs()).fold(0.0, f64::max);
    if size == 0.0 || !size.is_finite() {
        return (if size == 0.0 { 0.0 } else { f64::NAN }, 0);
    }
    // 2^−⌈log₂ size⌉ (within the normal range): the scaling and its undoing are exact.
    let inverse = 2f64.powi(-(size.log2().ceil().clamp(-1020.0, 1020.0) as i32));
    let (d, e2) = (
        d.map(|x| x * inverse),
        e.map(|x| (x * inverse) * (x * inverse)),
    );
    let (x, steps) = laguerre(&d, &e2, bound * inverse);
    (x / inverse, steps)
}

/// The largest eigenvalue of the tridiagonal T (diagonal `d`, squared off-diagonal `e2`) by
/// Laguerre's method from `x` above it, and the number of steps taken.
fn laguerre<const N: usize>(d: &[f64; N], e2: &[f64; N], mut x: f64) -> (f64, usize) {
    let n = N as f64;
    for steps in 0..200 {
        // p = det(T − x), p′, p″ by the recurrence of the leading minors.
        let (mut f0, mut f1, mut g0, mut g1, mut h0, mut h1) = (1.0, d[0] - x, 0.0, -1.0, 0.0, 0.0);
        for i in 1..N {
            let f2 = (d[i] - x) * f1 - e2[i - 1] * f0;
            let g2 = (d[i] - x) * g1 - f1 - e2[i - 1] * g0;
            let h2 = (d[i] - x) * h1 - 2.0 * g1 - e2[i - 1] * h0;
            (f0, f1, g0, g1, h0, h1) = (f1, f2, g1, g2, h1, h2);
        }
        // Laguerre's step: G = p′/p = Σ 1/(x − λᵢ), H = G² − p″/p = Σ 1/(x − λᵢ)².
        let inverse_p = 1.0 / f1;
        let g = g1 * inverse_p;
        let h = g * g - h1 * inverse_p;
        let root = ((n - 1.0) * (n * h - g * g)).max(0.0).sqrt();
        let step = -n / (g + root);
        // Monotone from above: a step that does not decrease x is round-off.
        if step >= 0.0 || step.is_nan() {
            return (x, steps + 1);
        }
        x += step;
        if -step <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE) {
            return (x, steps + 1);
        }
    }
    (x, 200)
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
        let (mut steps, mut most) = (0, 0);
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
            let (d, e) = tridiagonal(g);
            let (_, n) = largest_of_tridiagonal(&d, &e);
            steps += n;
            most = most.max(n);
        }
        assert!(worst < 32.0 * f64::EPSILON, "relative error {worst:e}");
        // Laguerre's cubic convergence: a few steps from Gershgorin's bound.
        eprintln!(
            "Laguerre steps: {} on average, at most {most}",
            steps as f64 / 3000.0
        );
        assert!(
            most <= 6 && steps <= 3000 * 4,
            "{steps} steps, at most {most}"
        );
        // Scaled to the ends of the range (subnormal entries, entries near the largest f64).
        for scale in [1e-310, 1e-300, 1e300] {
            let diagonal = [
                [2.0 * scale, 0.0, 0.0],
                [0.0, scale, 0.0],
                [0.0, 0.0, scale],
            ];
            assert_eq!(largest_eigenvalue(diagonal), 2.0 * scale, "scale {scale:e}");
        }
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
