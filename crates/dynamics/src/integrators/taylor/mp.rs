//! The MPFR Taylor kernel of `taylor-mp`: the coefficients f(x)ₙ of the Euler–Poisson right-hand
//! side as **limb-level fixed-point dot products** with one rounding per component, derived from
//! the same table of equations as every other kernel ([`VectorField`]'s flattened term list).
//!
//! Component k of f(x)ₙ is a sum of products (table of [`crate::equations::EULER_POISSON`]):
//!
//! ```text
//!   f(x)ₙ,ₖ = Σ_quadratic c·Σ_{m=0..n} x_{i,m} x_{j,n−m}  +  Σ_linear c·x_{i,n}
//! ```
//!
//! The generic path rounds every product and every partial sum to the working precision p
//! (2·(n+1) roundings per Cauchy sum, ~141 ns per multiply-add at 307 bits, 14 % of it
//! allocation). Here each term is a product of two p-bit mantissas, formed **exactly** by GMP's
//! `mpn_mul_n` (2L limbs for L = ⌈p/64⌉) and added (`mpn_add_n`) or subtracted (`mpn_sub_n`) at
//! its limb offset in a two's complement fixed-point accumulator spanning all the products; the
//! component is then rounded **once** to nearest (`mpfr_set_z_2exp` on a read-only `mpz` view of
//! the accumulator's limbs). Products are never shifted one by one: every operand is stored
//! with its exponent rounded up to a multiple of a grain g (its mantissa shifted right into the
//! spare low bits of the last limb: g = 8 at 307 bits, up to 64), so a product's binary point
//! modulo 64 takes few values; one accumulator per such bit phase, each shifted once at the end
//! (precisions that fill their last limb, g < 8, shift each product instead). Quadratic
//! coefficients that are ±2ʲ (all of them in the Euler–Poisson table: ±1, ±½) only move the
//! binary point; a linear term c·xᵢ,ₙ is one more exact product (the coefficient's mantissa
//! times xᵢ,ₙ's). A quadratic coefficient that is not a power of two (other tables) gets its
//! Cauchy sum rounded once first, then enters as the exact product c·S. No allocation happens in
//! the step loop: the operands of every order are copied once into a limb table (the gather,
//! O(p) per step) and all buffers are sized up front.
//!
//! **Accuracy.** The accumulator spans all products of a component (from the top bit of the
//! largest to the lowest bit of the smallest, plus one limb of carry room), so the result is the
//! exact sum correctly rounded to nearest — unless the products' exponents spread over more
//! than [`MAX_SPAN_LIMBS`]·64 bits (far beyond any Taylor series in practice), when products
//! entirely below the accumulator are dropped and those partly below are truncated: an error
//! below (number of products)·2^(−64·[`MAX_SPAN_LIMBS`] + 64) times the largest product, far below
//! the rounding errors of the generic path. Zeros are skipped; a NaN or an infinity among the
//! operands sends the call to the generic path (which propagates it). The result may differ from
//! the generic path in the last bits (that path rounds 2(n+1) times per sum); the tests check it
//! against the correctly rounded exact value and against the generic path's error bound.

use std::mem::MaybeUninit;

use gmp_mpfr_sys::gmp::{self, limb_t, mpz_t};
use gmp_mpfr_sys::mpfr::{self, rnd_t};
use rug::{Assign, Float};

use crate::equations::{CauchyScratch, VectorField};
use crate::state::DIM;

/// Which kernel computes the Taylor coefficients of `taylor-mp`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MpfrKernelChoice {
    /// This module's limb-level fixed-point sums (the default, up to [`MAX_DEFAULT_LIMBS`]
    /// limbs of precision; the generic path beyond).
    #[default]
    Limbs,
    /// The generic path of every scalar ([`VectorField::taylor_coefficient_orders`]): each
    /// product and partial sum rounded.
    Generic,
}

impl MpfrKernelChoice {
    /// The environment variable that overrides the default: `limbs` or `generic`.
    pub const ENV: &'static str = "RSTS_MPFR_KERNEL";

