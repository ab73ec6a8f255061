//! Bounds on the time derivatives of every event function along any motion of given energy, from
//! the table of the equations ([`EULER_POISSON`]) by majorants.
//!
//! The energy H = ω₁² + ω₂² + ω₃²/2 − (aα₁ + bβ₂) = h and |α| = |β| = 1 give
//! ω₁² + ω₂² + ω₃²/2 ≤ h + a + b, so |ω₁|, |ω₂| ≤ √(h+a+b), |ω₃| ≤ √(2(h+a+b)), and every
//! |αᵢ|, |βᵢ|, |γᵢ| ≤ 1. Each right-hand side is a sum of terms c·xᵢxⱼ and c·xᵢ, so by Leibniz's
//! rule x_k⁽ⁿ⁺¹⁾ = Σ c Σₚ C(n,p) xᵢ⁽ᵖ⁾ xⱼ⁽ⁿ⁻ᵖ⁾ + Σ c xᵢ⁽ⁿ⁾, and replacing every factor by its
//! bound gives a bound B⁽ⁿ⁺¹⁾ (a majorant series). γ = α × β obeys γ̇ = γ × ω, so
//! |γₖ⁽ⁿ⁺¹⁾| ≤ 2 Σₚ C(n,p) Γ⁽ᵖ⁾ W⁽ⁿ⁻ᵖ⁾ with W⁽ᵖ⁾ = maxᵢ B⁽ᵖ⁾(ωᵢ).

use rsts_dynamics::equations::{Param, EULER_POISSON};
use rsts_dynamics::state::DIM;

/// Highest derivative bounded.
pub const ORDERS: usize = 4;

/// `bounds[n][k]` ≥ |x_k⁽ⁿ⁾| (k < 9: ω, α, β; k = 9..12: γ) for n < [`ORDERS`].
pub fn derivative_bounds(a: f64, b: f64, h: f64) -> [[f64; DIM + 3]; ORDERS] {
    // A relative margin covers the rounding of these f64 sums.
    let margin = 1.0 + 1e-9;
    let e = (h + a.abs() + b.abs()).max(0.0) * margin;
    let mut out = [[0.0; DIM + 3]; ORDERS];
    out[0] = [
        e.sqrt(),
        e.sqrt(),
        (2.0 * e).sqrt(),
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
    ];
    let binom = |n: usize, p: usize| -> f64 {
        (0..p).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    };
    let param = |p: Param| match p {
        Param::One => 1.0,
        Param::A => a.abs(),
        Param::B => b.abs(),
    };
    for n in 0..ORDERS - 1 {
        for (k, comp) in EULER_POISSON.iter().enumerate() {
            let mut sum = 0.0;
            for t in comp.quadratic {
                let c = t.c.abs() * param(t.param);
                sum += c
                    * (0..=n)
                        .map(|p| binom(n, p) * out[p][t.i] * out[n - p][t.j])
                        .sum::<f64>();
            }
            for t in comp.linear {
                sum += t.c.abs() * param(t.param) * out[n][t.i];
            }
            out[n + 1][k] = sum * margin;
        }
        let w = |p: usize| out[p][0].max(out[p][1]).max(out[p][2]);
        let g = 2.0
            * (0..=n)
                .map(|p| binom(n, p) * out[p][DIM] * w(n - p))
                .sum::<f64>();
        out[n + 1][DIM..].fill(g * margin);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_derivative_bound_matches_the_equations_by_hand() {
        // ω̇₁ = ½ω₂ω₃ + ½bβ₃: |ω̇₁| ≤ ½√e·√(2e) + ½b.
        let (a, b, h) = (1.0, 0.5, -0.375);
        let e: f64 = h + a + b;
        let bounds = derivative_bounds(a, b, h);
        let by_hand = 0.5 * e.sqrt() * (2.0 * e).sqrt() + 0.5 * b;
        assert!((bounds[1][0] / by_hand - 1.0).abs() < 1e-8);
        // α̇₁ = α₂ω₃ − α₃ω₂: |α̇₁| ≤ √(2e) + √e.
        assert!((bounds[1][3] / ((2.0 * e).sqrt() + e.sqrt()) - 1.0).abs() < 1e-8);
    }
}
