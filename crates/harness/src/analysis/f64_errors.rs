//! The errors of one f64 sample against its exact state in double-double, in one function the
//! caller compiles with the processor's fused multiply-add ([`super::f64_samples`]): the state
//! error, the orientation error, the drifts of H, K, G, the constraints, off_N and the
//! differences the correct digits are taken from.
//!
//! The same numbers as [`crate::metrics::sample_errors`] in double-double, operation for
//! operation, where a value of the data is an f64: a product of two f64 is formed exactly
//! (`two_prod`, what the general double-double product gives when both low parts are 0) and a
//! double-double times an f64 is [`DoubleDouble::mul_f64`] (the general product with a low part
//! 0), so every double-double value is the one of the general code, bit for bit. The
//! orientation error alone is computed otherwise, and more accurately: from the differences
//! Q − Q̃ (sums of products of the angle's size, error ~2⁻¹⁰⁶ of the angle, where the general
//! code's entries of R ≈ I carry 2⁻¹⁰⁶ of 1, a unit of the 16th digit of an angle ~1e-16),
//! and for the small angles of a sample (tan θ < 2⁻¹⁴) the arctangent by its series
//! (docs/closed-form.md).

use rsts_dynamics::scalar::double_double::{quick_two_sum, two_prod, two_sum};
use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::{Fields, Real, State};

use crate::metrics::{ManifoldN, SampleErrors};

type Dd = DoubleDouble;

