//! The lane kernel: the Taylor coefficients xₙ of one step in lane form ([`Layout`]), computed
//! order by order in P-part arithmetic (P = 1: f64, P = 2: double-double, P = 3:
//! triple-double), generic over the code path [`Isa`].
//!
//! Per order m the kernel keeps the row xₘ (Q lanes and N values, P parts each) and the
//! factors of every slot, gathered once when xₘ is known: the left factors (c·p)·xᵢ,ₘ and the
//! right factors xⱼ,ₘ, one 8-lane row per slot row ([`OrderRows`]). The recursion
//!
//! ```text
//!   f(x)ₙ(lane) = Σ_rows Σ_{m=0..n} left[m] · right[n−m]      (Q lanes; a linear slot's right
//!                                                             factor is the series 1)
//!   f(x)ₙ(N)    = Σ_terms (c·p) · xᵢ,ₙ                        (N values)
//!   xₙ₊₁        = f(x)ₙ · 1/(n+1)
//! ```
//!
//! is then one lane-wise multiply-add (P = 1) or one exact product added with two_sum (P ≥ 2)
//! per slot row and m: 2 rows of 8 lanes for the 14 products and 2 linear terms of the
//! Euler–Poisson equations. In f64 the sum over m runs in two interleaved accumulators (even
//! and odd m) to halve the latency chain.

// Index loops on purpose: this code is inlined into `#[target_feature]` functions, and plain
// loops over constant ranges unroll there without any closure (a function of its own,
// compiled without the path's features).
#![allow(clippy::needless_range_loop)]

use super::expansion::{exact_scale, mul, Acc, Lanes};
use super::layout::{Layout, PermSpec, LANES, NMAX, ROWS};
use super::simd::{Isa, Row8};
use crate::state::DIM;

/// A coefficient row in lane form: the Q lanes, then the N values (position p < 8: lane p of
/// `q`; p ≥ 8: lane p − 8 of `n`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Row16 {
    pub q: Row8,
    pub n: Row8,
}

impl Row16 {
    /// The value at position `pos` (< 16).
    #[inline(always)]
    pub fn get(&self, pos: usize) -> f64 {
        debug_assert!(pos < 2 * LANES);
        // SAFETY: repr(C) of two [f64; 8]: 16 contiguous f64.
        unsafe { *(self as *const Self as *const f64).add(pos) }
    }

    #[inline(always)]
    pub fn set(&mut self, pos: usize, v: f64) {
        debug_assert!(pos < 2 * LANES);
        // SAFETY: as in `get`.
        unsafe { *(self as *mut Self as *mut f64).add(pos) = v }
    }
}

/// The factors of the slots at one order: `l[r][part]`, `r[r][part]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OrderRows<const P: usize> {
    l: [[Row8; P]; ROWS],
    r: [[Row8; P]; ROWS],
}

/// A linear term of an N value: `coef`·x at row position `pos`, into N value `n`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NCoef<const K: usize> {
    pub n: usize,
    pub coef: [f64; K],
    pub pos: usize,
}

/// The coefficient c·p of every slot and N term, in K parts.
#[derive(Clone, Debug)]
pub(crate) struct SlotCoefficients<const K: usize> {
    /// `left[r][part]`: the scale of the left factors of row r.
    pub left: [[Row8; K]; ROWS],
    /// The linear terms of the N values.
    pub n: Vec<NCoef<K>>,
}

impl<const K: usize> SlotCoefficients<K> {
    /// Rounded to P ≤ K parts (the parts are normalised, so the first P are the rounding).
    pub fn truncate<const P: usize>(&self) -> SlotCoefficients<P> {
        SlotCoefficients {
            left: std::array::from_fn(|r| std::array::from_fn(|i| self.left[r][i])),
            n: self
                .n
                .iter()
                .map(|t| NCoef {
                    n: t.n,
                    coef: std::array::from_fn(|i| t.coef[i]),
                    pos: t.pos,
                })
                .collect(),
        }
    }
}

/// The N terms as lane rows (see [`LaneSeries`]): for each row t, where each lane's factor
/// comes from, and the coefficients.
fn n_rows<const P: usize>(terms: &[NCoef<P>]) -> (Vec<PermSpec>, Vec<[Row8; P]>) {
    let mut perms: Vec<PermSpec> = Vec::new();
    let mut scales: Vec<[Row8; P]> = Vec::new();
    let mut count = [0usize; NMAX];
    for t in terms {
        let row = count[t.n];
        count[t.n] += 1;
        if perms.len() <= row {
            perms.push([None; LANES]);
            scales.push([Row8::default(); P]);
        }
        perms[row][t.n] = Some(t.pos);
        for i in 0..P {
            scales[row][i].0[t.n] = t.coef[i];
        }
    }
    (perms, scales)
}