    /// The choice from [`Self::ENV`] (unset or empty: [`Self::Limbs`]); an unknown value is an
    /// error naming the variable.
    pub fn from_env() -> Result<Self, String> {
        match std::env::var(Self::ENV).unwrap_or_default().trim() {
            "" | "limbs" => Ok(Self::Limbs),
            "generic" => Ok(Self::Generic),
            other => Err(format!(
                "{} must be 'limbs' or 'generic', got '{other}'",
                Self::ENV
            )),
        }
    }
}

/// Widest mantissa (in limbs) for which taylor-mp picks this kernel by default: up to 14 limbs
/// (896 bits, ~267 digits). Beyond, the products' O(L²) limb multiplications dominate both
/// paths and MPFR's own rounded products are as fast (measured with
/// `cargo bench -p rsts-dynamics --bench mpfr_kernel`: 3.2× faster at 5 limbs, 1.6× at 8,
/// 1.4× at 11, 0.94× at 16; docs/benchmarks.md).
pub const MAX_DEFAULT_LIMBS: usize = 14;

/// Largest span of one accumulator in limbs beyond the product width (see the module docs).
pub const MAX_SPAN_LIMBS: usize = 64;

/// The exponent of a zero operand: far below any real one, so a product with a zero factor has
/// a "top" below [`ZERO_TOP`] and is skipped.
const ZERO_EXP: i64 = i64::MIN / 4;
/// Products whose top exponent is below this have a zero factor.
const ZERO_TOP: i64 = i64::MIN / 8;

/// One quadratic term whose coefficient is ±2^shift: contributes ±2^shift·Σₘ x_{i,m} x_{j,n−m}.
#[derive(Clone, Copy, Debug)]
struct ShiftedTerm {
    i: usize,
    j: usize,
    neg: bool,
    shift: i64,
}

/// A quadratic term with any other coefficient: its Cauchy sum S is rounded to p bits first
/// (into sum slot `sum`), then c·S enters the component exactly. `c` is the index of the
/// coefficient operand.
#[derive(Clone, Copy, Debug)]
struct ScaledTerm {
    i: usize,
    j: usize,
    c: usize,
    sum: usize,
}

/// A linear term c·x_{i,n}: one exact product (`c` indexes the coefficient operand).
#[derive(Clone, Copy, Debug)]
struct LinearTerm {
    i: usize,
    c: usize,
}

/// The terms of one component, from the table.
#[derive(Clone, Debug, Default)]
struct ComponentPlan {
    shifted: Vec<ShiftedTerm>,
    scaled: Vec<ScaledTerm>,
    linear: Vec<LinearTerm>,
}

/// A run of products ±2^shift·a_k·b_k, k = 0..count, with operand slots a_k = a + k·a_step,
/// b_k = b + k·b_step: a whole Cauchy sum (a = x_{i,0}, x_{i,1}, …; b = x_{j,n}, x_{j,n−1}, …)
/// or a single product.
#[derive(Clone, Copy, Debug)]
struct Run {
    a: usize,
    a_step: isize,
    b: usize,
    b_step: isize,
    count: usize,
    neg: bool,
    shift: i64,
}

impl Run {
    fn single(a: usize, b: usize, neg: bool, shift: i64) -> Self {
        Self {
            a,
            a_step: 0,
            b,
            b_step: 0,
            count: 1,
            neg,
            shift,
        }
    }

    /// The Cauchy sum Σ_{m=0..n} x_{i,m} x_{j,n−m} with x_{i,m} at slot `first + m·DIM + i`.
    fn cauchy(first: usize, i: usize, j: usize, n: usize, neg: bool, shift: i64) -> Self {
        Self {
            a: first + i,
            a_step: DIM as isize,
            b: first + n * DIM + j,
            b_step: -(DIM as isize),
            count: n + 1,
            neg,
            shift,
        }
    }

