//! The phase clock of a motion: u = u₀ + u̇·t reduced modulo the period 4K of sn, carried
//! [`GUARD_BITS`] beyond the working precision so that long times do not eat into it.
//!
//! Two implementations of the same reduction from the same constants (u₀, u̇, 4K rounded once to
//! bits + 64 bits, bits = max(precision, 53)):
//!
//! * **MPFR** ([`PhaseClock::reduced`]): u, ⌊u/4K⌋ and u − n·4K in MPFR at bits + 64 bits. Used at
//!   any precision above f64's.
//! * **f64 expansions** ([`PhaseClock::reduced_f64`]), for precisions of 53 bits and less (the f64
//!   closed form): each constant of 117 bits is held exactly as an unevaluated sum of three f64
//!   (hi + mid + lo, 159 bits), the products u̇·t and n·4K are formed from error-free
//!   products (`two_prod` by FMA) and the nine pieces are added in double-double with
//!   error-free sums. For |t| ≤ [`F64_CLOCK_MAX_T`] the reduced phase carries an error below
//!   ~2⁻⁸⁵ (t = 1.5e9, u̇ ≈ 1), so rounded to f64 it is the MPFR reduction's f64 bit for bit
//!   except when both lie within ~2⁻⁸⁵ of a rounding boundary (the MPFR one itself errs by up
//!   to 2⁻¹¹⁷·|u̇t|). No allocation, about 20 floating-point operations instead of four MPFR
//!   operations on 117-bit numbers with allocations (55–70 % of an f64 state before).
//!   Larger or non-finite t go through MPFR.
//! * **Double-double** ([`PhaseClock::reduced_dd`]), for the double-double closed form (clock
//!   constants of 106 + 64 bits held to 159 bits in the same three f64): the same sum, returned
//!   as a double-double (hi + lo) before its last rounding. Its error is a few units of 2⁻¹⁰⁶
//!   of 4K plus 2⁻¹⁵⁹·|u̇t| (the dropped bits of the constants): 2⁻¹⁰³ for t ≤ 1e9.

use rsts_dynamics::scalar::double_double::DD_BITS;
use rsts_dynamics::scalar::{every_lane, DoubleDouble, DoubleDouble4, LANES};
use rug::Float;

use crate::scalar::GUARD_BITS;

/// Largest |t| served by the f64 expansion clock (beyond: MPFR). u̇·t then stays below 2⁵³·|u̇|
/// and n·4K's pieces are error-free products of integers below 2⁵³.
pub const F64_CLOCK_MAX_T: f64 = 1e12;

/// u₀, u̇ and the period 4K of sn for both variables, [`GUARD_BITS`] beyond the working precision,
/// in MPFR and as three-term f64 expansions.
#[derive(Clone, Debug)]
pub(super) struct PhaseClock {
    bits: u32,
    u0: [Float; 2],
    u_dot: [Float; 2],
    four_k: [Float; 2],
    /// The same constants as f64 expansions, when bits ≤ 106 + 64.
    fast: Option<[FastConstants; 2]>,
    /// The expansions are exact (bits ≤ 53 + 64 ≤ 159): [`Self::reduced_f64`] may use them.
    exact: bool,
    /// The phases in turns (u/4K) as f64 expansions, with `fast`.
    turns: Option<[TurnConstants; 2]>,
}

/// One variable's phase in turns, φ = u/4K = φ₀ + φ̇·t, as three-term f64 expansions (the
/// quotients u₀/4K and u̇/4K at the clock's precision, held to 159 bits).
#[derive(Clone, Copy, Debug)]
pub(super) struct TurnConstants {
    start: [f64; 3],
    rate: [f64; 3],
}

/// One variable's constants as exact three-term f64 expansions.
#[derive(Clone, Copy, Debug)]
struct FastConstants {
    u0: [f64; 3],
    u_dot: [f64; 3],
    four_k: [f64; 3],
}

/// x as hi + mid + lo (exact for x of at most 159 significant bits within f64's range).
fn split3(x: &Float) -> [f64; 3] {
    let hi = x.to_f64();
    let r = Float::with_val(x.prec(), x - hi);
    let mid = r.to_f64();
    let lo = Float::with_val(x.prec(), &r - mid).to_f64();
    [hi, mid, lo]
}