/// 1/(n+1) in `P` parts: successive quotients of the exact residuals (fma).
fn reciprocal<const P: usize>(n: usize) -> [f64; P] {
    let d = (n + 1) as f64;
    let mut rest = 1.0;
    std::array::from_fn(|_| {
        let q = rest / d;
        // rest − q·d is exact (q is within an ulp of rest/d).
        rest = (-q).mul_add(d, rest);
        q
    })
}

/// The Taylor coefficients of one step in lane form, P parts (see the module documentation).
pub(crate) struct LaneSeries<I: Isa, const P: usize> {
    /// `x[m][part]`: xₘ in lane form.
    pub x: Vec<[Row16; P]>,
    rows: Vec<OrderRows<P>>,
    perm_l: [I::P; ROWS],
    perm_r: [I::P; ROWS],
    scale_l: [[Row8; P]; ROWS],
    /// Rows whose scales are all exact (±1, ±½, 0 with no lower parts): one multiply per part.
    scale_exact: [bool; ROWS],
    unit: [Row8; ROWS],
    /// The linear terms of the N values as lane rows: row t holds the t-th term of every N
    /// value (lane j: N value j), its factors gathered by `perm_n[t]`, its coefficients
    /// `scale_n[t]`. Lane-wise, so the N values never go through memory on the way from one
    /// order to the next (a vector load of scalar stores stalls store forwarding).
    perm_n: Vec<I::P>,
    scale_n: Vec<[Row8; P]>,
    /// 1/(n+1), n = 0..order, in P parts.
    inv: Vec<[f64; P]>,
    order: usize,
    /// Guarded Cauchy sums (P ≥ 2; for long sums: see [`Acc`]).
    guarded: bool,
}

// The helpers below avoid closures and iterator adapters on purpose: everything here is
// inlined into a `#[target_feature]` entry point, and a closure is a function of its own,
// compiled without the path's features (its intrinsics would become calls).

#[inline(always)]
pub(crate) unsafe fn load<I: Isa, const P: usize>(r: &[Row8; P]) -> [I::V; P] {
    let mut v = [I::zero(); P];
    for i in 0..P {
        v[i] = I::load(&r[i]);
    }
    v
}

/// The Q lanes (`n = false`) or the N values of a P-part row.
#[inline(always)]
pub(crate) unsafe fn load_block<I: Isa, const P: usize>(r: &[Row16; P], n: bool) -> [I::V; P] {
    let mut v = [I::zero(); P];
    for i in 0..P {
        v[i] = I::load(if n { &r[i].n } else { &r[i].q });
    }
    v
}

#[inline(always)]
pub(crate) unsafe fn store_block<I: Isa, const P: usize>(
    v: &[I::V; P],
    r: &mut [Row16; P],
    n: bool,
) {
    for i in 0..P {
        I::store(v[i], if n { &mut r[i].n } else { &mut r[i].q });
    }
}

#[inline(always)]
pub(crate) unsafe fn splat<I: Isa, const P: usize>(x: &[f64; P]) -> [I::V; P] {
    let mut v = [I::zero(); P];
    for i in 0..P {
        v[i] = I::splat(x[i]);
    }
    v
}

#[inline(always)]
unsafe fn permute<I: Isa, const P: usize>(q: &[I::V; P], n: &[I::V; P], p: &I::P) -> [I::V; P] {
    let mut v = [I::zero(); P];
    for i in 0..P {
        v[i] = I::permute(q[i], n[i], p);
    }
    v
}

#[inline(always)]
unsafe fn scale<I: Isa, const P: usize>(x: &[I::V; P], s: I::V) -> [I::V; P] {
    let mut v = [I::zero(); P];
    for i in 0..P {
        v[i] = I::mul(x[i], s);
    }
    v
}

#[inline(always)]
pub(crate) unsafe fn store<I: Isa, const P: usize>(v: &[I::V; P], r: &mut [Row8; P]) {
    for i in 0..P {
        I::store(v[i], &mut r[i]);
    }
}

