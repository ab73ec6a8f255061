//! Numbers kept as unevaluated sums of K doubles ("expansions": K = 1 is f64, K = 2
//! double-double, K = 3 triple-double), in scalars or lane-wise in vectors ([`Arith`]).
//!
//! The Taylor kernels compute in K parts: the Cauchy sums in the kernel's precision (1 part
//! for taylor-f64, 2 for taylor-dd) and the few quantities that need one part more (the
//! compensated state, x₁ and x₂, the update terms x₁h and x₂h²). Everything is made of
//! error-free transformations (`two_sum`, the path's exact product [`Arith::two_prod`]); only
//! the last part is rounded.

// Index loops on purpose: this code is inlined into `#[target_feature]` functions, and plain
// loops over constant ranges unroll there without any closure (a function of its own,
// compiled without the path's features).
#![allow(clippy::needless_range_loop)]

use std::marker::PhantomData;

use super::simd::Isa;

/// Arithmetic on one kind of number: scalars or lane vectors of a code path.
pub(crate) trait Arith: Copy + 'static {
    type T: Copy;
    unsafe fn zero() -> Self::T;
    unsafe fn add(a: Self::T, b: Self::T) -> Self::T;
    unsafe fn sub(a: Self::T, b: Self::T) -> Self::T;
    unsafe fn mul(a: Self::T, b: Self::T) -> Self::T;
    /// a·b + c (fused where the path has FMA).
    unsafe fn mul_add(a: Self::T, b: Self::T, c: Self::T) -> Self::T;
    /// (p, e): p = fl(a·b), p + e = a·b exactly.
    unsafe fn two_prod(a: Self::T, b: Self::T) -> (Self::T, Self::T);
}

/// Scalars of path `I` (its exact product: FMA or Dekker's).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scalar<I>(PhantomData<I>);

/// 8-lane vectors of path `I`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lanes<I>(PhantomData<I>);

impl<I: Isa> Arith for Scalar<I> {
    type T = f64;
    #[inline(always)]
    unsafe fn zero() -> f64 {
        0.0
    }
    #[inline(always)]
    unsafe fn add(a: f64, b: f64) -> f64 {
        a + b
    }
    #[inline(always)]
    unsafe fn sub(a: f64, b: f64) -> f64 {
        a - b
    }
    #[inline(always)]
    unsafe fn mul(a: f64, b: f64) -> f64 {
        a * b
    }
    #[inline(always)]
    unsafe fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        I::mul_add_f64(a, b, c)
    }
    #[inline(always)]
    unsafe fn two_prod(a: f64, b: f64) -> (f64, f64) {
        I::two_prod_f64(a, b)
    }
}

impl<I: Isa> Arith for Lanes<I> {
    type T = I::V;
    #[inline(always)]
    unsafe fn zero() -> I::V {
        I::zero()
    }
    #[inline(always)]
    unsafe fn add(a: I::V, b: I::V) -> I::V {
        I::add(a, b)
    }
    #[inline(always)]
    unsafe fn sub(a: I::V, b: I::V) -> I::V {
        I::sub(a, b)
    }
    #[inline(always)]
    unsafe fn mul(a: I::V, b: I::V) -> I::V {
        I::mul(a, b)
    }
    #[inline(always)]
    unsafe fn mul_add(a: I::V, b: I::V, c: I::V) -> I::V {
        I::mul_add(a, b, c)
    }
    #[inline(always)]
    unsafe fn two_prod(a: I::V, b: I::V) -> (I::V, I::V) {
        I::two_prod(a, b)
    }
}

/// Knuth's error-free sum: s + e = a + b exactly, s = fl(a + b).
#[inline(always)]
pub(crate) unsafe fn two_sum<A: Arith>(a: A::T, b: A::T) -> (A::T, A::T) {
    let s = A::add(a, b);
    let bb = A::sub(s, a);
    let e = A::add(A::sub(a, A::sub(s, bb)), A::sub(b, bb));
    (s, e)
}

/// Dekker's error-free sum for |a| ≥ |b| (or a = 0).
#[inline(always)]
pub(crate) unsafe fn quick_two_sum<A: Arith>(a: A::T, b: A::T) -> (A::T, A::T) {
    let s = A::add(a, b);
    let e = A::sub(b, A::sub(s, a));
    (s, e)
}

