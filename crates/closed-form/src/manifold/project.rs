//! The nearest point of N to a state near a known motion, cheaply enough for every sample of a
//! run (issue 11: the error of an integrated motion split into drift along N and departure from
//! it).
//!
//! Near the torus (m, h) of the exact motion, N is parametrised by (ψ₁, ψ₂, m + δm, h + δh) and,
//! to first order in (δm, δh),
//!
//! ```text
//!   C(ψ, m + δm, h + δh) ≈ C(ψ) + ∂C/∂m(ψ)·δm + ∂C/∂h(ψ)·δh
//! ```
//!
//! with the derivatives from the closed form built once over dual numbers. Gauss–Newton over
//! (ψ₁, ψ₂, δm, δh) from a guess of the angles (the exact ones) gives the nearest point: its
//! angles (the phases of the state on its own torus), its (δm, δh) (the drift of the on-N
//! integrals) and the departure |state − nearest point| from N, in the units of the state. The
//! first-order model is exact to O(δm², δh²): an integrator's drift of the integrals (≤ 1e-6 in
//! practice) makes it negligible.
//!
//! Only C(ψ) is evaluated in the working precision: the derivatives (the Jacobian of the
//! Gauss–Newton steps, and ∂C/∂m, ∂C/∂h, which multiply the small δm, δh) are evaluated in f64,
//! so each step gains the 16 digits of f64 and the solution is that of the exact equations; a
//! first pass runs wholly in f64. At 30 digits this costs a few evaluations of the closed form
//! per state. Along a run, [`Projector::project_from`] starts from the nearest point of the
//! sample before (a warm start: one evaluation with derivatives and a chord step per sample).

use rsts_dynamics::jet::Jet;
use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::state::DIM;
use rsts_dynamics::Real;

use crate::error::ClosedFormError;
use crate::manifold::least_squares::{columns_of, rows_of, LeastSquares, Rows};
use crate::manifold::torus_map::{gauss_newton_step, max_gap, seeded_mh, wrap, TorusMap};
use crate::manifold::torus_table::TorusTable;
use crate::motion::{ExplicitMotion, TorusChoice};

/// The torus of a motion with the derivatives of its points in ψ, m and h (f64).
#[derive(Clone, Debug)]
pub struct Projector<T> {
    /// C(ψ) in the working precision.
    exact: TorusMap<T>,
    /// The same torus in f64, and built over jets seeded in m and h.
    map: TorusMap<f64>,
    in_mh: TorusMap<Jet<f64, 2>>,
    /// The f64 torus and its derivatives tabulated ([`TorusTable`]; `None`: the AGM path).
    table: Option<TorusTable>,
}

/// The nearest point of N to a state.
#[derive(Clone, Debug)]
pub struct Projection<T> {
    /// Its angles (ψ₁, ψ₂) ∈ [0, 2π)².
    pub phases: [T; 2],
    /// Its (m, h) minus the motion's.
    pub dm: T,
    pub dh: T,
    /// The point (ω, α, β).
    pub point: [T; DIM],
    /// max over the components of |state − point|: the departure from N.
    pub departure: T,
    /// Evaluations of the torus with its derivatives in the f64 pass (the cost: two from the
    /// exact angles on the default case, one from a warm start, [`Projector::project_from`]).
    pub jacobians: u32,
}

/// After step k + 1 of the f64 iteration, [`Projector::project_within`] gives up on a shift
/// beyond this many times its bound (never after the first step; from the fourth on, a shift
/// beyond the bound by more than four steps: the iteration goes on only while each step is at
/// most half the one before, so what remains of the shift's change is at most one step).
const GIVE_UP: [f64; 4] = [f64::INFINITY, 3000.0, 300.0, 1.0];

/// Below this step (radians) the f64 iteration keeps the last Jacobian (a chord step): it
/// changes by ~1e-6 relative over the remaining steps, so each step still gains six digits, and
/// the ∂C/∂m, ∂C/∂h of the final point are evaluated within 1e-6 of it (on the default case,
/// where the steps go 2e-5, 3e-10, 1e-16, within 3e-10).
const CHORD: f64 = 1e-6;

/// (ψ, δm, δh) during the iteration.
struct Unknowns<T> {
    psi: [T; 2],
    dm: T,
    dh: T,
}

