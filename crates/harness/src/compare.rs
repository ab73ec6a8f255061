//! Compare = produce a trajectory with an integrator + analyse it against the closed form.

use rsts_dynamics::integrators::{map_problem, MethodConfig, OutputGrid, Problem};
use rsts_dynamics::scalar::bits_for_digits;
use rug::Float;

use crate::analysis::{Analysis, Observer, RunInfo};
use crate::case::Case;
use crate::integrator::Integrator;
use crate::metrics::{exact_state, Report};
use crate::HarnessError;

/// Bits the closed-form reference carries beyond the integrator's scalar.
pub const REFERENCE_GUARD_BITS: u32 = 64;

/// Default for [`CompareOptions::pieces`].
pub const DEFAULT_PIECES: usize = 64;

/// How a comparison runs the integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareOptions {
    /// At most this many calls of a restartable integrator per run: the grid is integrated in
    /// pieces, each restarting from the last state of the previous one, so a run reports
    /// progress and can be stopped between pieces. 1: one uninterrupted call over the whole
    /// grid (as `rsts integrate` and `rsts bench` run).
    pub pieces: usize,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            pieces: DEFAULT_PIECES,
        }
    }
}

/// Bits of the closed-form reference for a method.
pub fn reference_bits(config: &MethodConfig) -> u32 {
    reference_bits_for(config.working_bits())
}

/// Bits of the closed-form reference for an integrator computing in `working_bits`.
pub fn reference_bits_for(working_bits: u32) -> u32 {
    working_bits.max(bits_for_digits(30)) + REFERENCE_GUARD_BITS
}

/// What a report says about an integrator.
pub fn run_info(integrator: &dyn Integrator) -> RunInfo {
    let tol = integrator.tolerances();
    RunInfo {
        method: integrator.name(),
        rtol: tol.map(|t| t.rtol),
        atol: tol.map(|t| t.atol),
        digits: integrator.digits(),
    }
}

/// Check a comparison of the built-in method `config` before any work or output is done: the
/// case (finite numbers, a point of N off Σ within the documented ranges, an existing torus),
/// the grid, and the method's step budget over the whole grid ([`MethodConfig::check_budget`]:
/// a hopeless run is refused at once with its estimate, not after hours).
pub fn preflight(case: &Case, config: &MethodConfig) -> Result<(), HarnessError> {
    let bits = reference_bits(config);
    let (motion, fields) = case.reference_motion(bits)?;
    let grid = case.grid()?;
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

/// Compare the built-in method `config` with the closed form along `case`.
pub fn compare(
    case: &Case,
    config: &MethodConfig,
    observer: &mut dyn Observer,
) -> Result<Report, HarnessError> {
    let mut config = *config;
    compare_integrator(case, &mut config, &CompareOptions::default(), observer)
}

/// Compare any integrator with the closed form along `case`: start it from the exact state at
/// t = 0, integrate through the case's N evenly spaced times (in pieces when the integrator is
/// restartable), and analyse every sample as it comes.
pub fn compare_integrator(
    case: &Case,
    integrator: &mut dyn Integrator,
    options: &CompareOptions,
    observer: &mut dyn Observer,
) -> Result<Report, HarnessError> {
    if options.pieces == 0 {
        return Err(HarnessError::setting(
            &["pieces"],
            "pieces must be at least 1",
        ));
    }
    let bits = reference_bits_for(integrator.working_bits());
    let f = |x: f64| Float::with_val(bits, x);
    let mut analysis = Analysis::for_case(case, bits, run_info(integrator))?;
    let grid = case.grid()?;
    let start = analysis.exact_state(&f(0.0));
    let fields = analysis.fields().clone();
    integrator.check_budget(
        &Problem {
            fields: fields.clone(),
            initial: start.clone(),
        },
        &grid,
    )?;
    if case.samples == 1 || case.t_end.is_zero() {
        // No time passes: every sample is the start, rounded to the integrator's scalar.
        let problem = Problem {
            fields,
            initial: start,
        };
        let traj = integrator.integrate(&problem, &[0.0])?;
        analysis.rename(integrator.name());
        analysis.set_digits(integrator.digits());
        analysis.add_stats(&traj.stats);
        if let Some(stated) = integrator.stated_stats() {
            analysis.forget_unstated(&stated);
        }
        if let Some(w) = traj.wall_seconds {
            analysis.add_wall_seconds(w);
        }
        for s in &traj.states {
            analysis.sample(&f(0.0), s, observer)?;
        }
        return Ok(analysis.finish());
    }
    let pieces = if integrator.restartable() {
        (case.samples - 1).min(options.pieces)
    } else {
        1
    };
    let mut state = start;
    let mut t0 = f(0.0);
    for piece in 0..pieces {
        if observer.should_stop() {
            analysis.mark_incomplete();
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
        let traj = integrator.integrate(&problem, &local.times())?;
        // An external integrator may name itself in its answer.
        analysis.rename(integrator.name());
        analysis.set_digits(integrator.digits());
        if traj.states.len() != local.samples || traj.times.len() != local.samples {
            return Err(HarnessError::Integrator(format!(
                "{} returned {} states for {} sample times",
                integrator.name(),
                traj.states.len(),
                local.samples
            )));
        }
        analysis.add_stats(&traj.stats);
        if let Some(stated) = integrator.stated_stats() {
            analysis.forget_unstated(&stated);
        }
        if let Some(w) = traj.wall_seconds {
            analysis.add_wall_seconds(w);
        }
        for (j, (t, s)) in traj.times.iter().zip(&traj.states).enumerate() {
            if j == 0 && piece > 0 {
                continue; // the last sample of the previous piece
            }
            if j > 0 && observer.should_stop() && !integrator.restartable() {
                analysis.mark_incomplete();
                break;
            }
            let t_abs = t0.clone() + f(*t);
            analysis.sample(&t_abs, s, observer)?;
        }
        state = traj.states.last().expect("a grid has samples").clone();
        t0 += f(*traj.times.last().expect("a grid has samples"));
    }
    Ok(analysis.finish())
}

/// A report with a non-finite figure is an error naming it (the integrated motion left f64's
/// range), never a number shown as a result: `rsts compare`, `rsts check` and the Python package.
pub fn check_finite_report(r: &Report) -> Result<(), HarnessError> {
    for (name, x) in [
        ("max state error", r.max_state_error),
        ("final state error", r.final_state_error),
        ("max orientation error", r.max_orientation_error),
        ("drift of H", r.drift.h),
        ("drift of K", r.drift.k),
        ("drift of G", r.drift.g),
        ("constraint drift", r.drift.constraints),
        ("distance from N", r.drift.off_n),
    ] {
        if !x.is_finite() {
            return Err(HarnessError::Integrator(format!(
                "the comparison produced a non-finite {name} ({x}): the integrated motion left f64's range"
            )));
        }
    }
    Ok(())
}