/// Renormalise K parts (same sum, exactly): parts non-overlapping, largest first.
#[inline(always)]
pub(crate) unsafe fn renormalize<A: Arith, const K: usize>(mut p: [A::T; K]) -> [A::T; K] {
    if K == 1 {
        return p;
    }
    for i in (0..K - 1).rev() {
        (p[i], p[i + 1]) = two_sum::<A>(p[i], p[i + 1]);
    }
    for i in 1..K - 1 {
        (p[i], p[i + 1]) = two_sum::<A>(p[i], p[i + 1]);
    }
    (p[0], p[1]) = quick_two_sum::<A>(p[0], p[1]);
    p
}

/// An accumulator by levels: part `l` collects terms of size ~ 2^(−53 l) relative to the
/// whole (the product of parts i and j goes to level i + j). A term added at level l is
/// summed with two_sum and its rounding error cascades to the next level; the last level is
/// summed plainly, or, with `G` (guarded, for long sums such as the Cauchy sums), with
/// two_sum too, its errors into a guard: a long sum then loses about one unit of the last
/// part, not one per term.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Acc<A: Arith, const K: usize, const G: bool = false> {
    parts: [A::T; K],
    guard: A::T,
}

impl<A: Arith, const K: usize, const G: bool> Acc<A, K, G> {
    #[inline(always)]
    pub unsafe fn zero() -> Self {
        Self {
            parts: [A::zero(); K],
            guard: A::zero(),
        }
    }

    /// Start from the value `x`.
    #[inline(always)]
    pub unsafe fn from(x: [A::T; K]) -> Self {
        Self {
            parts: x,
            guard: A::zero(),
        }
    }

    /// Add v at `level` < K − 1, cascading; what reaches the last level goes into `last`.
    #[inline(always)]
    unsafe fn cascade(&mut self, level: usize, v: A::T, last: &mut A::T) {
        let mut v = v;
        let mut l = level;
        while l + 1 < K {
            let (s, e) = two_sum::<A>(self.parts[l], v);
            self.parts[l] = s;
            v = e;
            l += 1;
        }
        *last = A::add(*last, v);
    }

    /// Add `last` to the last level (K ≥ 2), guarded: its rounding error to the guard.
    #[inline(always)]
    unsafe fn add_last(&mut self, last: A::T) {
        if G {
            let (s, e) = two_sum::<A>(self.parts[K - 1], last);
            self.parts[K - 1] = s;
            self.guard = A::add(self.guard, e);
        } else {
            self.parts[K - 1] = A::add(self.parts[K - 1], last);
        }
    }

    /// Add every part of `x` at its level.
    #[inline(always)]
    pub unsafe fn add_exp(&mut self, x: &[A::T; K]) {
        if K == 1 {
            self.parts[0] = A::add(self.parts[0], x[0]);
            return;
        }
        let mut last = x[K - 1];
        for l in 0..K - 1 {
            self.cascade(l, x[l], &mut last);
        }
        self.add_last(last);
    }

    /// Add a·b: the products of parts below level K − 1 exactly (two_prod), those at level
    /// K − 1 rounded (fused multiply-adds into one local sum, added once). K = 1 is one fused
    /// multiply-add.
    #[inline(always)]
    pub unsafe fn add_prod(&mut self, a: &[A::T; K], b: &[A::T; K]) {
        if K == 1 {
            self.parts[0] = A::mul_add(a[0], b[0], self.parts[0]);
            return;
        }
        // The rounded products of the last level first (no addition of a zero: x + 0 is
        // not folded in floating point).
        let mut last = A::mul(a[0], b[K - 1]);
        for i in 1..K {
            last = A::mul_add(a[i], b[K - 1 - i], last);
        }
        for l in 0..K - 1 {
            for i in 0..=l {
                let (p, e) = A::two_prod(a[i], b[l - i]);
                self.cascade(l, p, &mut last);
                if l + 2 == K {
                    last = A::add(last, e);
                } else {
                    self.cascade(l + 1, e, &mut last);
                }
            }
        }
        self.add_last(last);
    }