impl<I: Isa, const P: usize> LaneSeries<I, P> {
    /// A kernel for coefficients 0..=order, its Cauchy sums `guarded` or not (P ≥ 2). Must
    /// run on a CPU that has path `I`.
    pub unsafe fn new(
        layout: &Layout,
        coef: &SlotCoefficients<P>,
        order: usize,
        guarded: bool,
    ) -> Self {
        let zero_rows = OrderRows {
            l: [[Row8::default(); P]; ROWS],
            r: [[Row8::default(); P]; ROWS],
        };
        let scale_exact = std::array::from_fn(|r| {
            coef.left[r][0].0.iter().all(|&c| exact_scale(c))
                && coef.left[r][1..]
                    .iter()
                    .all(|p| p.0.iter().all(|&c| c == 0.0))
        });
        Self {
            x: vec![[Row16::default(); P]; order + 1],
            rows: vec![zero_rows; order + 1],
            perm_l: std::array::from_fn(|r| I::prepare(&layout.left_perm(r))),
            perm_r: std::array::from_fn(|r| I::prepare(&layout.right_perm(r))),
            scale_l: coef.left,
            scale_exact,
            unit: std::array::from_fn(|r| Row8(layout.unit_lanes(r))),
            perm_n: n_rows::<P>(&coef.n)
                .0
                .iter()
                .map(|p| I::prepare(p))
                .collect(),
            scale_n: n_rows::<P>(&coef.n).1,
            inv: (0..=order).map(reciprocal::<P>).collect(),
            order,
            guarded,
        }
    }

    /// Set row m (lane form) and gather its slot factors.
    #[inline(always)]
    pub unsafe fn set(&mut self, m: usize, x: &[Row16; P]) {
        self.x[m] = *x;
        let (q, n) = (load_block::<I, P>(x, false), load_block::<I, P>(x, true));
        self.gather(m, &q, &n);
    }

    /// Row m and its slot factors from a kernel with more parts (their first P parts: the
    /// rounding of normalised values; exact for the factors of exact scales).
    #[inline(always)]
    pub unsafe fn copy_from<const K: usize>(&mut self, m: usize, other: &LaneSeries<I, K>) {
        debug_assert!(K >= P);
        for i in 0..P {
            self.x[m][i] = other.x[m][i];
            for r in 0..ROWS {
                self.rows[m].l[r][i] = other.rows[m].l[r][i];
                self.rows[m].r[r][i] = other.rows[m].r[r][i];
            }
        }
    }

    /// The slot factors of order m from xₘ (Q lanes `q`, N values `n`).
    #[inline(always)]
    unsafe fn gather(&mut self, m: usize, q: &[I::V; P], n: &[I::V; P]) {
        type L<I> = Lanes<I>;
        let out = &mut self.rows[m];
        for r in 0..ROWS {
            let left = permute::<I, P>(q, n, &self.perm_l[r]);
            let left = if self.scale_exact[r] {
                scale::<I, P>(&left, I::load(&self.scale_l[r][0]))
            } else {
                mul::<L<I>, P>(&left, &load::<I, P>(&self.scale_l[r]))
            };
            store::<I, P>(&left, &mut out.l[r]);
            let mut right = permute::<I, P>(q, n, &self.perm_r[r]);
            if m == 0 {
                right[0] = I::add(right[0], I::load(&self.unit[r]));
            }
            store::<I, P>(&right, &mut out.r[r]);
        }
    }

    /// Coefficients xₙ₊₁ for n = from..to (rows 0..=from must be set; the factors of xₜₒ
    /// are not gathered: no later order needs them).
    #[inline(always)]
    pub unsafe fn advance(&mut self, from: usize, to: usize) {
        assert!(to <= self.order && from <= to);
        if P == 1 {
            return self.advance_f64(from, to);
        }
        if self.guarded {
            self.advance_parts::<true>(from, to)
        } else {
            self.advance_parts::<false>(from, to)
        }
    }

    /// [`LaneSeries::advance`] for P ≥ 2, the sums guarded (`G`: long sums) or not.
    #[inline(always)]
    unsafe fn advance_parts<const G: bool>(&mut self, from: usize, to: usize) {
        type L<I> = Lanes<I>;
        for n in from..to {
            let rows = &self.rows[..=n];
            // One accumulator for all rows (their sum is what is wanted): fewer registers;
            // the sums' latency chains are still shorter than the work per m.
            let mut f = Acc::<L<I>, P, G>::zero();
            for m in 0..=n {
                let (a, b) = (rows.get_unchecked(m), rows.get_unchecked(n - m));
                for r in 0..ROWS {
                    f.add_prod(&load::<I, P>(&a.l[r]), &load::<I, P>(&b.r[r]));
                }
            }
            let xq = self.times_inv(&f.value(), n);
            let (q, nv) = (
                load_block::<I, P>(&self.x[n], false),
                load_block::<I, P>(&self.x[n], true),
            );
            let xn = self.times_inv(&self.n_values(&q, &nv), n);
            store_block::<I, P>(&xq, &mut self.x[n + 1], false);
            store_block::<I, P>(&xn, &mut self.x[n + 1], true);
            if n + 1 < to {
                self.gather(n + 1, &xq, &xn);
            }
        }
    }

