//! [`f64_sample_errors`] of four samples at once, in the lanes of [`DoubleDouble4`]: every
//! double-double operation of the scalar kernel applied to each lane (the same IEEE
//! operations, the same fused multiply-adds), so that a caller compiled with AVX2 and FMA runs
//! the four samples in one 256-bit register, and each lane is the scalar kernel's result bit
//! for bit (tested). A group with a non-finite value, and a lane whose orientation error
//! leaves the small-angle series (tan θ ≥ 2⁻¹⁴), take the scalar kernel.

use rsts_dynamics::scalar::double_double::{quick_two_sum, two_prod, two_sum};
use rsts_dynamics::scalar::{every_lane, DoubleDouble4, LANES};

use super::*;

type D4 = DoubleDouble4;
/// Four f64, one per lane.
type F4 = [f64; LANES];

/// A [`DoubleDouble4`] whose lane `$i` is the [`DoubleDouble`] expression `$e`.
macro_rules! lanes {
    (|$i:ident| $e:expr) => {{
        let mut out = D4::default();
        for $i in 0..LANES {
            let r: Dd = $e;
            out.hi[$i] = r.hi;
            out.lo[$i] = r.lo;
        }
        out
    }};
}

/// [`f64_sample_errors`] of the four samples `x[i]` against `exact[i]` (slices of [`LANES`])
/// and the relative and mixed errors of their digits ([`crate::digits::of_differences`],
/// atol/rtol = `ratio`): the same numbers, bit for bit. Plain loops and branch-free lanes
/// (no closure handed to a library function: compiled with the caller's AVX2 and FMA).
#[inline(always)]
pub(crate) fn f64_sample_errors4(
    fields: &Fields<Dd>,
    n: &ManifoldN<Dd>,
    initial_integrals: &[Dd; 3],
    exact: &[State<Dd>],
    x: &[[f64; 9]],
    ratio: f64,
) -> [(SampleErrors, (f64, f64)); LANES] {
    let mut out = [(SampleErrors::default(), (0.0, 0.0)); LANES];
    let mut xs = [[0.0; LANES]; 9];
    let mut y = [D4::default(); 9];
    let mut finite = true;
    for i in 0..LANES {
        let yi = exact[i].to_array();
        for k in 0..9 {
            xs[k][i] = x[i][k];
            y[k].hi[i] = yi[k].hi;
            y[k].lo[i] = yi[k].lo;
            finite &= x[i][k].is_finite() & yi[k].hi.is_finite() & yi[k].lo.is_finite();
        }
    }
    if !finite {
        for (i, out) in out.iter_mut().enumerate() {
            let (errors, d) = f64_sample_errors(fields, n, initial_integrals, &exact[i], &x[i]);
            let digits = crate::digits::of_differences(&d, &exact[i].to_array(), ratio);
            *out = (errors, digits);
        }
        return out;
    }
    let mut delta = [D4::default(); 9];
    let mut d = [D4::default(); 9];
    let mut state_error = D4::splat(Dd::ZERO);
    for k in 0..9 {
        delta[k] = exact4(xs[k]) - y[k];
        d[k] = abs4(delta[k]);
        state_error = max4(state_error, d[k]);
    }
    let [h, k, g] = integrals4(fields, &xs);
    let two = D4::splat(Dd::from_f64_exact(2.0));
    let off_k = abs4(k - D4::splat(n.k));
    let off_g = abs4(two * g - D4::splat(n.p2) * h - D4::splat(n.r4m));
    let theta = orientation_error4(&xs, &y, &delta);
    let i0 = initial_integrals;
    let drift_h = abs4(h - D4::splat(i0[0]));
    let drift_k = abs4(k - D4::splat(i0[1]));
    let drift_g = abs4(g - D4::splat(i0[2]));
    let constraint = constraint_error4(&xs);
    let off_n = max4(off_k, off_g);
    let digits = digits4(&d, &y, ratio);
    for (i, out) in out.iter_mut().enumerate() {
        out.0 = SampleErrors {
            state_error: state_error.lane(i).to_f64(),
            orientation_error: theta.lane(i).to_f64(),
            drift_h: drift_h.lane(i).to_f64(),
            drift_k: drift_k.lane(i).to_f64(),
            drift_g: drift_g.lane(i).to_f64(),
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

/// |v| lane by lane, branch-free: the scalar [`Real::abs`] (negated where the sign of the
/// high part is set and it is no NaN: a sign flip of both parts).
#[inline(always)]
fn abs4(v: D4) -> D4 {
    let mut out = v;
    for i in 0..LANES {
        let h = v.hi[i];
        let flip = u64::from(h.is_sign_negative() & !h.is_nan()) << 63;
        out.hi[i] = f64::from_bits(h.to_bits() ^ flip);
        out.lo[i] = f64::from_bits(v.lo[i].to_bits() ^ flip);
    }
    out
}

/// The larger of u and v lane by lane, branch-free: the scalar [`Real::max_of`] (v where
/// v > u in the order of (hi, lo), else u).
#[inline(always)]
fn max4(u: D4, v: D4) -> D4 {
    let mut out = u;
    for i in 0..LANES {
        let greater = (v.hi[i] > u.hi[i]) | ((v.hi[i] == u.hi[i]) & (v.lo[i] > u.lo[i]));
        let mask = 0u64.wrapping_sub(u64::from(greater));
        out.hi[i] = f64::from_bits((v.hi[i].to_bits() & mask) | (u.hi[i].to_bits() & !mask));
        out.lo[i] = f64::from_bits((v.lo[i].to_bits() & mask) | (u.lo[i].to_bits() & !mask));
    }
    out
}

/// [`crate::digits::of_differences`] of four samples (d = |x − y|, y the exact states): the
/// sizes and scales in the lanes, the largest quotients lane by lane.
#[inline(always)]
fn digits4(d: &[D4; 9], y: &[D4; 9], ratio: f64) -> [(f64, f64); LANES] {
    let mut size = [D4::default(); 9];
    let mut scale = [D4::default(); 9];
    for k in 0..9 {
        size[k] = abs4(y[k]);
        scale[k] = lanes!(|i| size[k].lane(i).add_f64(ratio));
    }
    let mut out = [(0.0, 0.0); LANES];
    for (i, out) in out.iter_mut().enumerate() {
        let (mut di, mut si, mut ci) = ([Dd::ZERO; 9], [Dd::ZERO; 9], [Dd::ZERO; 9]);
        for k in 0..9 {
            (di[k], si[k], ci[k]) = (d[k].lane(i), size[k].lane(i), scale[k].lane(i));
        }
        *out = crate::digits::of_sizes(&di, &si, &ci);
    }
    out
}

/// Four f64, exactly.
#[inline(always)]
fn exact4(x: F4) -> D4 {
    D4 {
        hi: x,
        lo: [0.0; LANES],
    }
}

/// u·v lane by lane, exactly.
#[inline(always)]
fn prod4(u: F4, v: F4) -> D4 {
    lanes!(|i| prod(u[i], v[i]))
}

/// 2u lane by lane.
#[inline(always)]
fn twice(u: F4) -> F4 {
    u.map(|u| 2.0 * u)
}

/// v/2 lane by lane ([`half`]).
#[inline(always)]
fn half4(v: D4) -> D4 {
    lanes!(|i| half(v.lane(i)))
}

/// u×v ([`cross_dd`]).
#[inline(always)]
fn cross4(u: &[D4; 3], v: &[D4; 3]) -> [D4; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// u·v of f64 lanes and double-doubles ([`dot_f64_dd`]).
#[inline(always)]
fn dot4_f64_dd(u: &[F4; 3], v: &[D4; 3]) -> D4 {
    v[0].mul_f64(u[0]) + v[1].mul_f64(u[1]) + v[2].mul_f64(u[2])
}

/// u·v of f64 lanes ([`dot_f64`]).
#[inline(always)]
fn dot4_f64(u: &[F4], v: &[F4]) -> D4 {
    prod4(u[0], v[0]) + prod4(u[1], v[1]) + prod4(u[2], v[2])
}

/// [`integrals_f64`] of four states (`x[k]`: component k of each).
#[inline(always)]
fn integrals4(f: &Fields<Dd>, x: &[F4; 9]) -> [D4; 3] {
    let (w1, w2, w3) = (x[0], x[1], x[2]);
    let (a, b) = (D4::splat(f.a), D4::splat(f.b));
    let big_a = [a.mul_f64(x[3]), a.mul_f64(x[4]), a.mul_f64(x[5])];
    let big_b = [b.mul_f64(x[6]), b.mul_f64(x[7]), b.mul_f64(x[8])];
    let (w1s, w2s) = (prod4(w1, w1), prod4(w2, w2));
    let h = w1s + w2s + half4(prod4(w3, w3)) - (big_a[0] + big_b[1]);
    let kx = w1s - w2s + big_a[0] - big_b[1];
    let ky = prod4(twice(w1), w2) + big_a[1] + big_b[0];
    let k = kx.sqr() + ky.sqr();
    let m = [twice(w1), twice(w2), w3];
    let ma = dot4_f64_dd(&m, &big_a);
    let mb = dot4_f64_dd(&m, &big_b);
    let mab = dot4_f64_dd(&m, &cross4(&big_a, &big_b));
    let g = lanes!(|i| quarter((ma.sqr() + mb.sqr()).lane(i))) + half4(mab.mul_f64(w3))
        - D4::splat(f.b.sqr()) * big_a[0]
        - D4::splat(f.a.sqr()) * big_b[1];
    [h, k, g]
}

/// [`constraint_error`] of four states.
#[inline(always)]
fn constraint_error4(x: &[F4; 9]) -> D4 {
    let (alpha, beta) = (&x[3..6], &x[6..9]);
    let one = D4::splat(Dd::ONE);
    let r = [
        dot4_f64(alpha, alpha) - one,
        dot4_f64(beta, beta) - one,
        dot4_f64(alpha, beta),
    ];
    max4(max4(abs4(r[0]), abs4(r[1])), abs4(r[2]))
}

/// [`ProductSum`] in four lanes.
#[derive(Clone, Copy)]
struct ProductSum4 {
    hi: F4,
    lo: F4,
}

impl ProductSum4 {
    const ZERO: Self = Self {
        hi: [0.0; LANES],
        lo: [0.0; LANES],
    };

    #[inline(always)]
    fn add(mut self, u: D4, v: D4) -> Self {
        for i in 0..LANES {
            let (p, e) = two_prod(u.hi[i], v.hi[i]);
            let (s, f) = two_sum(self.hi[i], p);
            self.hi[i] = s;
            self.lo[i] += f + u.hi[i].mul_add(v.lo[i], u.lo[i].mul_add(v.hi[i], e));
        }
        self
    }

    #[inline(always)]
    fn sub(self, u: D4, v: D4) -> Self {
        self.add(-u, v)
    }

    #[inline(always)]
    fn value(self) -> D4 {
        let mut out = D4::default();
        for i in 0..LANES {
            (out.hi[i], out.lo[i]) = quick_two_sum(self.hi[i], self.lo[i]);
        }
        out
    }
}

/// [`orientation_error`] of four samples (`y`: their exact states, `delta`: x − y).
#[inline(always)]
fn orientation_error4(x: &[F4; 9], y: &[D4; 9], delta: &[D4; 9]) -> D4 {
    let (a, b) = (&y[3..6], &y[6..9]);
    let (da, db) = (&delta[3..6], &delta[6..9]);
    let beta = [exact4(x[6]), exact4(x[7]), exact4(x[8])];
    let mut c = [D4::default(); 3];
    let mut dc = [D4::default(); 3];
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        c[k] = ProductSum4::ZERO.add(a[i], b[j]).sub(a[j], b[i]).value();
        let sum = ProductSum4::ZERO.add(da[i], beta[j]).sub(da[j], beta[i]);
        dc[k] = sum.add(a[i], db[j]).sub(a[j], db[i]).value();
    }
    let q = [a, b, &c[..]];
    let dq = [da, db, &dc[..]];
    let mut s = [D4::default(); 3];
    for (k, sk) in s.iter_mut().enumerate() {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let mut sum = ProductSum4::ZERO;
        for l in 0..3 {
            sum = sum.add(dq[j][l], q[i][l]).sub(dq[i][l], q[j][l]);
        }
        *sk = sum.value();
    }
    let mut trace = ProductSum4::ZERO;
    for n in 0..9 {
        trace = trace.add(dq[n / 3][n % 3], q[n / 3][n % 3]);
    }
    let mut norm2 = ProductSum4::ZERO;
    for v in s {
        norm2 = norm2.add(v, v);
    }
    let sin = half4(norm2.value().sqrt());
    let cos = D4::splat(Dd::ONE) + half4(trace.value());
    small_angle4(sin, cos)
}

/// [`small_angle`] of four lanes: its series in the lanes, a lane beyond it by the scalar
/// function.
#[inline(always)]
fn small_angle4(sin: D4, cos: D4) -> D4 {
    const LIMIT: f64 = 6.103515625e-5; // 2⁻¹⁴, as small_angle's
    const THIRD: Dd = Dd {
        hi: 0.3333333333333333,
        lo: 1.850371707708594e-17,
    };
    let series: [bool; LANES] = std::array::from_fn(|i| {
        cos.hi[i] > 0.0 && sin.hi[i] >= 0.0 && sin.hi[i] < LIMIT * cos.hi[i]
    });
    let z = sin / cos;
    let w = z.sqr();
    let mut tail = [0.0; LANES];
    for ((t, z), w) in tail.iter_mut().zip(z.hi).zip(w.hi) {
        *t = z * w * w * (0.2 - w * (1.0 / 7.0 - w / 9.0));
    }
    let mut angle = z - z * w * D4::splat(THIRD);
    angle = lanes!(|i| angle.lane(i).add_f64(tail[i]));
    if !every_lane(series) {
        let (table, valid) = arctangent4(sin, cos);
        for (i, series) in series.into_iter().enumerate() {
            if !series {
                let lane = if valid[i] {
                    table.lane(i)
                } else {
                    small_angle(sin.lane(i), cos.lane(i))
                };
                angle.set_lane(i, lane);
            }
        }
    }
    angle
}

/// [`arctangent::arctangent`] of four lanes, the table's point chosen per lane, and where it
/// holds (false: a zero or non-finite argument, which the scalar function hands to atan2).
#[inline(always)]
fn arctangent4(sin: D4, cos: D4) -> (D4, [bool; LANES]) {
    use super::arctangent::{FIFTH, HALF_PI, STEPS, THIRD};
    use super::atan_table::ATAN;
    let across = abs4(cos);
    let mut swap = [false; LANES];
    let (mut a, mut b) = (sin, across);
    let mut valid = [false; LANES];
    let mut k = [0usize; LANES];
    let mut c = [0.0; LANES];
    let mut table = D4::default();
    for i in 0..LANES {
        swap[i] = sin.hi[i] > across.hi[i];
        if swap[i] {
            a.set_lane(i, across.lane(i));
            b.set_lane(i, sin.lane(i));
        }
        valid[i] = b.hi[i] > 0.0 && b.hi[i].is_finite() && a.hi[i] >= 0.0;
        let nearest = if valid[i] {
            a.hi[i] / b.hi[i] * f64::from(STEPS) + 0.5
        } else {
            0.0
        };
        k[i] = (nearest as usize).min(STEPS as usize);
        c[i] = k[i] as f64 / f64::from(STEPS);
        (table.hi[i], table.lo[i]) = ATAN[k[i]];
    }
    let u = (a - b.mul_f64(c)) / (b + a.mul_f64(c));
    let w = u.sqr();
    let mut tail = [0.0; LANES];
    for ((t, u), w1) in tail.iter_mut().zip(u.hi).zip(w.hi) {
        *t = u * w1 * w1 * w1 * (-1.0 / 7.0 + w1 * (1.0 / 9.0 - w1 * (1.0 / 11.0 - w1 / 13.0)));
    }
    let series = u - u * w * (D4::splat(THIRD) - w * D4::splat(FIFTH));
    let z = table + lanes!(|i| series.lane(i).add_f64(tail[i]));
    let angle = D4::select(swap, D4::splat(HALF_PI) - z, z);
    let mut behind = [false; LANES];
    for (behind, h) in behind.iter_mut().zip(cos.hi) {
        *behind = h < 0.0;
    }
    (D4::select(behind, D4::splat(Dd::PI) - angle, angle), valid)
}

#[cfg(test)]
mod tests;