    /// Call `f(a_k, b_k)` for the slots of the run, each below `slots` (checked once here at
    /// both ends of the two arithmetic progressions; the calls get unchecked-safe indices).
    #[inline(always)]
    fn for_each(&self, slots: usize, mut f: impl FnMut(usize, usize)) {
        if self.count == 0 {
            return;
        }
        let last = self.count as isize - 1;
        let ends = [
            self.a as isize,
            self.a as isize + last * self.a_step,
            self.b as isize,
            self.b as isize + last * self.b_step,
        ];
        assert!(
            ends.iter().all(|&e| e >= 0 && (e as usize) < slots),
            "operand slot out of range"
        );
        let (mut a, mut b) = (self.a as isize, self.b as isize);
        for _ in 0..self.count {
            f(a as usize, b as usize);
            a += self.a_step;
            b += self.b_step;
        }
    }
}

/// Operands: mantissas copied into one limb table, `limbs` limbs each, each shifted right by
/// up to `grain` − 1 bits into the spare low bits of its last limb so that its exponent is a
/// multiple of `grain` (a power of two, at most 64): then every product's binary point is a
/// multiple of `grain` too, and the accumulator needs only 64/`grain` bit phases.
#[derive(Clone, Debug)]
struct Operands {
    limbs: usize,
    grain: i64,
    /// Per slot: the exponent (value = ±M·2^(exp − 64L), M the slot's L limbs; [`ZERO_EXP`]
    /// for 0) and the sign.
    exp: Vec<i64>,
    neg: Vec<bool>,
    table: Vec<limb_t>,
}

/// The largest power of two g ≤ 64 with g − 1 ≤ 64·limbs − bits (the spare low bits of a
/// `bits`-bit mantissa in `limbs` limbs).
fn grain_for(bits: u32) -> i64 {
    let spare = 64 * limbs_for(bits) as i64 - i64::from(bits);
    let mut g = 1;
    while g < 64 && 2 * g - 1 <= spare {
        g *= 2;
    }
    g
}

/// Exponents beyond ±2^40 (far outside MPFR's default range) take the generic path, so sums
/// of exponents cannot overflow.
const MAX_EXP: i64 = 1 << 40;

impl Operands {
    fn new(bits: u32, slots: usize) -> Self {
        let limbs = limbs_for(bits);
        Self {
            limbs,
            grain: grain_for(bits),
            exp: vec![ZERO_EXP; slots],
            neg: vec![false; slots],
            table: vec![0; slots * limbs],
        }
    }

    /// Make room for `slots` operands.
    fn reserve(&mut self, slots: usize) {
        if self.exp.len() < slots {
            self.exp.resize(slots, ZERO_EXP);
            self.neg.resize(slots, false);
            self.table.resize(slots * self.limbs, 0);
        }
    }

    /// Copy `x` into slot `slot`, aligned to the grain. False when `x` is NaN or infinite, has
    /// more limbs than the kernel's precision, low bits the alignment would lose (more bits
    /// than the kernel's precision) or a huge exponent (the caller then takes the generic
    /// path).
    fn set(&mut self, slot: usize, x: &Float) -> bool {
        let l = self.limbs;
        let at = slot * l;
        if x.is_zero() {
            self.exp[slot] = ZERO_EXP;
            return true;
        }
        if !x.is_normal() {
            return false;
        }
        // SAFETY: a regular MPFR number has ⌈prec/64⌉ initialised limbs at `d`, most significant
        // last, its top bit set (MPFR's documented internal representation).
        unsafe {
            let raw = x.as_raw();
            let n = limbs_for((*raw).prec as u32);
            let exp = exponent(raw);
            if n > l || exp.abs() > MAX_EXP {
                return false;
            }
            let d = std::slice::from_raw_parts((*raw).d.as_ptr(), n);
            let dst = &mut self.table[at..at + l];
            dst[..l - n].fill(0);
            dst[l - n..].copy_from_slice(d);
            // Exponent up to the next multiple of the grain, mantissa down by as many bits.
            let shift = exp.rem_euclid(self.grain);
            let shift = if shift == 0 { 0 } else { self.grain - shift };
            if shift > 0 {
                if dst[0] & ((1 << shift) - 1) != 0 {
                    return false;
                }
                gmp::mpn_rshift(dst.as_mut_ptr(), dst.as_ptr(), l as _, shift as u32);
            }
            self.exp[slot] = exp + shift;
            self.neg[slot] = x.is_sign_negative();
        }
        true
    }
}

