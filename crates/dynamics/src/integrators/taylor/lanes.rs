//! taylor-f64 and taylor-dd on the lane stepper ([`super::fast`]): the code path, the
//! coefficients computed in extended parts, the state split into f64 parts and back, and the
//! [`Solution`] of a run.

use std::any::Any;

use rug::Float;

use crate::equations::{Component, VectorField};
use crate::error::DynamicsError;
use crate::integrators::dense::StepSamples;
use crate::integrators::{OutputGrid, Problem, Solution};
use crate::scalar::{double_double::DD_BITS, DoubleDouble, Real, F64_BITS};
use crate::state::{State, DIM};

use super::fast::{run_on, FastInput, FastOutput, FastSettings};
use super::layout::Layout;
use super::simd::SimdPath;
use super::{generic, Taylor};

impl Taylor {
    /// The code path this run uses: the forced one, else `RSTS_SIMD`, else the best available.
    pub fn simd_path(&self) -> Result<SimdPath, DynamicsError> {
        match self.simd {
            Some(p) if p.available() => Ok(p),
            Some(p) => Err(DynamicsError::Settings(format!(
                "the {p} code path is not available on this CPU"
            ))),
            None => SimdPath::from_env(),
        }
    }
}

/// Bits beyond the kernel scalar's that the compensated lane kernels deliver: the state and
/// x₁ … x_e carry one part more than the scalar, so what is rounded per step is
/// x_{e+1}τ^(e+1) and the tail, ~2⁻⁸ of the state or less; tolerances down to
/// 2^−(bits + 8) (f64: 4.3e-19, double-double: 4.8e-35) still lower the error (measured in
/// docs/taylor.md).
pub const LANE_EXTRA_BITS: u32 = 8;

/// Tolerances at least this many units of the kernel scalar's round-off run without extended
/// coefficients: the error there is the truncation's (≥ 10× the round-off of the plain
/// kernel, measured in docs/taylor.md), so the extra precision would buy nothing.
pub(crate) const PLAIN_ABOVE_ULPS: f64 = 512.0;

/// How many coefficients the kernel of P parts computes in P + 1 parts at tolerance `eps`:
/// none when `eps` ≥ [`PLAIN_ABOVE_ULPS`] units of its round-off; else x₁, x₂ for f64 (the
/// leading terms of the update: its floor drops ~10× from plain f64) and x₁, x₂, x₃ for
/// double-double, whose floor is set by the rounding of x₃τ³ otherwise (measured in
/// docs/taylor.md). The state and the update stay compensated (P + 1 parts) either way.
fn ext_orders(p: usize, eps: f64) -> usize {
    if eps >= PLAIN_ABOVE_ULPS * 2f64.powi(-53 * p as i32) {
        0
    } else if p == 1 {
        2
    } else {
        3
    }
}

/// `x` in K parts: successive roundings of the residual to f64 (exact when `x` has at most
/// 53·K significant bits, e.g. a double-double for K ≥ 2).
fn float_parts<const K: usize>(x: &Float) -> [f64; K] {
    let mut rest = Float::with_val(x.prec().max(64), x);
    std::array::from_fn(|_| {
        let p = rest.to_f64();
        if p.is_finite() {
            rest -= p;
        }
        p
    })
}

/// The sum of the parts at `bits` bits (exact when `bits` ≥ their span).
fn parts_to_float<const K: usize>(x: &[f64; K], bits: u32) -> Float {
    let mut f = Float::with_val(bits.max(64 * K as u32 + 64), x[0]);
    for p in &x[1..] {
        f += p;
    }
    Float::with_val(bits, f)
}

impl Taylor {
    /// Run the lane kernel (P parts, state in K = P + 1) for `table`, if it applies: the
    /// table has a [`Layout`] and the state is compensated. `bits`: the kernel scalar's bits
    /// (for the tolerance check); `dense`: [`FastSettings::dense`].
    fn run_lanes<const P: usize, const K: usize>(
        &self,
        table: &[Component; DIM],
        input: &FastInput<K>,
        bits: u32,
        name: &'static str,
        (grid, dense): (&OutputGrid, Option<usize>),
    ) -> Result<Option<FastOutput<K>>, DynamicsError> {
        // A fixed order and step runs on the generic stepper.
        if !self.compensated || self.fixed.is_some() {
            return Ok(None);
        }
        let Some(layout) = Layout::from_table(table) else {
            return Ok(None);
        };
        let grid = OutputGrid::new(grid.t_end, grid.samples)?;
        let eps = self.effective_tolerance(bits + LANE_EXTRA_BITS)?;
        let order = Self::order_for(eps);
        if input.x0.iter().flatten().any(|x| !x.is_finite()) {
            return Err(DynamicsError::State(
                "initial state has a component that is not a finite number".into(),
            ));
        }
        let path = self.simd_path()?;
        let settings = FastSettings {
            name,
            order,
            tolerances: self.tolerances,
            grid: &grid,
            ext: ext_orders(P, eps),
            dense,
        };
        run_on::<P, K>(path, &layout, input, settings).map(Some)
    }

