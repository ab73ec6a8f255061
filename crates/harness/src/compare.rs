//! Compare = produce a trajectory with an integrator + analyse it against the closed form.

use rsts_dynamics::integrators::{map_problem, MethodConfig, OutputGrid, Problem};
use rsts_dynamics::scalar::bits_for_digits;
use rug::Float;

use rsts_closed_form::{Decimal, Motion, Times};

use crate::analysis::{Analysis, Observer, RunInfo};
use crate::case::Case;
use crate::integrator::{check_times, Integrator};
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
    preflight_at(&case.motion, &case.times(), config)
}

/// [`preflight`] of a comparison at any `times` (a grid or a list from 0).
pub fn preflight_at(
    motion: &Motion,
    times: &Times,
    config: &MethodConfig,
) -> Result<(), HarnessError> {
    let bits = reference_bits(config);
    let case = sampled(motion, times)?;
    let (explicit, fields) = case.reference_motion(bits)?;
    let grid = case.grid()?;
    let start = exact_state(&explicit.at(&Float::with_val(bits, 0.0)));
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

/// The times of a comparison checked (a grid: T ≥ 0, N ≥ 1; a list: from 0, finite and
/// strictly increasing, at most [`crate::MAX_SAMPLES`]) and the case that holds their motion
/// for the reference: its grid spans the same [0, T] with as many samples.
pub fn sampled(motion: &Motion, times: &Times) -> Result<Case, HarnessError> {
    match times {
        Times::Grid { t_end, samples } => {
            let case = Case::new(motion.clone(), t_end.clone(), *samples);
            case.validate()?;
            Ok(case)
        }
        list => {
            if list.len() > crate::MAX_SAMPLES {
                return Err(HarnessError::Setting(
                    vec!["times".into()],
                    format!(
                        "at most {} times are supported, got {}",
                        crate::MAX_SAMPLES,
                        list.len()
                    ),
                ));
            }
            check_times(&list.to_f64s())
                .map_err(|e| HarnessError::Setting(vec!["times".into()], e.to_string()))?;
            let last = Decimal::from_f64(list.last_f64())
                .map_err(|e| HarnessError::Setting(vec!["times".into()], e.to_string()))?;
            Ok(Case::new(motion.clone(), last, list.len()))
        }
    }
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
    compare_at(&case.motion, &case.times(), integrator, options, observer)
}

/// [`compare_integrator`] at any `times` ([`Times::Grid`] of a case, or a list from 0 such as
/// Python's `times=`). Sample k is at `times.time_f64(k)`, t_k rounded once to f64: the
/// integrator is asked for those times (a piece after the first for the times from t_first:
/// the piece's own grid, or t_k − t_first of a list) and each sample is analysed at the time
/// it reached, t_first + the time it reports (exact at the reference precision).
pub fn compare_at(
    motion: &Motion,
    times: &Times,
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
    let case = sampled(motion, times)?;
    let samples = case.samples;
    let bits = reference_bits_for(integrator.working_bits());
    let f = |x: f64| Float::with_val(bits, x);
    let mut analysis = Analysis::for_case(&case, bits, run_info(integrator))?;
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
    let sample_times = SampleTimes::new(times);
    let time = |k: usize| sample_times.time(k);
    if samples == 1 || time(samples - 1) == 0.0 {
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
        (samples - 1).min(options.pieces)
    } else {
        1
    };
    let mut state = start;
    for piece in 0..pieces {
        if observer.should_stop() {
            analysis.mark_incomplete();
            break;
        }
        let first = piece * (samples - 1) / pieces;
        let last = (piece + 1) * (samples - 1) / pieces;
        let t_first = time(first);
        // A piece of a grid is a grid (its own times k·span/(n − 1)); a piece of a list, the
        // list's times from its first.
        let local: Vec<f64> = match times {
            Times::Grid { .. } => OutputGrid::new(time(last) - t_first, last - first + 1)?.times(),
            _ => (first..=last).map(|k| time(k) - t_first).collect(),
        };
        let problem = Problem {
            fields: fields.clone(),
            initial: state.clone(),
        };
        let traj = integrator.integrate(&problem, &local)?;
        // An external integrator may name itself in its answer.
        analysis.rename(integrator.name());
        analysis.set_digits(integrator.digits());
        if traj.states.len() != local.len() || traj.times.len() != local.len() {
            return Err(HarnessError::Integrator(format!(
                "{} returned {} states for {} sample times",
                integrator.name(),
                traj.states.len(),
                local.len()
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
            // The time the integrator reached (exact: t_k itself when it reports the time
            // asked and t_k − t_first was exact).
            let t_abs = f(t_first) + f(*t);
            analysis.sample(&t_abs, s, observer)?;
        }
        state = traj.states.last().expect("a grid has samples").clone();
    }
    Ok(analysis.finish())
}

/// The f64 sample times t_k of [`Times`], each rounded once: a grid of a binary64 T takes one
/// IEEE division where k·T is exact in f64 (then correctly rounded, as the MPFR quotient
/// [`Times::time_f64`] computes otherwise).
pub struct SampleTimes<'a> {
    times: &'a Times,
    /// T of a grid when it is a binary64 number, and N − 1.
    binary: Option<(f64, f64)>,
}

impl<'a> SampleTimes<'a> {
    pub fn new(times: &'a Times) -> Self {
        let binary = match times {
            Times::Grid { t_end, samples } if *samples > 1 && t_end.is_binary64() => {
                Some((t_end.to_f64(), (*samples - 1) as f64))
            }
            _ => None,
        };
        Self { times, binary }
    }

    /// Number of times.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// t_k rounded once to f64.
    pub fn time(&self, k: usize) -> f64 {
        if let Some((t_end, n)) = self.binary {
            let kf = k as f64;
            let p = t_end * kf;
            // k·T exact (the fused residual is 0), far from the subnormals; k < N − 1.
            if kf < n && p.abs() > 1e-280 && t_end.mul_add(kf, -p) == 0.0 {
                return p / n;
            }
        }
        self.times.time_f64(k)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast f64 grid times are the correctly rounded ones of `Times::time_f64` (MPFR), for
    /// T binary64 or not, products k·T exact or not.
    #[test]
    fn sample_times_are_the_correctly_rounded_grid_times() {
        for (t_end, n) in [
            ("100", 1001),
            ("0.1", 1001),
            ("3.7", 777),
            ("1e-3", 10),
            ("123456.789", 4097),
            (
                "0.299999999999999988897769753748434595763683319091796875",
                201,
            ),
        ] {
            let times = Times::grid(Decimal::parse(t_end).unwrap(), n);
            let fast = SampleTimes::new(&times);
            for k in (0..n).step_by(7).chain([n - 2, n - 1]) {
                assert_eq!(
                    fast.time(k).to_bits(),
                    times.time_f64(k).to_bits(),
                    "T = {t_end}, N = {n}, k = {k}"
                );
            }
        }
    }
}