/// The smallest grain for which products go into phase accumulators (else each product is
/// shifted into place).
const MIN_PHASED_GRAIN: i64 = 8;

/// The fixed-point accumulator, in two's complement modulo 2^(64·width): positive products are
/// added, negative ones subtracted. When the operands are aligned to a grain of at least
/// [`MIN_PHASED_GRAIN`] bits, it is split into bit phases: a product whose binary point is
/// 64q + r goes unshifted into phase r at limb q, and each phase used is shifted once when
/// the sum is complete (products of aligned operands fall into 64/grain phases, times the few
/// distinct residues of the coefficients ±2ʲ). Otherwise (precisions that fill their last
/// limb) each product is shifted into place.
#[derive(Clone, Debug)]
struct Accumulator {
    /// Limbs per accumulator (the widest a sum may need).
    cap: usize,
    /// One accumulator per phase, `cap` limbs each, and the total.
    phases: Vec<limb_t>,
    total: Vec<limb_t>,
    prod: Vec<limb_t>,
}

/// acc[start..] ±= p with the carry or borrow propagated through `acc` (modulo 2^(64·len)).
///
/// # Safety
/// `p` points to `len` ≥ 1 limbs not inside `acc`; start + len ≤ acc.len().
#[inline(always)]
unsafe fn add_or_sub(acc: &mut [limb_t], start: usize, p: *const limb_t, len: usize, neg: bool) {
    let end = start + len;
    let dst = acc[start..end].as_mut_ptr();
    if neg {
        let mut borrow = gmp::mpn_sub_n(dst, dst, p, len as _);
        for a in &mut acc[end..] {
            if borrow == 0 {
                break;
            }
            let (d, b) = a.overflowing_sub(1);
            *a = d;
            borrow = limb_t::from(b);
        }
    } else {
        let mut carry = gmp::mpn_add_n(dst, dst, p, len as _);
        for a in &mut acc[end..] {
            if carry == 0 {
                break;
            }
            let (s, c) = a.overflowing_add(1);
            *a = s;
            carry = limb_t::from(c);
        }
    }
}

impl Accumulator {
    fn new(limbs: usize) -> Self {
        let cap = 2 * limbs + 2 + MAX_SPAN_LIMBS;
        Self {
            cap,
            phases: vec![0; 64 * cap],
            total: vec![0; cap],
            prod: vec![0; 2 * limbs + 1],
        }
    }