/// Derivatives at one point, in f64: ∂C/∂ψ₁, ∂C/∂ψ₂, ∂C/∂m, ∂C/∂h (by rows: those of each
/// component), and C(ψ) itself.
struct Derivatives {
    value: [f64; DIM],
    rows: Rows,
}

impl<T: Real> Projector<T> {
    /// The projector for the torus of `motion`.
    pub fn new(motion: &ExplicitMotion<T>) -> Result<Self, ClosedFormError> {
        let c = &motion.constants;
        let [a, b, m, h] = [&c.a, &c.b, &c.m, &c.h].map(|x| x.to_f64());
        let torus = motion.choice.torus;
        let choice = TorusChoice {
            torus,
            phase1: 0.0,
            phase2: 0.0,
        };
        let lo = ExplicitMotion::new(a, b, m, h, choice)?;
        let in_mh = seeded_mh([&a, &b, &m, &h], torus)?;
        let dd = DoubleDouble::from_f64_exact;
        let fine = ExplicitMotion::new(dd(a), dd(b), dd(m), dd(h), choice).ok();
        let table = fine.and_then(|f| TorusTable::new(&TorusMap::of_motion(&f), &in_mh));
        Ok(Self {
            exact: TorusMap::of_motion(motion),
            map: TorusMap::of_motion(&lo),
            table,
            in_mh,
        })
    }

    /// The tabulated f64 torus (`None`: near Σ, the AGM path).
    pub fn table(&self) -> Option<&TorusTable> {
        self.table.as_ref()
    }

    /// ∂C/∂ψ₁, ∂C/∂ψ₂, ∂C/∂m, ∂C/∂h at ψ in f64 by the AGM path (over dual numbers and jets),
    /// what the table replaces.
    pub fn agm_derivatives(&self, psi: &[f64; 2]) -> [[f64; DIM]; 4] {
        let (_, jac) = self.map.state_and_jacobian(psi);
        let mh = self.in_mh.state_at(&psi.map(Jet::constant));
        [
            jac[0],
            jac[1],
            mh.each_ref().map(|d| d.eps[0]),
            mh.map(|d| d.eps[1]),
        ]
    }

    fn derivatives(&self, psi: &[f64; 2]) -> Derivatives {
        if let Some(table) = &self.table {
            let (value, rows) = table.state_and_rows(psi);
            return Derivatives { value, rows };
        }
        Derivatives {
            value: self.map.state_at(psi),
            rows: rows_of(&self.agm_derivatives(psi)),
        }
    }

    /// C(ψ) and the elimination of the Gauss–Newton step with its Jacobian (`None`: singular).
    #[inline]
    fn system(&self, psi: &[f64; 2]) -> ([f64; DIM], Option<LeastSquares>) {
        if let Some(table) = &self.table {
            return table.state_and_system(psi);
        }
        let d = self.derivatives(psi);
        (d.value, LeastSquares::new(&d.rows))
    }

    /// C(ψ) + ∂C/∂m·δm + ∂C/∂h·δh with the derivatives `d`.
    fn point(&self, x: &Unknowns<T>, base: [T; DIM], d: &Derivatives) -> [T; DIM] {
        let lit = |v: f64| x.dm.lit(v);
        std::array::from_fn(|k| {
            base[k].clone() + lit(d.rows[k][2]) * &x.dm + lit(d.rows[k][3]) * &x.dh
        })
    }

    /// The nearest point of N to `target`, from the angles `guess`. `None` when the Gauss–Newton
    /// system is singular (a state far from the torus).
    pub fn project(&self, target: &[T; DIM], guess: &[T; 2]) -> Option<Projection<T>> {
        self.project_within(target, guess, f64::INFINITY)
    }

