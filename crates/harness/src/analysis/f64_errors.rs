//! The errors of f64 samples against their exact states in double-double, one kernel written
//! once over the lane count L (as heyoka writes its kernels over the batch size): L = 1 is a
//! sample at a time, L = 4 four samples in the lanes of [`DoubleDouble4`], which a caller
//! compiled with AVX2 and FMA runs in one 256-bit register ([`super::f64_samples`]). Each lane
//! performs the same IEEE operations whatever L, so a sample's numbers do not depend on the
//! lanes it shares (tested, on both builds). Measured: the state error, the orientation error,
//! the drifts of H, K, G, the constraints, off_N and the relative and mixed errors of the
//! correct digits.
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
//!
//! Plain loops and `#[inline(always)]` helpers throughout, no closure handed to a library
//! function: under the caller's `#[target_feature]` every `mul_add` is then one instruction (a
//! closure compiled apart would call the library's `fma`).

// Index loops on purpose: one index i runs over the lanes of several arrays at once, in plain
// loops over constant ranges that unroll under the caller's `#[target_feature]`.
#![allow(clippy::needless_range_loop)]

use rsts_dynamics::scalar::double_double::{quick_two_sum, two_prod, two_sum};
use rsts_dynamics::scalar::{every_lane, DoubleDouble, DoubleDoubleLanes};
use rsts_dynamics::{Fields, Real, State};

use crate::metrics::{ManifoldN, SampleErrors};

type Dd = DoubleDouble;
/// L double-doubles, one per lane.
type Lanes<const L: usize> = DoubleDoubleLanes<L>;
/// L f64, one per lane.
type F64s<const L: usize> = [f64; L];

/// What the kernel measures of a sample: its errors and the relative and mixed errors of its
/// correct digits ([`crate::digits::of_differences`]).
pub(crate) type Measured = (SampleErrors, (f64, f64));

/// Everything measured of the L f64 samples `x[i]` (ω, α, β) against the exact states
/// `exact[i]` (slices of at least L), the digits' errors with atol/rtol = `ratio`.
#[inline(always)]
pub(crate) fn f64_sample_errors<const L: usize>(
    fields: &Fields<Dd>,
    n: &ManifoldN<Dd>,
    initial_integrals: &[Dd; 3],
    exact: &[State<Dd>],
    x: &[[f64; 9]],
    ratio: f64,
) -> [Measured; L] {
    // Component k of every sample: f64 lanes xs[k], double-double lanes y[k].
    let mut xs = [[0.0; L]; 9];
    let mut y = [Lanes::<L>::default(); 9];
    for i in 0..L {
        let yi = exact[i].to_array();
        for k in 0..9 {
            xs[k][i] = x[i][k];
            y[k].set_lane(i, yi[k]);
        }
    }
    let mut delta = [Lanes::default(); 9];
    let mut d = [Lanes::default(); 9];
    let mut state_error = Lanes::splat(Dd::ZERO);
    for k in 0..9 {
        delta[k] = Lanes::from_f64_exact(xs[k]) - y[k];
        d[k] = delta[k].abs();
        state_error = state_error.max_of(d[k]);
    }
    let [h, k, g] = integrals_f64(fields, &xs);
    let two = Lanes::splat(Dd::from_f64_exact(2.0));
    let off_k = (k - Lanes::splat(n.k)).abs();
    let off_g = (two * g - Lanes::splat(n.p2) * h - Lanes::splat(n.r4m)).abs();
    let theta = orientation_error(&xs, &y, &delta);
    let i0 = initial_integrals.map(Lanes::splat);
    let drift = [(h - i0[0]).abs(), (k - i0[1]).abs(), (g - i0[2]).abs()];
    let constraint = constraint_error(&xs);
    let off_n = off_k.max_of(off_g);
    let digits = digits(&d, &y, ratio);
    let mut out = [(SampleErrors::default(), (0.0, 0.0)); L];
    for (i, out) in out.iter_mut().enumerate() {
        out.0 = SampleErrors {
            state_error: state_error.lane(i).to_f64(),
            orientation_error: theta.lane(i).to_f64(),
            drift_h: drift[0].lane(i).to_f64(),
            drift_k: drift[1].lane(i).to_f64(),
            drift_g: drift[2].lane(i).to_f64(),
            constraint_drift: constraint.lane(i).to_f64(),
            off_n: off_n.lane(i).to_f64(),
            distance_from_n: f64::NAN,
            x_phi: f64::NAN,
            along_n: f64::NAN,
            phase_error: [f64::NAN; 2],
        };
        out.1 = digits[i];
    }
    out
}

