//! The comparison loop.

use rsts_closed_form::ExplicitMotion;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::integrators::{map_problem, MethodConfig, OutputGrid, Problem};
use rsts_dynamics::scalar::{bits_for_digits, digits_for_bits};
use rsts_dynamics::{Fields, State};
use rug::Float;

use crate::case::Case;
use crate::metrics::{exact_state, sample_errors, Drift, ManifoldN, Report, SampleRecord};
use crate::HarnessError;

/// Bits the closed-form reference carries beyond the integrator's scalar.
pub const REFERENCE_GUARD_BITS: u32 = 64;

/// At most this many restarts of the integrator per run: the grid is integrated in pieces so a
/// run can report progress and be stopped between pieces.
const MAX_PIECES: usize = 64;

/// Receives the samples of a comparison as they are computed.
pub trait Observer {
    /// Called once per sample, in time order.
    fn on_sample(&mut self, _record: &SampleRecord) -> Result<(), String> {
        Ok(())
    }
    /// Checked between pieces of the integration: true stops the run (the report then has
    /// `complete: false`).
    fn should_stop(&self) -> bool {
        false
    }
}

/// An observer that does nothing.
pub struct NoObserver;
impl Observer for NoObserver {}

/// What every sample is compared against.
struct Context<'a> {
    motion: &'a ExplicitMotion<Float>,
    fields: &'a Fields<Float>,
    n: &'a ManifoldN,
    initial_integrals: &'a [Float; 3],
}

impl Context<'_> {
    fn emit(
        &self,
        observer: &mut dyn Observer,
        index: usize,
        t: &Float,
        state: &State<Float>,
        report: &mut Report,
    ) -> Result<(), HarnessError> {
        let exact = exact_state(&self.motion.at(t));
        let (errors, ex, int) =
            sample_errors(self.fields, self.n, self.initial_integrals, &exact, state);
        report.absorb(&errors);
        observer
            .on_sample(&SampleRecord {
                index,
                t: t.to_f64(),
                exact: ex,
                integrated: int,
                errors,
            })
            .map_err(HarnessError::Observer)
    }
}

/// Bits of the closed-form reference for a method.
pub fn reference_bits(config: &MethodConfig) -> u32 {
    config.working_bits().max(bits_for_digits(30)) + REFERENCE_GUARD_BITS
}

/// Check a comparison before any work or output is done: the case (finite numbers, a point of
/// N off Σ within the documented ranges, an existing torus), the grid, and the method's step
/// budget over the whole grid ([`MethodConfig::check_budget`]: a hopeless run is refused at once
/// with its estimate, not after hours).
pub fn preflight(case: &Case, config: &MethodConfig) -> Result<(), HarnessError> {
    let bits = reference_bits(config);
    let (motion, fields) = case.reference_motion(bits)?;
    let grid = OutputGrid::new(case.t_end, case.samples)?;
    let start = exact_state(&motion.at(&Float::with_val(bits, 0.0)));
    let problem = map_problem(
        &Problem {
            fields,
            initial: start,
        },
        Float::to_f64,
    );
    config.check_budget(&problem, &grid)?;
    Ok(())
}

/// Compare `config` with the closed form along `case`.
pub fn compare(
    case: &Case,
    config: &MethodConfig,
    observer: &mut dyn Observer,
) -> Result<Report, HarnessError> {
    let bits = reference_bits(config);
    let f = |x: f64| Float::with_val(bits, x);
    let (motion, fields) = case.reference_motion(bits)?;
    let c = &motion.constants;
    let r4 = c.r2.clone() * &c.r2;
    let n = ManifoldN {
        k: r4.clone() * &c.m * &c.m,
        p2: c.p2.clone(),
        r4m: r4 * &c.m,
    };
    let grid = OutputGrid::new(case.t_end, case.samples)?;
    let start = exact_state(&motion.at(&f(0.0)));
    config.check_budget(
        &map_problem(
            &Problem {
                fields: fields.clone(),
                initial: start.clone(),
            },
            Float::to_f64,
        ),
        &grid,
    )?;
    let i0 = integrals(&fields, &start);
    let initial_integrals = [i0.h, i0.k, i0.g];
    let mut report = Report {
        method: config.method.as_str().to_string(),
        rtol: config.tolerances.rtol,
        atol: config.tolerances.atol,
        digits: digits_for_bits(config.working_bits()),
        reference_digits: digits_for_bits(bits),
        camera: motion.camera.label().to_string(),
        samples_compared: 0,
        complete: true,
        max_state_error: 0.0,
        final_state_error: 0.0,
        max_orientation_error: 0.0,
        drift: Drift::default(),
        steps: 0,
        rejected_steps: 0,
        rhs_evals: 0,
        integration_seconds: 0.0,
    };
    let ctx = Context {
        motion: &motion,
        fields: &fields,
        n: &n,
        initial_integrals: &initial_integrals,
    };
    if case.samples == 1 || case.t_end == 0.0 {
        // No time passes: every sample is the start, rounded to the method's scalar.
        let sol = config.propagate_mp(
            &Problem {
                fields: fields.clone(),
                initial: start,
            },
            &grid,
        )?;
        report.add_stats(&sol.stats);
        for (k, s) in sol.states.iter().enumerate() {
            ctx.emit(observer, k, &f(0.0), s, &mut report)?;
        }
        return Ok(report);
    }
    let pieces = (case.samples - 1).min(MAX_PIECES);
    let mut state = start;
    let mut t0 = f(0.0);
    for piece in 0..pieces {
        if observer.should_stop() {
            report.complete = false;
            break;
        }
        let first = piece * (case.samples - 1) / pieces;
        let last = (piece + 1) * (case.samples - 1) / pieces;
        let span = grid.time(last) - grid.time(first);
        let local = OutputGrid::new(span, last - first + 1)?;
        let problem = Problem {
            fields: fields.clone(),
            initial: state.clone(),
        };
        let sol = config.propagate_mp(&problem, &local)?;
        report.add_stats(&sol.stats);
        for (j, (t, s)) in sol.times.iter().zip(&sol.states).enumerate() {
            if j == 0 && piece > 0 {
                continue; // the last sample of the previous piece
            }
            let t_abs = t0.clone() + f(*t);
            ctx.emit(observer, first + j, &t_abs, s, &mut report)?;
        }
        state = sol.states.last().expect("a grid has samples").clone();
        t0 += f(*sol.times.last().expect("a grid has samples"));
    }
    Ok(report)
}
