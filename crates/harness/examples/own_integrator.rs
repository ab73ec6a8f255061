//! A user-defined integrator checked by the harness: the explicit midpoint rule (second order)
//! with a fixed step, written here from the vector field alone, compared with the closed form
//! and benchmarked against the built-in Dop853, and its order observed at fixed steps
//! (`rsts convergence` in-process: `rsts_harness::convergence`).
//!
//! `cargo run --release -p rsts-harness --example own_integrator`

use rsts_dynamics::integrators::{
    MethodConfig, MethodName, OutputGrid, Problem, Propagator, Solution, Stats, Tolerances,
};
use rsts_dynamics::{DynamicsError, State, VectorField};
use rsts_harness::convergence::FixedStepIntegrator;
use rsts_harness::rug::Float;
use rsts_harness::{
    compare_integrator, convergence, measure_against, measure_integrator, reference_bits_for, Case,
    CompareOptions, ConvergencePlan, HarnessError, Integrator, NoObserver, Propagated, Reference,
    Trajectory,
};

/// The midpoint rule at the fixed step a convergence study asks (every sample the end of a
/// step): the signature takes `Problem<rug::Float>`, with `rug` as the harness re-exports it.
struct FixedMidpoint;

impl FixedStepIntegrator for FixedMidpoint {
    fn name(&self) -> String {
        "midpoint".into()
    }
    fn working_bits(&self) -> u32 {
        53
    }
    fn integrate_at(
        &mut self,
        step: f64,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        Propagated::new(Midpoint { step }).integrate(problem, times)
    }
}

/// The explicit midpoint rule: y ← y + h f(y + h/2 f(y)), a whole number of steps per sample.
struct Midpoint {
    step: f64,
}

impl Propagator<f64> for Midpoint {
    fn name(&self) -> &'static str {
        "midpoint"
    }

    fn propagate_grid(
        &self,
        problem: &Problem<f64>,
        grid: &OutputGrid,
    ) -> Result<Solution<f64>, DynamicsError> {
        let field = VectorField::new(&problem.fields);
        let mut y = problem.initial.to_array();
        let (mut states, mut stats) = (vec![problem.initial.clone()], Stats::default());
        let started = std::time::Instant::now();
        for k in 1..grid.samples {
            let dt = grid.time(k) - grid.time(k - 1);
            let n = (dt / self.step).ceil().max(1.0) as u64;
            let h = dt / n as f64;
            for _ in 0..n {
                let (mut k1, mut k2) = ([0.0; 9], [0.0; 9]);
                field.eval_into(&y, &mut k1);
                let mid: [f64; 9] = std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]);
                field.eval_into(&mid, &mut k2);
                for i in 0..9 {
                    y[i] += h * k2[i];
                }
            }
            stats.accepted_steps += n;
            stats.rhs_evals += 2 * n;
            states.push(State::from_slice(&y));
        }
        stats.integration_seconds = started.elapsed().as_secs_f64();
        Ok(Solution {
            method: "midpoint",
            times: grid.times(),
            states,
            stats,
        })
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let case =
        Case::default_i_plus().with_grid(rsts_closed_form::Decimal::parse("20").unwrap(), 201);
    // compare: the report of `rsts compare` for the user's integrator.
    for step in [1e-2, 5e-3] {
        let mut mine = Propagated::new(Midpoint { step }).named(format!("midpoint h={step}"));
        let r = compare_integrator(
            &case,
            &mut mine,
            &CompareOptions::default(),
            &mut NoObserver,
        )?;
        println!(
            "{}: max state error {:.3e}, drift of H {:.3e}, {} steps",
            r.method,
            r.max_state_error,
            r.drift.h,
            r.steps.unwrap_or_default()
        );
    }
    // bench: work against precision, beside a built-in method, on one reference.
    let evals = |row: &rsts_harness::bench::BenchRow| {
        row.rhs_evals.map_or("n/a".to_string(), |n| n.to_string())
    };
    let reference = Reference::new(&case, reference_bits_for(53))?;
    println!(
        "\n{:>16}  {:>10}  {:>9}  {:>9}",
        "method", "max error", "rhs evals", "seconds"
    );
    for step in [4e-2, 2e-2, 1e-2] {
        let mut mine = Propagated::new(Midpoint { step }).named(format!("midpoint h={step}"));
        let row = measure_integrator(&reference, &mut mine, 3)?;
        println!(
            "{:>16}  {:>10.3e}  {:>9}  {:>9.2e}",
            row.method,
            row.max_error,
            evals(&row),
            row.integration_seconds
        );
    }
    // convergence: the observed order at fixed steps (the default sweep: min(0.5, the sample
    // spacing) and 8 halvings), with its floor judged.
    let case = Case::default_i_plus();
    let plan = ConvergencePlan::new(case.clone(), &ConvergencePlan::default_steps(&case))?;
    let report = convergence(&plan, &mut [&mut FixedMidpoint])?;
    println!(
        "\n{}: {}\n",
        report.fits[0].method,
        report.fits[0].describe()
    );
    let dop853 = MethodConfig::new(MethodName::Dop853, Tolerances::new(1e-8, 1e-8)?, None)?;
    let row = measure_against(&reference, &dop853, 3)?;
    println!(
        "{:>16}  {:>10.3e}  {:>9}  {:>9.2e}",
        "dop853 1e-8",
        row.max_error,
        evals(&row),
        row.integration_seconds
    );
    Ok(())
}