/// [`crate::digits::of_differences`] of each lane (d = |x − y|, y the exact states): the sizes
/// and scales in the lanes, the largest quotients lane by lane.
#[inline(always)]
fn digits<const L: usize>(d: &[Lanes<L>; 9], y: &[Lanes<L>; 9], ratio: f64) -> [(f64, f64); L] {
    let mut size = [Lanes::default(); 9];
    let mut scale = [Lanes::default(); 9];
    for k in 0..9 {
        size[k] = y[k].abs();
        scale[k] = size[k].add_f64([ratio; L]);
    }
    let mut out = [(0.0, 0.0); L];
    for (i, out) in out.iter_mut().enumerate() {
        let (mut di, mut si, mut ci) = ([Dd::ZERO; 9], [Dd::ZERO; 9], [Dd::ZERO; 9]);
        for k in 0..9 {
            (di[k], si[k], ci[k]) = (d[k].lane(i), size[k].lane(i), scale[k].lane(i));
        }
        *out = crate::digits::of_sizes(&di, &si, &ci);
    }
    out
}

/// 2u lane by lane.
#[inline(always)]
fn twice<const L: usize>(u: F64s<L>) -> F64s<L> {
    let mut out = u;
    for v in &mut out {
        *v *= 2.0;
    }
    out
}

