//! The portable path: plain arrays of 8 f64 (the compiler vectorises them with the baseline
//! instructions), separate multiply and add, and error-free products by Dekker's splitting
//! (17 flops; no call to a software `fma`).

use super::super::layout::{PermSpec, LANES};
use super::{Isa, Row8};

#[derive(Clone, Copy, Debug)]
pub(crate) struct Portable;

/// Veltkamp's splitting constant 2²⁷ + 1.
const SPLIT: f64 = 134_217_729.0;

/// a = hi + lo with hi holding the upper 26 bits (exact for |a| < 2⁹⁹⁶).
#[inline(always)]
fn split(a: f64) -> (f64, f64) {
    let c = SPLIT * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// Dekker's exact product: p + e = a·b.
#[inline(always)]
fn dekker(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    (p, e)
}

#[inline(always)]
fn map2(a: [f64; LANES], b: [f64; LANES], f: impl Fn(f64, f64) -> f64) -> [f64; LANES] {
    std::array::from_fn(|l| f(a[l], b[l]))
}

/// Source position of each lane (`u8::MAX`: zero).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Perm([u8; LANES]);

impl Isa for Portable {
    type V = [f64; LANES];
    type P = Perm;

    #[inline(always)]
    unsafe fn zero() -> Self::V {
        [0.0; LANES]
    }
    #[inline(always)]
    unsafe fn splat(x: f64) -> Self::V {
        [x; LANES]
    }
    #[inline(always)]
    unsafe fn load(r: &Row8) -> Self::V {
        r.0
    }
    #[inline(always)]
    unsafe fn store(v: Self::V, r: &mut Row8) {
        r.0 = v;
    }
    #[inline(always)]
    unsafe fn add(a: Self::V, b: Self::V) -> Self::V {
        map2(a, b, |x, y| x + y)
    }
    #[inline(always)]
    unsafe fn sub(a: Self::V, b: Self::V) -> Self::V {
        map2(a, b, |x, y| x - y)
    }
    #[inline(always)]
    unsafe fn mul(a: Self::V, b: Self::V) -> Self::V {
        map2(a, b, |x, y| x * y)
    }
    #[inline(always)]
    unsafe fn mul_add(a: Self::V, b: Self::V, c: Self::V) -> Self::V {
        std::array::from_fn(|l| a[l] * b[l] + c[l])
    }
    #[inline(always)]
    unsafe fn two_prod(a: Self::V, b: Self::V) -> (Self::V, Self::V) {
        let mut p = [0.0; LANES];
        let mut e = [0.0; LANES];
        for l in 0..LANES {
            (p[l], e[l]) = dekker(a[l], b[l]);
        }
        (p, e)
    }
    unsafe fn prepare(spec: &PermSpec) -> Self::P {
        Perm(spec.map(|s| s.map_or(u8::MAX, |p| p as u8)))
    }
    #[inline(always)]
    unsafe fn permute(q: Self::V, n: Self::V, p: &Self::P) -> Self::V {
        std::array::from_fn(|l| match p.0[l] as usize {
            s if s < LANES => q[s],
            s if s < 2 * LANES => n[s - LANES],
            _ => 0.0,
        })
    }
    #[inline(always)]
    unsafe fn max_abs(v: Self::V) -> f64 {
        v.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
    }
    #[inline(always)]
    unsafe fn two_prod_f64(a: f64, b: f64) -> (f64, f64) {
        dekker(a, b)
    }
    #[inline(always)]
    unsafe fn mul_add_f64(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}