    /// The sum, renormalised.
    #[inline(always)]
    pub unsafe fn value(&self) -> [A::T; K] {
        let mut p = self.parts;
        if G && K > 1 {
            p[K - 1] = A::add(p[K - 1], self.guard);
        }
        renormalize::<A, K>(p)
    }
}

/// a·b for K-part numbers (truncated as in [`Acc::add_prod`]), renormalised.
#[inline(always)]
pub(crate) unsafe fn mul<A: Arith, const K: usize>(a: &[A::T; K], b: &[A::T; K]) -> [A::T; K] {
    let mut acc = Acc::<A, K>::zero();
    acc.add_prod(a, b);
    acc.value()
}

/// Is x a power of two, zero or ±1? (multiplying by it is exact, barring under/overflow)
pub(crate) fn exact_scale(x: f64) -> bool {
    x == 0.0 || (x.is_finite() && x.abs().log2().fract() == 0.0)
}

#[cfg(test)]
mod tests {
    use super::super::simd::portable::Portable;
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rug::Float;

    type S = Scalar<Portable>;

    fn to_float<const K: usize>(x: &[f64; K]) -> Float {
        let mut f = Float::with_val(400, 0);
        for p in x {
            f += p;
        }
        f
    }

    /// A random K-part number near 1: successive residuals of a 400-bit value.
    fn random<const K: usize>(rng: &mut ChaCha8Rng) -> [f64; K] {
        let mut rest: Float = Float::with_val(400, rng.gen_range(-2.0..2.0))
            + Float::with_val(400, rng.gen_range(-1.0..1.0)) * 1e-17
            + Float::with_val(400, rng.gen_range(-1.0..1.0)) * 1e-34
            + Float::with_val(400, rng.gen_range(-1.0..1.0)) * 1e-51;
        std::array::from_fn(|_| {
            let p = rest.to_f64();
            rest -= p;
            p
        })
    }

    /// Products and sums of K-part numbers are accurate to ~2^(−53K) (against MPFR at 400
    /// bits): a·b + c within 2⁻¹⁰² of |ab| + |c| for K = 2, 2⁻¹⁵² for K = 3, and renormalised;
    /// an f64 product misses the K = 2 bound (the check is not vacuous).
    #[test]
    fn products_and_sums_are_accurate_to_k_doubles() {
        fn check<const K: usize>(bound: f64) {
            let mut rng = ChaCha8Rng::seed_from_u64(K as u64);
            for _ in 0..500 {
                let (a, b, c) = (
                    random::<K>(&mut rng),
                    random::<K>(&mut rng),
                    random(&mut rng),
                );
                let got = unsafe {
                    let mut acc = Acc::<S, K>::zero();
                    acc.add_prod(&a, &b);
                    acc.add_exp(&c);
                    acc.value()
                };
                let exact = to_float(&a) * to_float(&b) + to_float(&c);
                let err = Float::with_val(400, &to_float(&got) - &exact)
                    .abs()
                    .to_f64();
                let scale = (to_float(&a) * to_float(&b)).abs().to_f64() + c[0].abs();
                assert!(
                    err <= bound * scale,
                    "K = {K}: error {err:e}, scale {scale}"
                );
                for i in 1..K {
                    assert!(got[i].abs() <= got[i - 1].abs() * 2f64.powi(-52), "{got:?}");
                }
            }
        }
        check::<2>(2f64.powi(-102));
        check::<3>(2f64.powi(-152));
        let a = [1.0 / 3.0, 1.850371707708594e-17];
        let plain = [a[0] * a[0], 0.0];
        let exact = to_float(&a) * to_float(&a);
        let err = Float::with_val(400, &to_float(&plain) - &exact)
            .abs()
            .to_f64();
        assert!(err > 2f64.powi(-102), "{err:e}");
    }

    #[test]
    fn exact_scales() {
        for x in [0.0, 1.0, -1.0, 0.5, -0.5, 4.0] {
            assert!(exact_scale(x), "{x}");
        }
        for x in [0.3, 3.0, -0.75, f64::NAN, f64::INFINITY] {
            assert!(!exact_scale(x), "{x}");
        }
    }
}