/// u×v in double-double ([`rsts_dynamics::vec3::cross`]).
#[inline(always)]
fn cross<const L: usize>(u: &[Lanes<L>; 3], v: &[Lanes<L>; 3]) -> [Lanes<L>; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// u·v of an f64 vector and a double-double one.
#[inline(always)]
fn dot_f64_dd<const L: usize>(u: &[F64s<L>; 3], v: &[Lanes<L>; 3]) -> Lanes<L> {
    v[0].mul_f64(u[0]) + v[1].mul_f64(u[1]) + v[2].mul_f64(u[2])
}

/// u·v of two f64 vectors: three exact products summed in double-double.
#[inline(always)]
fn dot_f64<const L: usize>(u: &[F64s<L>], v: &[F64s<L>]) -> Lanes<L> {
    Lanes::prod_f64(u[0], v[0]) + Lanes::prod_f64(u[1], v[1]) + Lanes::prod_f64(u[2], v[2])
}

/// H, K, G of the f64 states `x` (`x[k]`: component k of each; the same operations as
/// [`rsts_dynamics::integrals::integrals`]).
#[inline(always)]
pub(crate) fn integrals_f64<const L: usize>(f: &Fields<Dd>, x: &[F64s<L>; 9]) -> [Lanes<L>; 3] {
    let (w1, w2, w3) = (x[0], x[1], x[2]);
    let (a, b) = (Lanes::splat(f.a), Lanes::splat(f.b));
    let big_a = [a.mul_f64(x[3]), a.mul_f64(x[4]), a.mul_f64(x[5])];
    let big_b = [b.mul_f64(x[6]), b.mul_f64(x[7]), b.mul_f64(x[8])];
    let (w1s, w2s) = (Lanes::prod_f64(w1, w1), Lanes::prod_f64(w2, w2));
    let h = w1s + w2s + Lanes::prod_f64(w3, w3).scale_exact(0.5) - (big_a[0] + big_b[1]);
    let kx = w1s - w2s + big_a[0] - big_b[1];
    let ky = Lanes::prod_f64(twice(w1), w2) + big_a[1] + big_b[0];
    let k = kx.sqr() + ky.sqr();
    let m = [twice(w1), twice(w2), w3];
    let ma = dot_f64_dd(&m, &big_a);
    let mb = dot_f64_dd(&m, &big_b);
    let mab = dot_f64_dd(&m, &cross(&big_a, &big_b));
    let g = (ma.sqr() + mb.sqr()).scale_exact(0.25) + mab.mul_f64(w3).scale_exact(0.5)
        - Lanes::splat(f.b.sqr()) * big_a[0]
        - Lanes::splat(f.a.sqr()) * big_b[1];
    [h, k, g]
}

/// max(||α|² − 1|, ||β|² − 1|, |α·β|) of the f64 states `x` ([`State::constraint_error`]).
#[inline(always)]
fn constraint_error<const L: usize>(x: &[F64s<L>; 9]) -> Lanes<L> {
    let (alpha, beta) = (&x[3..6], &x[6..9]);
    let one = Lanes::splat(Dd::ONE);
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
/// One sum per lane.
#[derive(Clone, Copy)]
struct ProductSum<const L: usize> {
    hi: F64s<L>,
    lo: F64s<L>,
}

impl<const L: usize> ProductSum<L> {
    const ZERO: Self = Self {
        hi: [0.0; L],
        lo: [0.0; L],
    };

    #[inline(always)]
    fn add(mut self, u: Lanes<L>, v: Lanes<L>) -> Self {
        for i in 0..L {
            let (p, e) = two_prod(u.hi[i], v.hi[i]);
            let (s, f) = two_sum(self.hi[i], p);
            self.hi[i] = s;
            self.lo[i] += f + u.hi[i].mul_add(v.lo[i], u.lo[i].mul_add(v.hi[i], e));
        }
        self
    }

    #[inline(always)]
    fn sub(self, u: Lanes<L>, v: Lanes<L>) -> Self {
        self.add(-u, v)
    }

    #[inline(always)]
    fn value(self) -> Lanes<L> {
        let mut out = Lanes::default();
        for i in 0..L {
            (out.hi[i], out.lo[i]) = quick_two_sum(self.hi[i], self.lo[i]);
        }
        out
    }
}

/// The rotation angle of R = Q Q̃ᵀ, Q of the f64 states `x` and Q̃ of the exact states `y`,
/// from the differences Δ = Q − Q̃ (`delta`: Δα, Δβ as measured for the state error): R − I =
/// ΔQ̃ᵀ up to Q̃Q̃ᵀ − I (~2⁻¹⁰⁶, symmetric: none in the skew part), so the skew part of R and
/// tr R − 3 are sums of products of the size of the angle, formed with error ~2⁻¹⁰⁶ of it
/// ([`rsts_dynamics::vec3::rotation_angle`] forms the entries of R ≈ I, error 2⁻¹⁰⁶ of 1).
#[inline(always)]
pub(crate) fn orientation_error<const L: usize>(
    x: &[F64s<L>; 9],
    y: &[Lanes<L>; 9],
    delta: &[Lanes<L>; 9],
) -> Lanes<L> {
    let (a, b) = (&y[3..6], &y[6..9]);
    let (da, db) = (&delta[3..6], &delta[6..9]);
    let beta = [x[6], x[7], x[8]].map(Lanes::from_f64_exact);
    // γ̃ = α̃×β̃ and Δγ = α×β − α̃×β̃ = Δα×β + α̃×Δβ (k, i, j cyclic).
    let mut c = [Lanes::default(); 3];
    let mut dc = [Lanes::default(); 3];
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        c[k] = ProductSum::ZERO.add(a[i], b[j]).sub(a[j], b[i]).value();
        let sum = ProductSum::ZERO.add(da[i], beta[j]).sub(da[j], beta[i]);
        dc[k] = sum.add(a[i], db[j]).sub(a[j], db[i]).value();
    }
    let q = [a, b, &c[..]];
    let dq = [da, db, &dc[..]];
    // The skew part s_k = R_ji − R_ij (k, i, j cyclic), R_ij − δ_ij = Δq_i·q̃_j.
    let mut s = [Lanes::default(); 3];
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
    let sin = norm2.value().sqrt().scale_exact(0.5);
    let cos = Lanes::splat(Dd::ONE) + trace.value().scale_exact(0.5);
    small_angle(sin, cos)
}

/// atan2(sin, cos) for sin ≥ 0, lane by lane: for tan θ = z < 2⁻¹⁴ the series z − z³/3 +
/// z⁵/5 − z⁷/7 + z⁹/9 (z³/3 in double-double; the rest, below 2⁻⁵⁶ z, in f64 from z.hi; the
/// next term is below 2⁻¹⁴⁰ z), otherwise by a table and a short series
/// ([`arctangent::arctangent`]). Each is computed only when a lane needs it.
#[inline(always)]
pub(crate) fn small_angle<const L: usize>(sin: Lanes<L>, cos: Lanes<L>) -> Lanes<L> {
    const LIMIT: f64 = 6.103515625e-5; // 2⁻¹⁴
    let mut series = [false; L];
    for i in 0..L {
        series[i] = (cos.hi[i] > 0.0) & (sin.hi[i] >= 0.0) & (sin.hi[i] < LIMIT * cos.hi[i]);
    }
    let mut angle = Lanes::default();
    if !every_lane(series.map(|s| !s)) {
        let z = sin / cos;
        let w = z.sqr();
        let mut tail = [0.0; L];
        for i in 0..L {
            let (z, w) = (z.hi[i], w.hi[i]);
            tail[i] = z * w * w * (0.2 - w * (1.0 / 7.0 - w / 9.0));
        }
        angle = (z - z * w * Lanes::splat(arctangent::THIRD)).add_f64(tail);
    }
    if !every_lane(series) {
        angle = Lanes::select(series, angle, arctangent::arctangent(sin, cos));
    }
    angle
}

mod arctangent;
mod atan_table;

#[cfg(test)]
mod tests;