/// s + e = a + b exactly, s = fl(a + b) (Knuth).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// p + e = a·b exactly, p = fl(a·b).
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// A double-double accumulator: (hi, lo) += x with an error-free sum and renormalisation.
#[inline(always)]
fn dd_add((hi, lo): (f64, f64), x: f64) -> (f64, f64) {
    let (s, e) = two_sum(hi, x);
    let (s, e2) = two_sum(s, e + lo);
    (s, e2)
}

impl PhaseClock {
    /// The clock from constants computed at `bits` (= working bits + [`GUARD_BITS`]).
    pub(super) fn new(bits: u32, u0: [Float; 2], u_dot: [Float; 2], four_k: [Float; 2]) -> Self {
        let exact = bits <= 53 + GUARD_BITS;
        let fast = (bits <= DD_BITS + GUARD_BITS).then(|| {
            std::array::from_fn(|i| FastConstants {
                u0: split3(&u0[i]),
                u_dot: split3(&u_dot[i]),
                four_k: split3(&four_k[i]),
            })
        });
        // Every piece must be finite and the split exact for the fast path to be the same
        // reduction.
        let fast = fast.filter(|f: &[FastConstants; 2]| {
            f.iter().all(|c| {
                [c.u0, c.u_dot, c.four_k]
                    .iter()
                    .flatten()
                    .all(|x| x.is_finite())
                    && c.four_k[0] > 0.0
            })
        });
        let turns = fast.map(|_| {
            std::array::from_fn(|i| TurnConstants {
                start: split3(&Float::with_val(bits, &u0[i] / &four_k[i])),
                rate: split3(&Float::with_val(bits, &u_dot[i] / &four_k[i])),
            })
        });
        let turns = turns.filter(|c: &[TurnConstants; 2]| {
            c.iter()
                .all(|c| c.start.iter().chain(&c.rate).all(|x| x.is_finite()))
        });
        Self {
            bits,
            u0,
            u_dot,
            four_k,
            fast,
            exact,
            turns,
        }
    }

    /// The constants of the phases in turns ([`turns_at`]), when the clock has expansions.
    #[inline(always)]
    pub(super) fn turns(&self) -> Option<&[TurnConstants; 2]> {
        self.turns.as_ref()
    }

    /// Bits of the MPFR constants.
    pub(super) fn bits(&self) -> u32 {
        self.bits
    }

    /// The rates u̇ of both variables.
    pub(super) fn u_dot(&self) -> &[Float; 2] {
        &self.u_dot
    }

    /// u₀ and 4K of both variables.
    pub(super) fn u0_four_k(&self) -> (&[Float; 2], &[Float; 2]) {
        (&self.u0, &self.four_k)
    }

    /// u at time t reduced to [0, 4K), in MPFR at the clock's precision: u = u̇t + u₀ and
    /// u − n·4K, each rounded once, with n = ⌊u/4K⌋. n comes from f64 (u/4K to 53 bits, off by
    /// less than 2⁻⁵⁰·|u/4K|) when that is farther than (|u/4K| + 1)·2⁻⁴⁶ from an integer and
    /// below 2⁴⁰, so it is the n of the MPFR quotient, and n·4K is a product by an integer: the
    /// MPFR division's result bit for bit, without the division, the floor and their numbers
    /// ([`Self::reduced_by_division`] otherwise).
    pub(super) fn reduced(&self, i: usize, t: &Float) -> Float {
        let mut u = Float::with_val(self.bits, &self.u_dot[i] * t);
        u += &self.u0[i];
        let q = u.to_f64() / self.four_k[i].to_f64();
        let n = q.floor();
        let (frac, margin) = (q - n, (q.abs() + 1.0) * 2f64.powi(-46));
        if !(q.abs() < 2f64.powi(40) && frac > margin && frac < 1.0 - margin) {
            return self.reduced_by_division(i, u);
        }
        u -= Float::with_val(self.bits, &self.four_k[i] * n as i64);
        u
    }

    /// u − n·4K with n = ⌊u/4K⌋ from an MPFR division (u = u̇t + u₀ at the clock's precision).
    fn reduced_by_division(&self, i: usize, u: Float) -> Float {
        let n = Float::with_val(self.bits, &u / &self.four_k[i]).floor();
        u - n * &self.four_k[i]
    }