    /// [`Projector::project`] of a nearest point with |δm|, |δh| ≤ `bound` (`None` otherwise).
    /// The f64 iteration gives up early on a state whose shift clearly stays beyond the bound
    /// (a sample whose error has saturated then costs three or four steps instead of sixteen):
    /// after step k a shift beyond [`GIVE_UP`]`[k]`·bound and beyond the bound by more than four
    /// times its last step. On 13 500 states off N in every camera (tests/closed_form/projector.rs) the
    /// shifts of the iterations that end within the bound were at most 186, 163, 27 and 1 times
    /// the bound after steps 1 to 4 (on camera V's dopri5 run, stop 30: 236, 138, 12 and 0.998):
    /// the thresholds of steps 2 and 3 leave a margin of 11 to 18. From step 4 on only the four
    /// steps count (stop 30): on that run the 2 % of its saturated samples whose shift creeps
    /// towards ~1.04 times the bound with steps shrinking fourfold gave up after 16 steps, now
    /// after 4 to 6 (8 % fewer evaluations of the torus on its saturated samples).
    pub fn project_within(
        &self,
        target: &[T; DIM],
        guess: &[T; 2],
        bound: f64,
    ) -> Option<Projection<T>> {
        self.project_from(target, guess, [0.0; 2], bound)
    }

