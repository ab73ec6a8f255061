//! The stepper of taylor-f64 and taylor-dd on the lane kernel ([`LaneSeries`]), with the
//! compensated state in K = P + 1 parts (P: the kernel's parts, 1 for f64, 2 for
//! double-double), generic over the code path and instantiated per path under
//! `#[target_feature]` ([`run_on`]).
//!
//! One step, from the state s (K parts, lane form) at time t:
//!
//! 1. x₁ = f(s), x₂ = f(x)₁/2 in K parts: the same kernel in K-part arithmetic for orders 0
//!    and 1, from s itself (its low part and the low parts of a, b included);
//! 2. x₃ … xₚ in P parts: the kernel from rows 0, 1, 2 = s, x₁, x₂ rounded to P parts;
//! 3. the Jorba–Zou step h from ‖xₚ₋₁‖, ‖xₚ‖, rounded down to a multiple of a power of two g
//!    chosen so that every time t stays an exact f64 (so t_grid − t is exact);
//! 4. samples at the grid times inside the step, and the update, both as
//!    s + x₁τ + x₂τ² (K parts, exact products of τ's two parts) + Σ_{k≥3} xₖτᵏ (Horner in P
//!    parts), renormalised: an error-free compensated update.

// Index loops on purpose: this code is inlined into `#[target_feature]` functions, and plain
// loops over constant ranges unroll there without any closure (a function of its own,
// compiled without the path's features).
#![allow(clippy::needless_range_loop)]

use crate::equations::Param;
use crate::error::DynamicsError;
use crate::integrators::{OutputGrid, Tolerances};
use crate::state::DIM;

use super::expansion::{mul, two_sum, Acc, Lanes, Scalar};
use super::layout::{Layout, ROWS};
use super::series::{
    from_lanes, load_block, splat, store_block, to_lanes, LaneSeries, NCoef, Row16,
    SlotCoefficients,
};
use super::simd::{portable::Portable, Isa, Row8, SimdPath};
use super::stepping::{run_steps, Stepper, Steps};

/// A run's input in K parts: the initial state (natural order) and the fields.
#[derive(Clone, Debug)]
pub(crate) struct FastInput<const K: usize> {
    pub x0: [[f64; K]; DIM],
    pub a: [f64; K],
    pub b: [f64; K],
}

/// A run's output: the states at the grid times in K parts (natural order), or with
/// [`FastSettings::dense`] the run's own steps (rounded to f64, the start left out).
pub(crate) type FastOutput<const K: usize> = Steps<[[f64; K]; DIM]>;

/// The settings of a run.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FastSettings<'a> {
    pub name: &'static str,
    pub order: usize,
    pub tolerances: Tolerances,
    pub grid: &'a OutputGrid,
    /// Coefficients x₁ … x_ext computed in K parts (≤ [`MAX_EXT`]).
    pub ext: usize,
    /// `Some(k)`: sample the run's own steps, k times inside each
    /// ([`polynomial_step`](crate::integrators::dense::polynomial_step)),
    /// instead of the grid.
    pub dense: Option<usize>,
}

/// c·param in K parts.
unsafe fn coefficient<I: Isa, const K: usize>(
    input: &FastInput<K>,
    c: f64,
    param: Param,
) -> [f64; K] {
    let mut cc = [0.0; K];
    cc[0] = c;
    match param {
        Param::One => cc,
        Param::A => mul::<Scalar<I>, K>(&cc, &input.a),
        Param::B => mul::<Scalar<I>, K>(&cc, &input.b),
    }
}

/// The slot coefficients of `layout` for the fields of `input`, in K parts.
pub(super) unsafe fn slot_coefficients<I: Isa, const K: usize>(
    layout: &Layout,
    input: &FastInput<K>,
) -> SlotCoefficients<K> {
    let mut left = [[Row8::default(); K]; ROWS];
    for (r, row) in layout.slots.iter().enumerate() {
        for (lane, slot) in row.iter().enumerate() {
            if slot.left.is_some() {
                let c = coefficient::<I, K>(input, slot.c, slot.param);
                for (i, p) in c.iter().enumerate() {
                    left[r][i].0[lane] = *p;
                }
            }
        }
    }
    let n = layout
        .n_terms
        .iter()
        .map(|t| NCoef {
            n: t.n,
            coef: coefficient::<I, K>(input, t.c, t.param),
            pos: layout.pos[t.i],
        })
        .collect();
    SlotCoefficients { left, n }
}

/// The time granularity g = 2^(E − 52), 2^(E−1) > t_end: every multiple of g up to 2^E is an
/// f64, so t (a sum of steps that are multiples of g) is exact.
fn granularity(t_end: f64) -> f64 {
    let e = t_end.max(1.0).log2().floor() as i32 + 2;
    2f64.powi(e - 52)
}

/// Most coefficients computed in K parts.
pub(crate) const MAX_EXT: usize = 3;