    /// u at time t reduced to [0, 4K) and rounded to f64, from the f64 expansions; `None` when
    /// the clock has none (precision above f64's) or t is not finite or beyond
    /// [`F64_CLOCK_MAX_T`] (then use [`Self::reduced`]). The error-free products use the FMA
    /// instruction where the CPU has it (detected at run time; the build targets any x86-64),
    /// else `f64::mul_add` in software: the same exact results.
    #[inline]
    pub(super) fn reduced_f64(&self, i: usize, t: f64) -> Option<f64> {
        if !self.exact {
            return None;
        }
        self.reduced_pair(i, t).map(|(hi, lo)| hi + lo)
    }

    /// u at time t reduced to [0, 4K) as a double-double, from the f64 expansions; `None` when
    /// the clock has none (precision above double-double's) or t is not finite or beyond
    /// [`F64_CLOCK_MAX_T`] (then use [`Self::reduced`]).
    #[inline]
    pub(super) fn reduced_dd(&self, i: usize, t: f64) -> Option<DoubleDouble> {
        self.reduced_pair(i, t)
            .map(|(hi, lo)| DoubleDouble::new(hi, lo))
    }

    /// The reduction as (hi, lo) before the last rounding: `hi + lo` in f64 is the f64 result.
    #[inline]
    fn reduced_pair(&self, i: usize, t: f64) -> Option<(f64, f64)> {
        let c = &self.fast.as_ref()?[i];
        if t.is_nan() || t.abs() > F64_CLOCK_MAX_T {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA (checked just above).
            return unsafe { reduce_fma(c, t) };
        }
        reduce_portable(c, t)
    }
}

/// [`reduce`] compiled for CPUs with FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn reduce_fma(c: &FastConstants, t: f64) -> Option<(f64, f64)> {
    reduce(c, t)
}

/// [`reduce`] for any CPU.
fn reduce_portable(c: &FastConstants, t: f64) -> Option<(f64, f64)> {
    reduce(c, t)
}

/// u₀ + u̇t − n·4K for the n that puts it in [0, 4K), as (hi, lo) with hi + lo rounded to f64
/// the f64 result: the large products exact
/// (`two_prod`), their difference exact (`two_sum`), the other nine pieces added in
/// double-double from large to small. `None` if n cannot be settled in three tries (a remainder
/// within rounding of 0 or 4K: the caller then uses MPFR).
#[inline(always)]
fn reduce(c: &FastConstants, t: f64) -> Option<(f64, f64)> {
    let [uh, um, ul] = c.u_dot;
    let [kh, km, kl] = c.four_k;
    let [oh, om, ol] = c.u0;
    // n = ⌊u/4K⌋ from an f64 estimate, corrected if the remainder leaves [0, 4K).
    let mut n = (uh.mul_add(t, oh) / kh).floor();
    for _ in 0..3 {
        let (p1, e1) = two_prod(uh, t);
        let (p2, e2) = two_prod(um, t);
        let p3 = ul * t;
        let (q1, f1) = two_prod(n, kh);
        let (q2, f2) = two_prod(n, km);
        let q3 = n * kl;
        // The large pieces first (they cancel), then the rest from large to small; the
        // smallest (below 2⁻⁷⁰·|u̇t|) in plain f64.
        let mut acc = two_sum(p1, -q1);
        for x in [oh, p2, -q2, e1, -f1, om] {
            acc = dd_add(acc, x);
        }
        let tail = ((e2 - f2) + (p3 - q3)) + ol;
        let lo = acc.1 + tail;
        let r = acc.0 + lo;
        if r < 0.0 {
            n -= 1.0;
        } else if r >= kh {
            // At least 4K to f64 accuracy: one more period.
            n += 1.0;
        } else {
            return Some((acc.0, lo));
        }
    }
    None
}

/// The phase in turns φ₀ + φ̇t − n ∈ [0, 1) at an f64 time as a double-double (`None` for t
/// not finite or beyond [`F64_CLOCK_MAX_T`], or an n not settled in three tries: the caller
/// then reduces u in the clock's other ways). As [`reduce`] with a period of 1: φ̇t from
/// error-free products, n an integer (no product n·4K), the pieces added in double-double
/// from large to small. Error a few units of 2⁻¹⁰⁶ plus 2⁻¹⁵⁹·|φ̇t| (the constants' dropped
/// bits); sin and cos of 2πφ need no reduction by π then ([`DoubleDouble::sin_cos_turns`]).
#[inline(always)]
pub(super) fn turns_at(c: &TurnConstants, t: f64) -> Option<DoubleDouble> {
    if t.is_nan() || t.abs() > F64_CLOCK_MAX_T {
        return None;
    }
    let [fh, fm, fl] = c.rate;
    let [oh, om, ol] = c.start;
    let (p1, e1) = two_prod(fh, t);
    let (p2, e2) = two_prod(fm, t);
    let tail = (e2 + fl * t) + ol;
    let mut n = (p1 + oh).floor();
    for _ in 0..3 {
        let mut acc = two_sum(p1, -n);
        for x in [oh, p2, e1, om] {
            acc = dd_add(acc, x);
        }
        let lo = acc.1 + tail;
        let r = acc.0 + lo;
        if r < 0.0 {
            n -= 1.0;
        } else if r >= 1.0 {
            n += 1.0;
        } else {
            return Some(DoubleDouble::new(acc.0, lo));
        }
    }
    None
}

