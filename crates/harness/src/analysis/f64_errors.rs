//! The errors of one f64 sample against its exact state in double-double, in one function the
//! caller compiles with the processor's fused multiply-add ([`super::f64_samples`]): the state
//! error, the orientation error, the drifts of H, K, G, the constraints, off_N and the
//! differences the correct digits are taken from.
//!
//! The same numbers as [`crate::metrics::sample_errors`] in double-double, operation for
//! operation, where a value of the data is an f64: a product of two f64 is formed exactly
//! (`two_prod`, what the general double-double product gives when both low parts are 0) and a
//! double-double times an f64 is [`DoubleDouble::mul_f64`] (the general product with a low part
//! 0), so every double-double value is the one of the general code, bit for bit. Only the
//! orientation error's arctangent differs: for the small angles of a sample (tan θ < 2⁻²⁷) it
//! is the series θ = z − z³/3 of z = sin θ / cos θ in double-double instead of a Newton step on
//! the double-double sine, both within a few units of 2⁻¹⁰⁶ of θ, so the f64 they round to is
//! the same but for a value within ~2⁻¹⁰⁰ of an f64 rounding boundary (docs/closed-form.md).

use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::{Fields, Real, State};

use crate::metrics::{ManifoldN, SampleErrors};

type Dd = DoubleDouble;

/// Everything measured of f64 data `x` (ω, α, β) against the exact state `exact`: the errors
/// and the nine differences |xₖ − x̃ₖ| of the correct digits ([`crate::digits::of_differences`]).
#[inline(always)]
pub(crate) fn f64_sample_errors(
    fields: &Fields<Dd>,
    n: &ManifoldN<Dd>,
    initial_integrals: &[Dd; 3],
    exact: &State<Dd>,
    x: &[f64; 9],
) -> (SampleErrors, [Dd; 9]) {
    let y = exact.to_array();
    let d: [Dd; 9] = std::array::from_fn(|k| (Dd::from_f64_exact(x[k]) - y[k]).abs());
    let state_error = d.iter().fold(Dd::ZERO, |a, b| a.max_of(*b));
    let [h, k, g] = integrals_f64(fields, x);
    let two = Dd::from_f64_exact(2.0);
    let off_k = (k - n.k).abs();
    let off_g = (two * g - n.p2 * h - n.r4m).abs();
    let errors = SampleErrors {
        state_error: state_error.to_f64(),
        orientation_error: orientation_error(x, exact).to_f64(),
        drift_h: (h - initial_integrals[0]).abs().to_f64(),
        drift_k: (k - initial_integrals[1]).abs().to_f64(),
        drift_g: (g - initial_integrals[2]).abs().to_f64(),
        constraint_drift: constraint_error(x).to_f64(),
        off_n: off_k.max_of(off_g).to_f64(),
        distance_from_n: f64::NAN,
        x_phi: f64::NAN,
        along_n: f64::NAN,
        phase_error: [f64::NAN; 2],
    };
    (errors, d)
}

/// u·v, exactly (a double-double).
#[inline(always)]
fn prod(u: f64, v: f64) -> Dd {
    Dd::prod_f64(u, v)
}

/// u×v of two f64 vectors, each component from two exact products.
#[inline(always)]
fn cross_f64(u: &[f64], v: &[f64]) -> [Dd; 3] {
    [
        prod(u[1], v[2]) - prod(u[2], v[1]),
        prod(u[2], v[0]) - prod(u[0], v[2]),
        prod(u[0], v[1]) - prod(u[1], v[0]),
    ]
}

