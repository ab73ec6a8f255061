//! The AVX-512F path: a row is one 8-lane register; a lane permutation is one `vpermt2pd` over
//! the 16 lanes of (Q lanes, N values) with zero-masking.

use std::arch::x86_64::*;

use super::super::layout::{PermSpec, LANES, NMAX};
use super::{Isa, Row8};

#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512;

#[derive(Clone, Copy, Debug)]
pub(crate) struct Perm {
    idx: __m512i,
    keep: __mmask8,
}

impl Isa for Avx512 {
    type V = __m512d;
    type P = Perm;

    #[inline(always)]
    unsafe fn zero() -> __m512d {
        _mm512_setzero_pd()
    }
    #[inline(always)]
    unsafe fn splat(x: f64) -> __m512d {
        _mm512_set1_pd(x)
    }
    #[inline(always)]
    unsafe fn load(r: &Row8) -> __m512d {
        _mm512_load_pd(r.0.as_ptr())
    }
    #[inline(always)]
    unsafe fn store(v: __m512d, r: &mut Row8) {
        _mm512_store_pd(r.0.as_mut_ptr(), v)
    }
    #[inline(always)]
    unsafe fn add(a: __m512d, b: __m512d) -> __m512d {
        _mm512_add_pd(a, b)
    }
    #[inline(always)]
    unsafe fn sub(a: __m512d, b: __m512d) -> __m512d {
        _mm512_sub_pd(a, b)
    }
    #[inline(always)]
    unsafe fn mul(a: __m512d, b: __m512d) -> __m512d {
        _mm512_mul_pd(a, b)
    }
    #[inline(always)]
    unsafe fn mul_add(a: __m512d, b: __m512d, c: __m512d) -> __m512d {
        _mm512_fmadd_pd(a, b, c)
    }
    #[inline(always)]
    unsafe fn two_prod(a: __m512d, b: __m512d) -> (__m512d, __m512d) {
        let p = _mm512_mul_pd(a, b);
        (p, _mm512_fmsub_pd(a, b, p))
    }
    unsafe fn prepare(spec: &PermSpec) -> Perm {
        // vpermt2pd: index 0..8 selects from the first source (Q lanes), 8..16 from the second
        // (N values).
        let mut idx = [0i64; LANES];
        let mut keep: __mmask8 = 0;
        for (l, s) in spec.iter().enumerate() {
            if let Some(s) = *s {
                assert!(s < LANES + NMAX, "source position {s} out of range");
                idx[l] = s as i64;
                keep |= 1 << l;
            }
        }
        Perm {
            idx: _mm512_loadu_si512(idx.as_ptr().cast()),
            keep,
        }
    }
    #[inline(always)]
    unsafe fn permute(q: __m512d, n: __m512d, p: &Perm) -> __m512d {
        _mm512_maskz_permutex2var_pd(p.keep, q, p.idx, n)
    }
    #[inline(always)]
    unsafe fn max_abs(v: __m512d) -> f64 {
        _mm512_reduce_max_pd(_mm512_abs_pd(v))
    }
    #[inline(always)]
    unsafe fn two_prod_f64(a: f64, b: f64) -> (f64, f64) {
        let p = a * b;
        (p, a.mul_add(b, -p))
    }
    #[inline(always)]
    unsafe fn mul_add_f64(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}