    /// [`LaneSeries::advance`] for P = 1 (f64): the Cauchy sums in two interleaved
    /// accumulators per row (even and odd m: two independent FMA chains per lane), walking two
    /// pointers, rows\[m\] up and rows\[n − m\] down.
    #[inline(always)]
    unsafe fn advance_f64(&mut self, from: usize, to: usize) {
        // The newest row xₙ and its factors, in registers: the terms that use them (m = 0 and
        // m = n) are added last, so the sum over the older rows 1 … n − 1 does not wait for
        // the previous order (the latency chain from order to order is the gather and a few
        // additions, not the whole sum).
        let mut l_new = [I::zero(); ROWS];
        let mut r_new = [I::zero(); ROWS];
        let newest = self.rows.get_unchecked(from);
        for r in 0..ROWS {
            l_new[r] = I::load(&newest.l[r][0]);
            r_new[r] = I::load(&newest.r[r][0]);
        }
        let x_from = &self.x.get_unchecked(from)[0];
        let (mut q_prev, mut n_prev) = (I::load(&x_from.q), I::load(&x_from.n));
        let first = self.rows.get_unchecked(0);
        let mut l0 = [I::zero(); ROWS];
        let mut r0 = [I::zero(); ROWS];
        for r in 0..ROWS {
            l0[r] = I::load(&first.l[r][0]);
            r0[r] = I::load(&first.r[r][0]);
        }
        for n in from..to {
            // The N values of xₙ₊₁ depend on xₙ only.
            let inv = I::splat(self.inv.get_unchecked(n)[0]);
            let mut xn = I::zero();
            for t in 0..self.perm_n.len() {
                let x = I::permute(q_prev, n_prev, self.perm_n.get_unchecked(t));
                xn = I::mul_add(x, I::load(&self.scale_n.get_unchecked(t)[0]), xn);
            }
            let xn = I::mul(xn, inv);
            // m = 1 … n − 1: pairs (m, m + 1), then the last one if n − 1 is odd.
            let base = self.rows.as_ptr();
            let mut lo = base.add(1);
            let mut hi = base.add(n.saturating_sub(1));
            let mut even = [I::zero(); ROWS];
            let mut odd = [I::zero(); ROWS];
            let interior = n.saturating_sub(1);
            for _ in 0..interior / 2 {
                let (a, b, c, d) = (&*lo, &*hi, &*lo.add(1), &*hi.sub(1));
                for r in 0..ROWS {
                    even[r] = I::mul_add(I::load(&a.l[r][0]), I::load(&b.r[r][0]), even[r]);
                    odd[r] = I::mul_add(I::load(&c.l[r][0]), I::load(&d.r[r][0]), odd[r]);
                }
                lo = lo.add(2);
                hi = hi.sub(2);
            }
            if interior % 2 == 1 {
                let (a, b) = (&*lo, &*hi);
                for r in 0..ROWS {
                    even[r] = I::mul_add(I::load(&a.l[r][0]), I::load(&b.r[r][0]), even[r]);
                }
            }
            // The terms with the newest row: L₀·Rₙ and, for n ≥ 1, Lₙ·R₀.
            for r in 0..ROWS {
                odd[r] = I::mul_add(l0[r], r_new[r], odd[r]);
                if n >= 1 {
                    even[r] = I::mul_add(l_new[r], r0[r], even[r]);
                }
            }
            let mut f = I::add(even[0], odd[0]);
            for r in 1..ROWS {
                f = I::add(f, I::add(even[r], odd[r]));
            }
            let xq = I::mul(f, inv);
            let next = &mut self.x.get_unchecked_mut(n + 1)[0];
            I::store(xq, &mut next.q);
            I::store(xn, &mut next.n);
            (q_prev, n_prev) = (xq, xn);
            if n + 1 < to {
                (l_new, r_new) = self.gather_f64(n + 1, xq, xn);
            }
        }
    }