/// [`turns_at`] of four times: the first try of n of each lane in the four lanes at once
/// (the same operations); a lane that needs another n, or a time out of the clock's range, by
/// [`turns_at`] itself. The phases, and per lane whether it has none (then its phase is ⅛
/// turn, a placeholder).
#[inline(always)]
pub(super) fn turns_at4(c: &TurnConstants, t: [f64; LANES]) -> (DoubleDouble4, [bool; LANES]) {
    let [fh, fm, fl] = c.rate;
    let [oh, om, ol] = c.start;
    let (mut phi, mut settled) = (DoubleDouble4::default(), [false; LANES]);
    for i in 0..LANES {
        let t = t[i];
        let (p1, e1) = two_prod(fh, t);
        let (p2, e2) = two_prod(fm, t);
        let tail = (e2 + fl * t) + ol;
        let n = (p1 + oh).floor();
        let mut acc = two_sum(p1, -n);
        for x in [oh, p2, e1, om] {
            acc = dd_add(acc, x);
        }
        let lo = acc.1 + tail;
        let r = acc.0 + lo;
        settled[i] = (t.abs() <= F64_CLOCK_MAX_T) & (0.0..1.0).contains(&r);
        // DoubleDouble::new(acc.0, lo).
        let (hi, lo) = two_sum(acc.0, lo);
        phi.hi[i] = hi;
        phi.lo[i] = lo;
    }
    let mut none = [false; LANES];
    if !every_lane(settled) {
        for i in 0..LANES {
            if !settled[i] {
                let x = turns_at(c, t[i]);
                none[i] = x.is_none();
                phi.set_lane(i, x.unwrap_or(DoubleDouble::from_f64_exact(0.125)));
            }
        }
    }
    (phi, none)
}

#[cfg(test)]
mod tests {
    use super::super::{ExplicitMotion, TorusChoice};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rug::Float;