    /// The lane-kernel run of taylor-f64 or taylor-dd (`None`: another scalar, or a table or
    /// setting the kernel does not take); `dense`: [`FastSettings::dense`].
    pub(super) fn lane_run<T: Real>(
        &self,
        field: &VectorField<T>,
        problem: &Problem<T>,
        grid: &OutputGrid,
        dense: Option<usize>,
    ) -> Result<Option<LaneRun>, DynamicsError> {
        let any: &dyn Any = problem;
        let table = field.table();
        if let Some(p) = any.downcast_ref::<Problem<f64>>() {
            let input = FastInput::<2> {
                x0: p.initial.to_array().map(|x| [x, 0.0]),
                a: [p.fields.a, 0.0],
                b: [p.fields.b, 0.0],
            };
            let out =
                self.run_lanes::<1, 2>(table, &input, F64_BITS, Self::NAME_F64, (grid, dense));
            Ok(out?.map(LaneRun::F64))
        } else if let Some(p) = any.downcast_ref::<Problem<DoubleDouble>>() {
            let dd = |x: &DoubleDouble| [x.hi, x.lo, 0.0];
            let input = FastInput::<3> {
                x0: p.initial.to_array().map(|x| dd(&x)),
                a: dd(&p.fields.a),
                b: dd(&p.fields.b),
            };
            let out = self.run_lanes::<2, 3>(table, &input, DD_BITS, Self::NAME_DD, (grid, dense));
            Ok(out?.map(LaneRun::Dd))
        } else {
            Ok(None)
        }
    }

    /// taylor-f64 and taylor-dd of [`Taylor::propagate_field`] on the lane kernel (`None`:
    /// another scalar, or a table or setting the kernel does not take).
    pub(super) fn propagate_lanes<T: Real>(
        &self,
        field: &VectorField<T>,
        problem: &Problem<T>,
        grid: &OutputGrid,
    ) -> Result<Option<Solution<T>>, DynamicsError> {
        let solution: Box<dyn Any> = match self.lane_run(field, problem, grid, None)? {
            Some(LaneRun::F64(out)) => Box::new(solution(Self::NAME_F64, out, |x| x[0] + x[1])),
            Some(LaneRun::Dd(out)) => Box::new(solution(Self::NAME_DD, out, |x| {
                DoubleDouble::new(x[0], x[1] + x[2])
            })),
            None => return Ok(None),
        };
        Ok(Some(
            *solution
                .downcast::<Solution<T>>()
                .expect("the solution has the problem's scalar"),
        ))
    }

    /// taylor-f64 (`dd = false`) or taylor-dd (`dd = true`) from a high-precision problem,
    /// with nothing lost at the start: the initial state and the fields enter with their low
    /// parts (x = x₀ + x₁ (+ x₂), each part the f64 rounding of the rest), and the states come
    /// back with the compensated state's low part, at the precision of `problem`. Falls back
    /// to rounding the problem to the scalar when the lane kernel does not apply
    /// (uncompensated).
    pub fn propagate_float(
        &self,
        dd: bool,
        problem: &Problem<Float>,
        grid: &OutputGrid,
    ) -> Result<Solution<Float>, DynamicsError> {
        let bits = problem.initial.omega[0].prec();
        let table = &crate::equations::EULER_POISSON;
        if dd {
            let input = FastInput::<3> {
                x0: problem.initial.to_array().map(|x| float_parts(&x)),
                a: float_parts(&problem.fields.a),
                b: float_parts(&problem.fields.b),
            };
            if let Some(out) =
                self.run_lanes::<2, 3>(table, &input, DD_BITS, Self::NAME_DD, (grid, None))?
            {
                return Ok(solution(Self::NAME_DD, out, |x| parts_to_float(x, bits)));
            }
            let p = crate::integrators::map_problem(problem, DoubleDouble::from_float);
            let sol = generic::propagate(self, VectorField::new(&p.fields), &p, grid)?;
            Ok(crate::integrators::map_solution(sol, |x| x.to_float(bits)))
        } else {
            let input = FastInput::<2> {
                x0: problem.initial.to_array().map(|x| float_parts(&x)),
                a: float_parts(&problem.fields.a),
                b: float_parts(&problem.fields.b),
            };
            if let Some(out) =
                self.run_lanes::<1, 2>(table, &input, F64_BITS, Self::NAME_F64, (grid, None))?
            {
                return Ok(solution(Self::NAME_F64, out, |x| parts_to_float(x, bits)));
            }
            let p = crate::integrators::map_problem(problem, Float::to_f64);
            let sol = generic::propagate(self, VectorField::new(&p.fields), &p, grid)?;
            Ok(crate::integrators::map_solution(sol, |x| {
                Float::with_val(bits, *x)
            }))
        }
    }
}

/// A lane-kernel run: taylor-f64 (state in two parts) or taylor-dd (three).
pub(super) enum LaneRun {
    F64(FastOutput<2>),
    Dd(FastOutput<3>),
}

impl LaneRun {
    /// The run's own steps ([`FastSettings::dense`]).
    pub(super) fn steps(self) -> StepSamples {
        match self {
            LaneRun::F64(out) => out.steps,
            LaneRun::Dd(out) => out.steps,
        }
    }
}

/// A [`Solution`] from a lane-kernel run, each state's K parts mapped by `f`.
fn solution<T, const K: usize>(
    method: &'static str,
    out: FastOutput<K>,
    f: impl Fn(&[f64; K]) -> T,
) -> Solution<T> {
    Solution {
        method,
        times: out.times,
        states: out
            .states
            .iter()
            .map(|x| {
                let v: [T; DIM] = std::array::from_fn(|k| f(&x[k]));
                let [w1, w2, w3, a1, a2, a3, b1, b2, b3] = v;
                State {
                    omega: [w1, w2, w3],
                    alpha: [a1, a2, a3],
                    beta: [b1, b2, b3],
                }
            })
            .collect(),
        stats: out.stats,
    }
}