    /// [`LaneSeries::gather`] for P = 1, returning the factors (left, right) as well.
    #[inline(always)]
    unsafe fn gather_f64(&mut self, m: usize, q: I::V, n: I::V) -> ([I::V; ROWS], [I::V; ROWS]) {
        let out = self.rows.get_unchecked_mut(m);
        let mut l = [I::zero(); ROWS];
        let mut r = [I::zero(); ROWS];
        for k in 0..ROWS {
            l[k] = I::mul(
                I::permute(q, n, &self.perm_l[k]),
                I::load(&self.scale_l[k][0]),
            );
            r[k] = I::permute(q, n, &self.perm_r[k]);
            if m == 0 {
                r[k] = I::add(r[k], I::load(&self.unit[k]));
            }
            I::store(l[k], &mut out.l[k][0]);
            I::store(r[k], &mut out.r[k][0]);
        }
        (l, r)
    }

    /// f(x)ₙ of the N values (lanes 0..NMAX), from xₙ (Q lanes `q`, N values `n`).
    #[inline(always)]
    unsafe fn n_values(&self, q: &[I::V; P], n: &[I::V; P]) -> [I::V; P] {
        let mut g = Acc::<Lanes<I>, P>::zero();
        for t in 0..self.perm_n.len() {
            let x = permute::<I, P>(q, n, self.perm_n.get_unchecked(t));
            g.add_prod(&x, &load::<I, P>(self.scale_n.get_unchecked(t)));
        }
        g.value()
    }

    /// f · 1/(n+1): exact scaling when n + 1 is a power of two, else a P-part product.
    #[inline(always)]
    unsafe fn times_inv(&self, f: &[I::V; P], n: usize) -> [I::V; P] {
        let inv = self.inv[n];
        if (n + 1).is_power_of_two() {
            scale::<I, P>(f, I::splat(inv[0]))
        } else {
            mul::<Lanes<I>, P>(f, &splat::<I, P>(&inv))
        }
    }

    /// ‖xₘ‖∞ (leading parts).
    #[inline(always)]
    pub unsafe fn norm(&self, m: usize) -> f64 {
        let x = &self.x[m][0];
        I::max_abs(I::load(&x.q)).max(I::max_abs(I::load(&x.n)))
    }

    /// Σ_{k=first..order} xₖ τ^(k−first) by Horner's rule, lane form (Q lanes, N values).
    #[inline(always)]
    pub unsafe fn horner(&self, first: usize, tau: &[f64; P]) -> ([I::V; P], [I::V; P]) {
        let t = splat::<I, P>(tau);
        let mut q = load_block::<I, P>(&self.x[self.order], false);
        let mut n = load_block::<I, P>(&self.x[self.order], true);
        for k in (first..self.order).rev() {
            q = Self::times_add(&q, &t, &load_block::<I, P>(&self.x[k], false));
            n = Self::times_add(&n, &t, &load_block::<I, P>(&self.x[k], true));
        }
        (q, n)
    }

    /// s·t + x in P parts.
    #[inline(always)]
    unsafe fn times_add(s: &[I::V; P], t: &[I::V; P], x: &[I::V; P]) -> [I::V; P] {
        let mut acc = Acc::<Lanes<I>, P>::from(*x);
        acc.add_prod(s, t);
        acc.value()
    }
}

/// A row given in natural order (component k at index k) in lane form.
pub(crate) fn to_lanes<const P: usize>(layout: &Layout, x: &[[f64; P]; DIM]) -> [Row16; P] {
    let mut out = [Row16::default(); P];
    for (k, parts) in x.iter().enumerate() {
        for (i, &v) in parts.iter().enumerate() {
            out[i].set(layout.pos[k], v);
        }
    }
    out
}

/// The row in natural order from lane form.
pub(crate) fn from_lanes<const P: usize>(layout: &Layout, x: &[Row16; P]) -> [[f64; P]; DIM] {
    std::array::from_fn(|k| std::array::from_fn(|i| x[i].get(layout.pos[k])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reciprocals_carry_p_parts() {
        use rug::Float;
        for n in [0usize, 1, 2, 6, 36, 99] {
            let parts = reciprocal::<3>(n);
            let mut sum = Float::with_val(300, 0);
            for p in parts {
                sum += p;
            }
            let err = (sum * (n as f64 + 1.0) - 1u32).abs().to_f64();
            assert!(err < 1e-47, "1/{}: {err:e}", n + 1);
        }
    }
}