    /// Σ over the products of `runs` of ±2^shift·a·b, exactly in fixed point, rounded once into
    /// `out`.
    fn sum(&mut self, operands: &Operands, runs: &[Run], out: &mut Float) {
        let (exp, sign, table) = (&operands.exp, &operands.neg, &operands.table);
        let limbs = operands.limbs;
        let l = limbs as i64;
        // Pass 1: the extremes of the products' exponents (a product is below 2^top,
        // top = ea + eb + shift; its lowest bit has weight 2^(top − 128L)).
        let mut top_max = ZERO_TOP;
        let mut top_min = i64::MAX;
        let slots = exp.len().min(sign.len()).min(table.len() / limbs);
        for run in runs {
            run.for_each(slots, |a, b| {
                // SAFETY: a, b < slots (checked by for_each).
                let top = unsafe { exp.get_unchecked(a) + exp.get_unchecked(b) } + run.shift;
                if top > ZERO_TOP {
                    top_max = top_max.max(top);
                    top_min = top_min.min(top);
                }
            });
        }
        if top_max == ZERO_TOP {
            out.assign(0);
            return;
        }
        // The binary point. Limbs: the span of all products plus one limb of carry (and sign)
        // room and one for the bit shift, at most the product width plus MAX_SPAN_LIMBS.
        let span = ((top_max - top_min + 128 * l) as u64).div_ceil(64) as usize + 2;
        let width = span.min(self.cap);
        // Weight of limb 0's lowest bit: the top limb is carry room above 2^top_max.
        let base = top_max + 64 - 64 * width as i64;
        let pl = 2 * limbs;
        let phased = operands.grain >= MIN_PHASED_GRAIN;
        let cap = self.cap;
        let mut used: u64 = 0;
        if !phased {
            self.total[..width].fill(0);
        }
        for run in runs {
            run.for_each(slots, |a, b| {
                // SAFETY: a, b < slots (checked by for_each).
                let (top, negative) = unsafe {
                    (
                        exp.get_unchecked(a) + exp.get_unchecked(b) + run.shift,
                        sign.get_unchecked(a) ^ sign.get_unchecked(b) ^ run.neg,
                    )
                };
                if top <= ZERO_TOP {
                    return;
                }
                let offset = top - 128 * l - base;
                // SAFETY: operands lie in `table` (L limbs each); `prod` has 2L + 1 limbs; a
                // product below 2^top_max placed at `offset` ends below limb width − 1 (the carry
                // room), so every write stays inside the accumulator's `width` limbs.
                unsafe {
                    let pp = self.prod.as_mut_ptr();
                    gmp::mpn_mul_n(
                        pp,
                        table.as_ptr().add(a * limbs),
                        table.as_ptr().add(b * limbs),
                        limbs as _,
                    );
                    let (acc, start, len) = if offset >= 0 {
                        let start = (offset / 64) as usize;
                        let bits = offset % 64;
                        if phased {
                            let phase = bits as usize;
                            let acc = &mut self.phases[phase * cap..phase * cap + width];
                            if used & (1 << phase) == 0 {
                                used |= 1 << phase;
                                acc.fill(0);
                            }
                            (acc, start, pl)
                        } else {
                            *pp.add(pl) = if bits == 0 {
                                0
                            } else {
                                gmp::mpn_lshift(pp, pp, pl as _, bits as u32)
                            };
                            (&mut self.total[..width], start, pl + 1)
                        }
                    } else {
                        // Below the accumulator (span over MAX_SPAN_LIMBS): truncated, into
                        // phase 0 (or the total).
                        let drop = (-offset) as u64;
                        if drop >= 64 * pl as u64 {
                            return;
                        }
                        let (whole, bits) = ((drop / 64) as usize, (drop % 64) as u32);
                        let rest = pl - whole;
                        if bits > 0 {
                            gmp::mpn_rshift(pp, pp.add(whole), rest as _, bits);
                        } else {
                            gmp::mpn_copyi(pp, pp.add(whole), rest as _);
                        }
                        let acc = if phased {
                            let acc = &mut self.phases[..width];
                            if used & 1 == 0 {
                                used |= 1;
                                acc.fill(0);
                            }
                            acc
                        } else {
                            &mut self.total[..width]
                        };
                        (acc, 0, rest)
                    };
                    add_or_sub(acc, start, pp, len, negative);
                }
            });
        }
        let w = width as gmp::size_t;
        // SAFETY: all accumulators have `cap` ≥ `width` limbs; the shifts work modulo
        // 2^(64·width) (two's complement), where the exact sum fits with its sign.
        unsafe {
            let tp = self.total.as_mut_ptr();
            if phased {
                self.total[..width].fill(0);
                while used != 0 {
                    let phase = used.trailing_zeros() as usize;
                    used &= used - 1;
                    let src = self.phases.as_mut_ptr().add(phase * cap);
                    if phase > 0 {
                        gmp::mpn_lshift(src, src, w, phase as u32);
                    }
                    gmp::mpn_add_n(tp, tp, src, w);
                }
            }
            // The sign is the top bit; round |sum|·2^base once.
            let negative = self.total[width - 1] >> 63 == 1;
            if negative {
                gmp::mpn_neg(tp, tp, w);
            }
            let mut z = MaybeUninit::<mpz_t>::uninit();
            let size = if negative { -w } else { w };
            let zp = gmp::mpz_roinit_n(z.as_mut_ptr(), tp, size);
            mpfr::set_z_2exp(out.as_raw_mut(), zp, base as mpfr::exp_t, rnd_t::RNDN);
        }
    }
}