    /// [`Projector::project_within`] from the angles `guess` and the shift (δm, δh) `shift`: a
    /// warm start from the nearest point of the sample before (its phase error added to this
    /// sample's exact angles, its shift), where the first step is already below [`CHORD`] and
    /// one evaluation with derivatives and a chord step converge. The same nearest point to
    /// the round-off (tests/closed_form/projector.rs, `a_warm_start_finds_the_nearest_point_of_a_cold_one`).
    pub fn project_from(
        &self,
        target: &[T; DIM],
        guess: &[T; 2],
        shift: [f64; 2],
        bound: f64,
    ) -> Option<Projection<T>> {
        let high = target[0].prec() > 53;
        // First pass in f64.
        let target64 = target.clone().map(|x| x.to_f64());
        let mut x64 = Unknowns {
            psi: guess.clone().map(|p| p.to_f64()),
            dm: shift[0],
            dh: shift[1],
        };
        let mut jacobians = 0;
        let mut last: Option<LeastSquares> = None;
        let mut previous = f64::INFINITY;
        // C(ψ) at the final angles, predicted from the last evaluation when the last step was
        // within the round-off.
        let mut predicted = None;
        for k in 0..16 {
            // A chord step once the steps are below CHORD: the Jacobian of the last evaluation
            // (at most CHORD away) serves, and only C(ψ) is evaluated; not where the shift of
            // the torus is so large that the lag of its ∂C/∂m, ∂C/∂h would move the point by
            // more than the round-off (1e-15).
            let lag = previous * (x64.dm.abs() + x64.dh.abs());
            let (value, system) = match (&self.table, last.take()) {
                (Some(table), Some(system)) if previous <= CHORD && lag <= 1e-15 => {
                    (table.state_at(&x64.psi), system)
                }
                _ => {
                    let (value, system) = self.system(&x64.psi);
                    jacobians += 1;
                    (value, system?)
                }
            };
            let rows = system.rows();
            let r: [f64; DIM] = std::array::from_fn(|k| {
                value[k] + rows[k][2] * x64.dm + rows[k][3] * x64.dh - target64[k]
            });
            let step = system.step(&r);
            let size = step[0].abs().max(step[1].abs());
            x64.psi = [x64.psi[0] + step[0], x64.psi[1] + step[1]];
            x64.dm += step[2];
            x64.dh += step[3];
            // Converged, or stalled at the round-off of the evaluation.
            if size <= 64.0 * f64::EPSILON || size > 0.5 * previous {
                if size <= 64.0 * f64::EPSILON {
                    // C(ψ + δψ) = C(ψ) + ∂C/∂ψ·δψ to O(δψ²) ~ 1e-27.
                    predicted = Some(std::array::from_fn(|k| {
                        value[k] + rows[k][0] * step[0] + rows[k][1] * step[1]
                    }));
                }
                last = Some(system);
                break;
            }
            last = Some(system);
            let give_up = GIVE_UP[k.min(GIVE_UP.len() - 1)] * bound;
            let beyond =
                |shift: f64, step: f64| shift.abs() > give_up.max(bound + 4.0 * step.abs());
            if beyond(x64.dm, step[2]) || beyond(x64.dh, step[3]) {
                return None;
            }
            previous = size;
        }
        // In f64 the shift is final: a sample beyond the bound needs no nearest point.
        let within64 = x64.dm.abs() <= bound && x64.dh.abs() <= bound;
        if !high && !within64 {
            return None;
        }
        let lift = |v: f64| target[0].lit(v);
        let mut x = Unknowns {
            psi: x64.psi.map(lift),
            dm: lift(x64.dm),
            dh: lift(x64.dh),
        };
        let eps = target[0].epsilon().to_f64();
        let mut d = if high {
            self.derivatives(&x64.psi)
        } else {
            let rows = *last?.rows();
            Derivatives {
                value: [0.0; DIM],
                rows,
            }
        };
        let base = match (&self.table, high, predicted) {
            (Some(_), false, Some(value)) => value.map(lift),
            (Some(table), false, None) => table.state_at(&x64.psi).map(lift),
            _ => self.exact.state_at(&x.psi),
        };
        let mut point = self.point(&x, base, &d);
        // Then in the working precision: each step with f64 derivatives gains ~16 digits.
        if high {
            let mut previous = f64::INFINITY;
            for _ in 0..12 {
                let r: [f64; DIM] =
                    std::array::from_fn(|k| (point[k].clone() - &target[k]).to_f64());
                let step = gauss_newton_step(columns_of(&d.rows).each_ref(), &r)?;
                let size = step[0].abs().max(step[1].abs());
                x.psi = [
                    x.psi[0].clone() + lift(step[0]),
                    x.psi[1].clone() + lift(step[1]),
                ];
                x.dm += lift(step[2]);
                x.dh += lift(step[3]);
                d = self.derivatives(&x.psi.clone().map(|p| p.to_f64()));
                point = self.point(&x, self.exact.state_at(&x.psi), &d);
                // The next step would be this one times the contraction of the iteration (the
                // f64 derivatives' 1e-16, the first-order model's δm, δh): stop when that is
                // below the precision, or when the steps stall at the round-off.
                let contraction =
                    1e-14 + 10.0 * (step[2].abs() + step[3].abs() + x64.dm.abs() + x64.dh.abs());
                if size * contraction <= 256.0 * eps || size > 0.5 * previous {
                    break;
                }
                previous = size;
            }
        }
        let within = |shift: &T| shift.abs().to_f64() <= bound;
        if !(within(&x.dm) && within(&x.dh)) {
            return None;
        }
        let two_pi = T::pi(target[0].prec()) * target[0].lit(2.0);
        Some(Projection {
            phases: x.psi.map(|p| wrap(p, &two_pi)),
            departure: max_gap(&point, target),
            point,
            dm: x.dm,
            dh: x.dh,
            jacobians,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With the table or by the AGM path, the projector finds the same nearest point (to the
    /// round-off of the two f64 tori) of states off the torus in a camera with m > 0 and one
    /// with m < 0.
    #[test]
    fn the_table_and_the_agm_path_find_the_same_nearest_point() {
        for (m, h) in [(0.3, -0.375), (-0.7092, 1.5643)] {
            let choice = TorusChoice::default();
            let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
            let with = Projector::new(&motion).unwrap();
            assert!(with.table.is_some());
            let without = Projector {
                table: None,
                ..with.clone()
            };
            let near = ExplicitMotion::new(1.0, 0.5, m + 2e-7, h - 3e-7, choice).unwrap();
            let torus = TorusMap::of_motion(&near);
            for k in 0..50 {
                let psi = [0.13 * k as f64, 6.0 - 0.11 * k as f64];
                let mut target = torus.state_at(&psi);
                target[k % DIM] += 1e-6;
                let guess = [psi[0] + 1e-3, psi[1] - 2e-3];
                let (p, q) = (
                    with.project(&target, &guess).unwrap(),
                    without.project(&target, &guess).unwrap(),
                );
                let what = format!("({m}, {h}) ψ = {psi:?}");
                for i in 0..2 {
                    let gap = (p.phases[i] - q.phases[i]).abs();
                    assert!(gap.min(TAU - gap) < 1e-12, "{what}: ψ{i} {gap:e}");
                }
                assert!(
                    (p.dm - q.dm).abs() < 1e-13 && (p.dh - q.dh).abs() < 1e-13,
                    "{what}"
                );
                assert!((p.departure - q.departure).abs() < 1e-14, "{what}");
                // The move off N by 1e-6 is partly a shift of the torus.
                assert!(
                    (p.dm - 2e-7).abs() < 3e-6 && p.departure > 1e-8,
                    "{what}: {p:?}"
                );
            }
        }
    }

    const TAU: f64 = std::f64::consts::TAU;
}