/// Everything measured of f64 data `x` (ω, α, β) against the exact state `exact`: the errors
/// and the nine differences |xₖ − x̃ₖ| of the correct digits ([`crate::digits::of_differences`]).
/// Plain loops and `#[inline(always)]` helpers throughout, no closure handed to a library
/// function: under the caller's `#[target_feature(enable = "fma")]` every `mul_add` is then
/// one instruction (a closure compiled apart would call the library's `fma`).
#[inline(always)]
pub(crate) fn f64_sample_errors(
    fields: &Fields<Dd>,
    n: &ManifoldN<Dd>,
    initial_integrals: &[Dd; 3],
    exact: &State<Dd>,
    x: &[f64; 9],
) -> (SampleErrors, [Dd; 9]) {
    let y = exact.to_array();
    let mut delta = [Dd::ZERO; 9];
    let mut d = [Dd::ZERO; 9];
    let mut state_error = Dd::ZERO;
    for k in 0..9 {
        delta[k] = Dd::from_f64_exact(x[k]) - y[k];
        d[k] = delta[k].abs();
        state_error = state_error.max_of(d[k]);
    }
    let [h, k, g] = integrals_f64(fields, x);
    let two = Dd::from_f64_exact(2.0);
    let off_k = (k - n.k).abs();
    let off_g = (two * g - n.p2 * h - n.r4m).abs();
    let errors = SampleErrors {
        state_error: state_error.to_f64(),
        orientation_error: orientation_error(x, exact, &delta).to_f64(),
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

/// v/2, exactly.
#[inline(always)]
fn half(v: Dd) -> Dd {
    Dd {
        hi: v.hi * 0.5,
        lo: v.lo * 0.5,
    }
}

/// v/4, exactly.
#[inline(always)]
fn quarter(v: Dd) -> Dd {
    Dd {
        hi: v.hi * 0.25,
        lo: v.lo * 0.25,
    }
}

/// u·v, exactly (a double-double).
#[inline(always)]
fn prod(u: f64, v: f64) -> Dd {
    Dd::prod_f64(u, v)
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
    let big_a = [
        f.a.mul_f64(alpha[0]),
        f.a.mul_f64(alpha[1]),
        f.a.mul_f64(alpha[2]),
    ];
    let big_b = [
        f.b.mul_f64(beta[0]),
        f.b.mul_f64(beta[1]),
        f.b.mul_f64(beta[2]),
    ];
    let (w1s, w2s) = (prod(w1, w1), prod(w2, w2));
    let h = w1s + w2s + half(prod(w3, w3)) - (big_a[0] + big_b[1]);
    let kx = w1s - w2s + big_a[0] - big_b[1];
    let ky = prod(2.0 * w1, w2) + big_a[1] + big_b[0];
    let k = kx.sqr() + ky.sqr();
    let m = [2.0 * w1, 2.0 * w2, w3];
    let ma = dot_f64_dd(&m, &big_a);
    let mb = dot_f64_dd(&m, &big_b);
    let mab = dot_f64_dd(&m, &cross_dd(&big_a, &big_b));
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

/// A sum of products formed exactly in their high parts: Σ uᵢvᵢ of double-doubles (or f64)
/// with error ~2⁻¹⁰⁶ Σ|uᵢvᵢ| (each uᵢ.hi·vᵢ.hi exact by `two_prod`, the sum of the high parts
/// error-free by `two_sum`, the rest — low parts and cross terms, each below 2⁻⁵³ of its
/// product — summed in f64), at about a third of the cost of double-double products and sums.
#[derive(Clone, Copy)]
struct ProductSum {
    hi: f64,
    lo: f64,
}

impl ProductSum {
    const ZERO: Self = Self { hi: 0.0, lo: 0.0 };

    #[inline(always)]
    fn add(mut self, u: Dd, v: Dd) -> Self {
        let (p, e) = two_prod(u.hi, v.hi);
        let (s, f) = two_sum(self.hi, p);
        self.hi = s;
        self.lo += f + u.hi.mul_add(v.lo, u.lo.mul_add(v.hi, e));
        self
    }

    #[inline(always)]
    fn sub(self, u: Dd, v: Dd) -> Self {
        self.add(-u, v)
    }

    #[inline(always)]
    fn value(self) -> Dd {
        let (hi, lo) = quick_two_sum(self.hi, self.lo);
        Dd { hi, lo }
    }
}

/// The rotation angle of R = Q Q̃ᵀ, Q of the f64 state `x` and Q̃ of the exact state, from the
/// differences Δ = Q − Q̃ (`delta`: Δα, Δβ as measured for the state error): R − I = ΔQ̃ᵀ up to
/// Q̃Q̃ᵀ − I (~2⁻¹⁰⁶, symmetric: none in the skew part), so the skew part of R and tr R − 3 are
/// sums of products of the size of the angle, formed with error ~2⁻¹⁰⁶ of it
/// ([`rsts_dynamics::vec3::rotation_angle`] forms the entries of R ≈ I, error 2⁻¹⁰⁶ of 1).
#[inline(always)]
fn orientation_error(x: &[f64; 9], exact: &State<Dd>, delta: &[Dd; 9]) -> Dd {
    let f = Dd::from_f64_exact;
    let (a, b) = (&exact.alpha, &exact.beta);
    let (da, db) = (&delta[3..6], &delta[6..9]);
    let beta = [f(x[6]), f(x[7]), f(x[8])];
    // γ̃ = α̃×β̃ and Δγ = α×β − α̃×β̃ = Δα×β + α̃×Δβ (k, i, j cyclic).
    let mut c = [Dd::ZERO; 3];
    let mut dc = [Dd::ZERO; 3];
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        c[k] = ProductSum::ZERO.add(a[i], b[j]).sub(a[j], b[i]).value();
        let sum = ProductSum::ZERO.add(da[i], beta[j]).sub(da[j], beta[i]);
        dc[k] = sum.add(a[i], db[j]).sub(a[j], db[i]).value();
    }
    let q = [a, b, &c];
    let dq = [da, db, &dc[..]];
    // The skew part s_k = R_ji − R_ij (k, i, j cyclic), R_ij − δ_ij = Δq_i·q̃_j.
    let mut s = [Dd::ZERO; 3];
    for (k, sk) in s.iter_mut().enumerate() {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let mut sum = ProductSum::ZERO;
        for l in 0..3 {
            sum = sum.add(dq[j][l], q[i][l]).sub(dq[i][l], q[j][l]);
        }
        *sk = sum.value();
    }
    let mut trace = ProductSum::ZERO;
    for n in 0..9 {
        trace = trace.add(dq[n / 3][n % 3], q[n / 3][n % 3]);
    }
    let mut norm2 = ProductSum::ZERO;
    for v in s {
        norm2 = norm2.add(v, v);
    }
    let sin = half(norm2.value().sqrt());
    let cos = Dd::ONE + half(trace.value());
    small_angle(sin, cos)
}

/// atan2(sin, cos) for sin ≥ 0: for tan θ = z < 2⁻¹⁴ the series z − z³/3 + z⁵/5 − z⁷/7 + z⁹/9
/// (z³/3 in double-double; the rest, below 2⁻⁵⁶ z, in f64 from z.hi; the next term is below
/// 2⁻¹⁴⁰ z), otherwise by a table and a short series ([`arctangent::arctangent`]).
#[inline(always)]
pub(crate) fn small_angle(sin: Dd, cos: Dd) -> Dd {
    const LIMIT: f64 = 6.103515625e-5; // 2⁻¹⁴
    const THIRD: Dd = Dd {
        hi: 0.3333333333333333,
        lo: 1.850371707708594e-17,
    };
    if cos.hi > 0.0 && sin.hi >= 0.0 && sin.hi < LIMIT * cos.hi {
        let z = sin / cos;
        let w = z.sqr();
        let tail = z.hi * w.hi * w.hi * (0.2 - w.hi * (1.0 / 7.0 - w.hi / 9.0));
        (z - z * w * THIRD).add_f64(tail)
    } else {
        arctangent::arctangent(sin, cos)
    }
}

mod arctangent;
mod atan_table;
mod four;

pub(crate) use four::f64_sample_errors4;

#[cfg(test)]
mod tests;