/// The limb-level MPFR kernel for one vector field at one precision (see the module docs).
/// Build it once per run with [`MpfrKernel::new`], then call
/// [`coefficient`](MpfrKernel::coefficient) for n = 0, 1, … of each step.
#[derive(Clone, Debug)]
pub struct MpfrKernel {
    /// Working precision in bits.
    bits: u32,
    plans: [ComponentPlan; DIM],
    /// The constant operands (coefficients, then one slot per scaled term's rounded sum),
    /// then `DIM` per gathered order.
    operands: Operands,
    /// Number of constant operands.
    constants: usize,
    /// First slot of the scaled terms' sums.
    first_sum: usize,
    /// Orders gathered from the current series.
    rows: usize,
    /// All coefficients are finite (else every call takes the generic path).
    usable: bool,
    /// The runs of products of the sum being formed (reused).
    runs: Vec<Run>,
    acc: Accumulator,
    /// Rounded Cauchy sums of the scaled terms (working precision).
    sums: Vec<Float>,
    /// The generic path, for non-finite operands.
    generic: CauchyScratch<Float>,
    field: VectorField<Float>,
}

/// The exponent field of a regular MPFR number (a `c_long`: 32 bits on some targets).
///
/// # Safety
/// `raw` points to an initialised `mpfr_t`.
#[allow(clippy::unnecessary_cast)]
unsafe fn exponent(raw: *const mpfr::mpfr_t) -> i64 {
    (*raw).exp as i64
}

/// Limbs of a `bits`-bit MPFR mantissa.
fn limbs_for(bits: u32) -> usize {
    (bits as usize).div_ceil(64)
}

/// Whether `x` is ±2^k (a regular number with a one-bit mantissa): `Some((negative, k))`.
fn power_of_two(x: &Float) -> Option<(bool, i64)> {
    if !x.is_normal() {
        return None;
    }
    // SAFETY: `x` is a regular MPFR number: its mantissa has ⌈prec/64⌉ initialised limbs.
    unsafe {
        let raw = x.as_raw();
        let n = limbs_for((*raw).prec as u32);
        let d = std::slice::from_raw_parts((*raw).d.as_ptr(), n);
        let one_bit = d[n - 1] == 1 << 63 && d[..n - 1].iter().all(|&l| l == 0);
        // Value 0.1₂ · 2^exp = 2^(exp − 1).
        one_bit.then(|| (x.is_sign_negative(), exponent(raw) - 1))
    }
}

impl MpfrKernel {
    /// The kernel for `field` at `bits` bits (the precision of the series it will be given).
    pub fn new(field: &VectorField<Float>, bits: u32) -> Self {
        let limbs = limbs_for(bits);
        let mut plans: [ComponentPlan; DIM] = Default::default();
        let mut coefficients: Vec<&Float> = Vec::new();
        let (quad, lin) = field.flat_terms();
        let mut scaled = 0;
        for (c, i, j, k) in quad {
            if c.is_zero() {
                continue;
            }
            match power_of_two(c) {
                Some((neg, shift)) => plans[*k].shifted.push(ShiftedTerm {
                    i: *i,
                    j: *j,
                    neg,
                    shift,
                }),
                None => {
                    coefficients.push(c);
                    plans[*k].scaled.push(ScaledTerm {
                        i: *i,
                        j: *j,
                        c: coefficients.len() - 1,
                        sum: scaled,
                    });
                    scaled += 1;
                }
            }
        }
        for (c, i, k) in lin {
            if c.is_zero() {
                continue;
            }
            coefficients.push(c);
            plans[*k].linear.push(LinearTerm {
                i: *i,
                c: coefficients.len() - 1,
            });
        }
        let first_sum = coefficients.len();
        let constants = first_sum + scaled;
        let mut operands = Operands::new(bits, constants);
        let mut finite = true;
        for (slot, c) in coefficients.iter().enumerate() {
            finite &= operands.set(slot, c);
        }
        Self {
            bits,
            plans,
            operands,
            constants,
            first_sum,
            rows: 0,
            // A coefficient that cannot be an operand (non-finite) sends every call to the
            // generic path.
            usable: finite,
            runs: Vec::new(),
            acc: Accumulator::new(limbs),
            sums: vec![Float::new(bits); scaled],
            generic: CauchyScratch::new(&Float::new(bits)),
            field: field.clone(),
        }
    }