    /// For every example point of a = 1, b = 0.5 (nine cameras) and 20 000 random times up to
    /// 1.5e9 (uniform, integers, small, and skewed towards 0), the f64 expansion clock gives
    /// the MPFR reduction's phase rounded to f64 bit for bit. The check has teeth: the plain
    /// f64 reduction fmod(u̇t + u₀, 4K) fails it at long times.
    #[test]
    fn f64_clock_is_the_mpfr_reduction_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(15);
        let mut naive_misses = 0;
        for (camera, m, h) in crate::EXAMPLE_POINTS_A1_B05 {
            let choice = TorusChoice {
                torus: 0,
                phase1: 0.7,
                phase2: 2.1,
            };
            let motion = ExplicitMotion::<f64>::new(1.0, 0.5, m, h, choice).unwrap();
            let clock = motion.clock.as_ref().unwrap();
            let fast = clock.fast.as_ref().unwrap();
            for k in 0..20_000 {
                let t = match k % 4 {
                    0 => rng.gen_range(0.0..1.5e9),
                    1 => rng.gen_range(-1e3..1e3),
                    2 => rng.gen_range(0..1_500_000_000u64) as f64,
                    _ => 1.5e9 * rng.gen::<f64>().powi(8),
                };
                for (i, c) in fast.iter().enumerate() {
                    let exact = clock.reduced(i, &Float::with_val(clock.bits(), t)).to_f64();
                    let got = clock.reduced_f64(i, t).unwrap();
                    assert_eq!(
                        got.to_bits(),
                        exact.to_bits(),
                        "{camera:?} variable {i} t = {t:e}: {got:e} vs {exact:e}"
                    );
                    let naive = c.u_dot[0].mul_add(t, c.u0[0]).rem_euclid(c.four_k[0]);
                    naive_misses += usize::from(naive != exact);
                }
            }
        }
        eprintln!("plain f64 reduction: {naive_misses} of 360000 phases differ");
        assert!(naive_misses > 100_000, "{naive_misses}");
    }

    /// The MPFR reduction with n from f64 is the one by an MPFR division bit for bit, at 30, 100
    /// and 1000 digits over the nine cameras: random times up to 1e15 and times within 1e-30 of
    /// a turning point u = j·4K (where n from f64 is undecided and the division serves).
    #[test]
    fn mpfr_clock_without_division_is_the_division_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        for digits in [30, 100, 1000] {
            let bits = rsts_dynamics::scalar::bits_for_digits(digits);
            let f = |x: f64| Float::with_val(bits, x);
            for (camera, m, h) in crate::EXAMPLE_POINTS_A1_B05 {
                let choice = TorusChoice {
                    torus: 0,
                    phase1: 0.7,
                    phase2: 2.1,
                };
                let motion = ExplicitMotion::new(f(1.0), f(0.5), f(m), f(h), choice).unwrap();
                let clock = motion.clock.as_ref().unwrap();
                let hi = clock.bits();
                for k in 0..400 {
                    let i = k % 2;
                    let t = match k % 5 {
                        0 => Float::with_val(hi, rng.gen_range(0.0..1e15)),
                        1 => Float::with_val(hi, rng.gen_range(-1e3..1e3)),
                        2 => Float::with_val(hi, rng.gen_range(0.0..1.0)) / 3u32 * 1e9,
                        _ => {
                            // u = j·4K ± 1e-30: the turning point of a random period.
                            let j = rng.gen_range(-1000..1000i32);
                            let (u0, four_k) = clock.u0_four_k();
                            let tj =
                                (Float::with_val(hi, &four_k[i] * j) - &u0[i]) / &clock.u_dot()[i];
                            tj + Float::with_val(hi, rng.gen_range(-1.0..1.0) * 1e-30)
                        }
                    };
                    let fast = clock.reduced(i, &t);
                    let u = Float::with_val(hi, &clock.u_dot[i] * &t) + &clock.u0[i];
                    let slow = clock.reduced_by_division(i, u);
                    assert!(
                        fast == slow && fast.prec() == slow.prec(),
                        "{camera:?} {digits} digits, variable {i}, t = {t}: {fast} vs {slow}"
                    );
                }
            }
        }
    }

    /// Beyond F64_CLOCK_MAX_T and for non-finite t the fast clock declines (MPFR serves them);
    /// a clock above f64 precision has no fast path.
    #[test]
    fn fast_clock_declines_what_it_cannot_do() {
        let choice = TorusChoice::default();
        let motion = ExplicitMotion::<f64>::new(1.0, 0.5, 0.3, -0.375, choice).unwrap();
        let clock = motion.clock.as_ref().unwrap();
        assert!(clock.reduced_f64(0, 1e11).is_some());
        assert!(clock.reduced_f64(0, 2e12).is_none());
        assert!(clock.reduced_f64(1, f64::NAN).is_none());
        assert!(clock.reduced_f64(1, f64::INFINITY).is_none());
        let f = |x: f64| Float::with_val(200, x);
        let mp = ExplicitMotion::<Float>::new(f(1.0), f(0.5), f(0.3), f(-0.375), choice).unwrap();
        assert!(mp.clock.as_ref().unwrap().reduced_f64(0, 1.0).is_none());
    }

    /// The FMA and the portable builds of the reduction give the same bits (both form exact
    /// products), whichever one the CPU runs.
    #[test]
    fn fma_and_portable_paths_agree() {
        let motion =
            ExplicitMotion::<f64>::new(1.0, 0.5, -0.7092, 1.5643, TorusChoice::default()).unwrap();
        let fast = motion.clock.as_ref().unwrap().fast.unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..2000 {
            let t = rng.gen_range(-1.5e9..1.5e9);
            for c in &fast {
                let portable = super::reduce_portable(c, t);
                #[cfg(target_arch = "x86_64")]
                if std::arch::is_x86_feature_detected!("fma") {
                    // SAFETY: FMA is available.
                    assert_eq!(portable, unsafe { super::reduce_fma(c, t) }, "t = {t:e}");
                }
                assert!(portable.is_some());
            }
        }
    }
}
