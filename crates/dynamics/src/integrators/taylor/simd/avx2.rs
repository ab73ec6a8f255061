//! The AVX2 + FMA path: a row is two 4-lane registers; lane permutations from a runtime table
//! with `vpermps` (doubles moved as pairs of 32-bit halves) and blends.

use std::arch::x86_64::*;

use super::super::layout::{PermSpec, LANES};
use super::{Isa, Row8};

#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2;

/// 8 lanes: lanes 0..4 in `lo`, 4..8 in `hi`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V {
    lo: __m256d,
    hi: __m256d,
}

/// One 4-lane half of a permutation: `vpermps` indices (within a source register) and the
/// masks of the lanes taken from the high Q register and from the N register. A lane with no
/// source reads N lane 3, which is always zero (at most 3 N values: [`NMAX`] − 1 < 4).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Half {
    idx: __m256i,
    from_hi: __m256d,
    from_n: __m256d,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Perm([Half; 2]);

#[inline(always)]
unsafe fn mask(bits: [bool; 4]) -> __m256d {
    let m = bits.map(|b| if b { -1i64 } else { 0 });
    _mm256_castsi256_pd(_mm256_set_epi64x(m[3], m[2], m[1], m[0]))
}

#[inline(always)]
unsafe fn gather(src: __m256d, idx: __m256i) -> __m256d {
    _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(src), idx))
}

/// Branch-free: three `vpermps` and two blends.
#[inline(always)]
unsafe fn permute_half(q: &V, n: &V, h: &Half) -> __m256d {
    let v = _mm256_blendv_pd(gather(q.lo, h.idx), gather(q.hi, h.idx), h.from_hi);
    _mm256_blendv_pd(v, gather(n.lo, h.idx), h.from_n)
}

impl Isa for Avx2 {
    type V = V;
    type P = Perm;

    #[inline(always)]
    unsafe fn zero() -> V {
        V {
            lo: _mm256_setzero_pd(),
            hi: _mm256_setzero_pd(),
        }
    }
    #[inline(always)]
    unsafe fn splat(x: f64) -> V {
        let v = _mm256_set1_pd(x);
        V { lo: v, hi: v }
    }
    #[inline(always)]
    unsafe fn load(r: &Row8) -> V {
        let p = r.0.as_ptr();
        V {
            lo: _mm256_load_pd(p),
            hi: _mm256_load_pd(p.add(4)),
        }
    }
    #[inline(always)]
    unsafe fn store(v: V, r: &mut Row8) {
        let p = r.0.as_mut_ptr();
        _mm256_store_pd(p, v.lo);
        _mm256_store_pd(p.add(4), v.hi);
    }
    #[inline(always)]
    unsafe fn add(a: V, b: V) -> V {
        V {
            lo: _mm256_add_pd(a.lo, b.lo),
            hi: _mm256_add_pd(a.hi, b.hi),
        }
    }
    #[inline(always)]
    unsafe fn sub(a: V, b: V) -> V {
        V {
            lo: _mm256_sub_pd(a.lo, b.lo),
            hi: _mm256_sub_pd(a.hi, b.hi),
        }
    }
    #[inline(always)]
    unsafe fn mul(a: V, b: V) -> V {
        V {
            lo: _mm256_mul_pd(a.lo, b.lo),
            hi: _mm256_mul_pd(a.hi, b.hi),
        }
    }
    #[inline(always)]
    unsafe fn mul_add(a: V, b: V, c: V) -> V {
        V {
            lo: _mm256_fmadd_pd(a.lo, b.lo, c.lo),
            hi: _mm256_fmadd_pd(a.hi, b.hi, c.hi),
        }
    }
    #[inline(always)]
    unsafe fn two_prod(a: V, b: V) -> (V, V) {
        let p = Self::mul(a, b);
        let e = V {
            lo: _mm256_fmsub_pd(a.lo, b.lo, p.lo),
            hi: _mm256_fmsub_pd(a.hi, b.hi, p.hi),
        };
        (p, e)
    }
    unsafe fn prepare(spec: &PermSpec) -> Perm {
        Perm(std::array::from_fn(|half| {
            // No source: N lane 3, always zero.
            let lanes: [usize; 4] =
                std::array::from_fn(|l| spec[4 * half + l].unwrap_or(LANES + 3));
            for &s in &lanes {
                assert!(s < LANES + 4, "source position {s} out of range");
            }
            // Within its source register, lane s % 4 is 32-bit elements 2(s % 4), 2(s % 4) + 1.
            let e: [i32; 8] = std::array::from_fn(|k| (2 * (lanes[k / 2] % 4) + k % 2) as i32);
            Half {
                idx: _mm256_setr_epi32(e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7]),
                from_hi: mask(std::array::from_fn(|l| lanes[l] / 4 == 1)),
                from_n: mask(std::array::from_fn(|l| lanes[l] / 4 == 2)),
            }
        }))
    }
    #[inline(always)]
    unsafe fn permute(q: V, n: V, p: &Perm) -> V {
        V {
            lo: permute_half(&q, &n, &p.0[0]),
            hi: permute_half(&q, &n, &p.0[1]),
        }
    }
    #[inline(always)]
    unsafe fn max_abs(v: V) -> f64 {
        let sign = _mm256_set1_pd(-0.0);
        let m = _mm256_max_pd(_mm256_andnot_pd(sign, v.lo), _mm256_andnot_pd(sign, v.hi));
        let m2 = _mm_max_pd(_mm256_castpd256_pd128(m), _mm256_extractf128_pd(m, 1));
        let m1 = _mm_max_sd(m2, _mm_unpackhi_pd(m2, m2));
        _mm_cvtsd_f64(m1)
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