/// u×v in double-double ([`rsts_dynamics::vec3::cross`]).
#[inline(always)]
fn cross_dd(u: &[Dd; 3], v: &[Dd; 3]) -> [Dd; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// u·v of an f64 vector and a double-double one.
#[inline(always)]
fn dot_f64_dd(u: &[f64], v: &[Dd; 3]) -> Dd {
    v[0].mul_f64(u[0]) + v[1].mul_f64(u[1]) + v[2].mul_f64(u[2])
}

/// u·v in double-double.
#[inline(always)]
fn dot_dd(u: &[Dd; 3], v: &[Dd; 3]) -> Dd {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// u·v of two f64 vectors: three exact products summed in double-double.
#[inline(always)]
fn dot_f64(u: &[f64], v: &[f64]) -> Dd {
    prod(u[0], v[0]) + prod(u[1], v[1]) + prod(u[2], v[2])
}

/// H, K, G of the f64 state `x` ([`rsts_dynamics::integrals::integrals`], the same operations).
#[inline(always)]
pub(crate) fn integrals_f64(f: &Fields<Dd>, x: &[f64; 9]) -> [Dd; 3] {
    let (w1, w2, w3) = (x[0], x[1], x[2]);
    let (alpha, beta) = (&x[3..6], &x[6..9]);
    let big_a: [Dd; 3] = std::array::from_fn(|i| f.a.mul_f64(alpha[i]));
    let big_b: [Dd; 3] = std::array::from_fn(|i| f.b.mul_f64(beta[i]));
    // Halving and quartering are exact.
    let half = |v: Dd| Dd {
        hi: v.hi * 0.5,
        lo: v.lo * 0.5,
    };
    let (w1s, w2s) = (prod(w1, w1), prod(w2, w2));
    let h = w1s + w2s + half(prod(w3, w3)) - (big_a[0] + big_b[1]);
    let kx = w1s - w2s + big_a[0] - big_b[1];
    let ky = prod(2.0 * w1, w2) + big_a[1] + big_b[0];
    let k = kx.sqr() + ky.sqr();
    let m = [2.0 * w1, 2.0 * w2, w3];
    let ma = dot_f64_dd(&m, &big_a);
    let mb = dot_f64_dd(&m, &big_b);
    let mab = dot_f64_dd(&m, &cross_dd(&big_a, &big_b));
    let quarter = |v: Dd| Dd {
        hi: v.hi * 0.25,
        lo: v.lo * 0.25,
    };
    let g = quarter(ma.sqr() + mb.sqr()) + half(mab.mul_f64(w3))
        - f.b.sqr() * big_a[0]
        - f.a.sqr() * big_b[1];
    [h, k, g]
}

/// max(||α|² − 1|, ||β|² − 1|, |α·β|) of the f64 state `x` ([`State::constraint_error`]).
#[inline(always)]
fn constraint_error(x: &[f64; 9]) -> Dd {
    let (alpha, beta) = (&x[3..6], &x[6..9]);
    let one = Dd::ONE;
    let r = [
        dot_f64(alpha, alpha) - one,
        dot_f64(beta, beta) - one,
        dot_f64(alpha, beta),
    ];
    r[0].abs().max_of(r[1].abs()).max_of(r[2].abs())
}

/// The rotation angle of Q Q̃ᵀ, Q of the f64 state `x` and Q̃ of the exact state
/// ([`rsts_dynamics::vec3::rotation_angle`]).
#[inline(always)]
fn orientation_error(x: &[f64; 9], exact: &State<Dd>) -> Dd {
    let (alpha, beta) = (&x[3..6], &x[6..9]);
    let gamma = cross_f64(alpha, beta);
    let ex = [exact.alpha, exact.beta, cross_dd(&exact.alpha, &exact.beta)];
    // R = Q Q̃ᵀ: rows α, β of Q are f64, its row γ double-double.
    let r: [[Dd; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| match i {
            0 => dot_f64_dd(alpha, &ex[j]),
            1 => dot_f64_dd(beta, &ex[j]),
            _ => dot_dd(&gamma, &ex[j]),
        })
    });
    let s = [r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]];
    let two = Dd::from_f64_exact(2.0);
    let sin = dot_dd(&s, &s).sqrt() / two;
    let cos = (r[0][0] + r[1][1] + r[2][2] - Dd::ONE) / two;
    small_angle(sin, cos)
}

/// atan2(sin, cos) for sin ≥ 0: for tan θ = z < 2⁻²⁷ the series z − z³/3 (the next term,
/// z⁵/5, is below 2⁻¹⁰⁸ z; z³/3 is below 2⁻⁵⁵ z and taken in f64 from z.hi), otherwise the
/// double-double arctangent.
#[inline(always)]
pub(crate) fn small_angle(sin: Dd, cos: Dd) -> Dd {
    const LIMIT: f64 = 7.450580596923828e-9; // 2⁻²⁷
    if cos.hi > 0.0 && sin.hi >= 0.0 && sin.hi < LIMIT * cos.hi {
        let z = sin / cos;
        z.add_f64(-z.hi * z.hi * z.hi / 3.0)
    } else {
        sin.atan2(&cos)
    }
}

#[cfg(test)]
mod tests;