    /// Working precision in bits.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The kernel taylor-mp uses by default at `bits` bits: this one up to
    /// [`MAX_DEFAULT_LIMBS`] limbs, `None` (the generic path) beyond.
    pub fn by_default(field: &VectorField<Float>, bits: u32) -> Option<Self> {
        (limbs_for(bits) <= MAX_DEFAULT_LIMBS).then(|| Self::new(field, bits))
    }

    /// Slot of x_{i,m} in the operand table.
    fn slot(&self, m: usize, i: usize) -> usize {
        self.constants + m * DIM + i
    }

    /// Gather order `m` of the series into the operand table. False: a value that cannot be an
    /// operand (non-finite).
    fn gather(&mut self, m: usize, row: &[Float; DIM]) -> bool {
        let first = self.slot(m, 0);
        self.operands.reserve(first + DIM);
        let mut ok = true;
        for (i, x) in row.iter().enumerate() {
            ok &= self.operands.set(first + i, x);
        }
        ok
    }

    /// Coefficient `n` of f(x(t)) from the series stored order by order (`series[m][i]` = x_{i,m},
    /// `series[..=n]` read) into `out`, each component rounded once to the precision of `out`.
    /// Between the calls for 0, 1, …, n of one recursion only row `series[n]` may be new (the
    /// rows gathered by earlier calls are reused; a call for 0 or out of sequence regathers).
    pub fn coefficient(&mut self, series: &[[Float; DIM]], n: usize, out: &mut [Float; DIM]) {
        let series = &series[..=n];
        let mut finite = self.usable;
        if n == 0 || self.rows != n {
            for (m, row) in series[..n].iter().enumerate() {
                finite &= self.gather(m, row);
            }
        }
        finite &= self.gather(n, &series[n]);
        if !finite {
            self.rows = 0;
            self.field
                .taylor_coefficient_orders(series, n, out, &mut self.generic);
            return;
        }
        self.rows = n + 1;
        for (k, o) in out.iter_mut().enumerate() {
            self.component(k, n, o);
        }
    }

    /// Component k of f(x)ₙ into `out` (one rounding; one more per scaled term).
    fn component(&mut self, k: usize, n: usize, out: &mut Float) {
        let first = self.constants;
        // Scaled terms first: S rounded once, then c·S is an exact product like the others.
        for term in &self.plans[k].scaled {
            self.runs.clear();
            self.runs
                .push(Run::cauchy(first, term.i, term.j, n, false, 0));
            let sum = &mut self.sums[term.sum];
            self.acc.sum(&self.operands, &self.runs, sum);
            // A finite sum of finite products (or an overflow to ∞, then the generic path
            // would give ∞ too and the integrator stops on it).
            self.operands.set(self.first_sum + term.sum, sum);
        }
        let plan = &self.plans[k];
        self.runs.clear();
        for term in &plan.scaled {
            self.runs
                .push(Run::single(term.c, self.first_sum + term.sum, false, 0));
        }
        for term in &plan.shifted {
            self.runs
                .push(Run::cauchy(first, term.i, term.j, n, term.neg, term.shift));
        }
        for term in &plan.linear {
            self.runs
                .push(Run::single(term.c, first + n * DIM + term.i, false, 0));
        }
        self.acc.sum(&self.operands, &self.runs, out);
    }
}