/// s + Σ_{k=1..e} xₖτᵏ (K parts, exact products with τ's two parts) + τ^(e+1)·Σ_{k>e} xₖτ^(k−e−1)
/// (Horner in P parts), lane form; τ = τ₀ + τ₁ exactly, e = `ext` (≤ [`MAX_EXT`]) extended
/// coefficients.
#[inline(always)]
unsafe fn evaluate<I: Isa, const P: usize, const K: usize>(
    main: &LaneSeries<I, P>,
    ext: &LaneSeries<I, K>,
    state: &[Row16; K],
    tau: [f64; 2],
    order: usize,
    e: usize,
) -> [Row16; K] {
    type S<I> = Scalar<I>;
    // τ, τ², …, τ^(e+1) in K parts.
    let mut pow = [[0.0; K]; MAX_EXT + 1];
    pow[0][0] = tau[0];
    pow[0][1] = tau[1];
    for k in 1..=e {
        pow[k] = mul::<S<I>, K>(&pow[k - 1], &pow[0]);
    }
    let tail = if order > e {
        let mut tp = [0.0; P];
        let mut tq = [0.0; P];
        tp.copy_from_slice(&pow[0][..P]);
        tq.copy_from_slice(&pow[e][..P]);
        let (q, n) = main.horner(e + 1, &tp);
        let tq = splat::<I, P>(&tq);
        Some((mul::<Lanes<I>, P>(&q, &tq), mul::<Lanes<I>, P>(&n, &tq)))
    } else {
        None
    };
    let mut out = [Row16::default(); K];
    for block in [false, true] {
        let mut acc = Acc::<Lanes<I>, K>::from(load_block::<I, K>(state, block));
        for k in 1..=e {
            acc.add_prod(
                &load_block::<I, K>(&ext.x[k], block),
                &splat::<I, K>(&pow[k - 1]),
            );
        }
        if let Some((q, n)) = &tail {
            let s = if block { n } else { q };
            let mut w = [I::zero(); K];
            w[..P].copy_from_slice(&s[..P]);
            acc.add_exp(&w);
        }
        store_block::<I, K>(&acc.value(), &mut out, block);
    }
    out
}

/// The first P parts of K.
#[inline(always)]
fn trunc<const K: usize, const P: usize>(x: &[Row16; K]) -> [Row16; P] {
    let mut out = [Row16::default(); P];
    out.copy_from_slice(&x[..P]);
    out
}

/// The lane stepper on path `I` over [`run_steps`] (see the module documentation). P + 1 = K.
#[inline(always)]
unsafe fn run<I: Isa, const P: usize, const K: usize>(
    layout: &Layout,
    input: &FastInput<K>,
    settings: FastSettings,
) -> Result<FastOutput<K>, DynamicsError> {
    debug_assert_eq!(P + 1, K);
    let FastSettings {
        name,
        order,
        tolerances,
        grid,
        dense,
        ..
    } = settings;
    let coef = slot_coefficients::<I, K>(layout, input);
    // The extended coefficients x₁ … x_e (and the main kernel's rows 0 … e − 1, copied).
    let e = settings.ext.min(order).min(MAX_EXT);
    let mut stepper = LaneStepper {
        layout,
        ext: LaneSeries::<I, K>::new(layout, &coef, e, false),
        main: LaneSeries::<I, P>::new(layout, &coef.truncate::<P>(), order, true),
        state: to_lanes(layout, &input.x0),
        t: 0.0,
        order,
        e,
        tolerances,
        safety: (-0.7 / (order as f64 - 1.0)).exp() / std::f64::consts::E.powi(2),
        g: granularity(grid.t_end),
    };
    run_steps(&mut stepper, name, order, grid, dense)
}

/// The state of a lane run (K parts, lane form) at time t, and its series.
struct LaneStepper<'a, I: Isa, const P: usize, const K: usize> {
    layout: &'a Layout,
    /// x₁ … x_e in K parts.
    ext: LaneSeries<I, K>,
    /// x_(e+1) … xₚ in P parts (rows 0 … e copied from `ext`).
    main: LaneSeries<I, P>,
    state: [Row16; K],
    /// A multiple of `g`: an exact f64.
    t: f64,
    order: usize,
    /// Coefficients in K parts ([`FastSettings::ext`], at most the order).
    e: usize,
    tolerances: Tolerances,
    /// e^(−0.7/(p − 1))/e², Jorba–Zou's safety factor.
    safety: f64,
    /// The time granularity ([`granularity`]).
    g: f64,
}

impl<I: Isa, const P: usize, const K: usize> LaneStepper<'_, I, P, K> {
    /// The state at time `t` inside the step (τ = t − self.t exactly, in two parts).
    #[inline(always)]
    unsafe fn evaluate_at(&self, t: f64) -> [[f64; K]; DIM] {
        let (tau, tau_lo) = two_sum::<Scalar<I>>(t, -self.t);
        let (main, ext, state) = (&self.main, &self.ext, &self.state);
        let x = evaluate::<I, P, K>(main, ext, state, [tau, tau_lo], self.order, self.e);
        from_lanes(self.layout, &x)
    }
}

impl<I: Isa, const P: usize, const K: usize> Stepper for LaneStepper<'_, I, P, K> {
    type State = [[f64; K]; DIM];

    #[inline(always)]
    fn now(&self) -> f64 {
        self.t
    }

    /// x₁ … x_e in K parts, then x_(e+1) … xₚ in P parts.
    #[inline(always)]
    unsafe fn coefficients(&mut self) {
        let (e, order) = (self.e, self.order);
        let (main, ext) = (&mut self.main, &mut self.ext);
        if e == 0 {
            main.set(0, &trunc(&self.state));
            main.advance(0, order);
        } else {
            ext.set(0, &self.state);
            ext.advance(0, e);
            for m in 0..e {
                main.copy_from(m, ext);
            }
            if order > e {
                main.set(e, &trunc(&ext.x[e]));
                main.advance(e, order);
            } else {
                main.x[e] = trunc(&ext.x[e]);
            }
        }
    }

    /// Jorba–Zou's step.
    #[inline(always)]
    unsafe fn step(&self) -> f64 {
        let Tolerances { rtol, atol } = self.tolerances;
        let order = self.order;
        let row = &self.state[0];
        let x_norm = I::max_abs(I::load(&row.q)).max(I::max_abs(I::load(&row.n)));
        let ln_x = if rtol * x_norm > atol {
            x_norm.ln()
        } else {
            0.0
        };
        let (n1, n2) = (self.main.norm(order - 1), self.main.norm(order));
        // min(ρ_{p−1}, ρ_p) with one exp (exp is monotonic: the same value).
        let e1 = (ln_x - n1.ln()) / (order - 1) as f64;
        let e2 = (ln_x - n2.ln()) / order as f64;
        let rho = e1.min(e2).exp();
        rho * self.safety
    }

    #[inline(always)]
    fn least_step(&self) -> f64 {
        self.g
    }

    /// Rounded down to a multiple of g: every time stays an exact f64.
    #[inline(always)]
    fn rounded(&self, h: f64) -> f64 {
        (h / self.g).floor() * self.g
    }

    #[inline(always)]
    unsafe fn state_at(&mut self, t: f64) -> [[f64; K]; DIM] {
        self.evaluate_at(t)
    }

    /// The step end t + h is exact, so τ = h there: the state [`Stepper::advance`] computes.
    #[inline(always)]
    unsafe fn state_at_f64(&mut self, t: f64) -> [f64; DIM] {
        let x = self.evaluate_at(t);
        std::array::from_fn(|i| x[i].iter().rev().sum())
    }

    #[inline(always)]
    fn is_finite(x: &[[f64; K]; DIM]) -> bool {
        x.iter().all(|c| c[0].is_finite())
    }

    #[inline(always)]
    unsafe fn advance(&mut self, h: f64) {
        let (main, ext) = (&self.main, &self.ext);
        self.state = evaluate::<I, P, K>(main, ext, &self.state, [h, 0.0], self.order, self.e);
        self.t += h;
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn run_avx512<const P: usize, const K: usize>(
    layout: &Layout,
    input: &FastInput<K>,
    settings: FastSettings,
) -> Result<FastOutput<K>, DynamicsError> {
    run::<super::simd::avx512::Avx512, P, K>(layout, input, settings)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2<const P: usize, const K: usize>(
    layout: &Layout,
    input: &FastInput<K>,
    settings: FastSettings,
) -> Result<FastOutput<K>, DynamicsError> {
    run::<super::simd::avx2::Avx2, P, K>(layout, input, settings)
}

fn run_portable<const P: usize, const K: usize>(
    layout: &Layout,
    input: &FastInput<K>,
    settings: FastSettings,
) -> Result<FastOutput<K>, DynamicsError> {
    // SAFETY: the portable path uses no instruction beyond the build's target.
    unsafe { run::<Portable, P, K>(layout, input, settings) }
}

/// Run the lane kernel on `path` (which must be available: [`SimdPath::available`]).
pub(crate) fn run_on<const P: usize, const K: usize>(
    path: SimdPath,
    layout: &Layout,
    input: &FastInput<K>,
    settings: FastSettings,
) -> Result<FastOutput<K>, DynamicsError> {
    if !path.available() {
        return Err(DynamicsError::Settings(format!(
            "the {path} code path is not available on this CPU"
        )));
    }
    match path {
        // SAFETY: the CPU has the path's features (checked above).
        #[cfg(target_arch = "x86_64")]
        SimdPath::Avx512 => unsafe { run_avx512::<P, K>(layout, input, settings) },
        #[cfg(target_arch = "x86_64")]
        SimdPath::Avx2 => unsafe { run_avx2::<P, K>(layout, input, settings) },
        _ => run_portable::<P, K>(layout, input, settings),
    }
}
