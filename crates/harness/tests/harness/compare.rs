//! The harness measures real errors: tight runs in every camera are accurate, a loose run is
//! reported as loose, and the reported figures are consistent with each other.

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_harness::{compare, Case, NoObserver, Observer, SampleRecord};

fn case(m: f64, h: f64) -> Case {
    Case::binary([1.0, 0.5, m, h], 0, [0.4, 1.3], 20.0, 41).unwrap()
}

fn config(method: MethodName, tol: f64) -> MethodConfig {
    MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap()
}

#[test]
fn tight_runs_are_accurate_and_loose_runs_are_caught_in_every_camera() {
    for (camera, m, h) in rsts_closed_form::EXAMPLE_POINTS_A1_B05 {
        let label = camera.label();
        let tight = compare(
            &case(m, h),
            &config(MethodName::Dop853, 1e-12),
            &mut NoObserver,
        )
        .unwrap();
        assert_eq!(tight.camera, label);
        assert!(tight.complete && tight.samples_compared == 41);
        assert!(
            tight.max_state_error < 1e-8,
            "{label}: dop853 at 1e-12 off by {:e}",
            tight.max_state_error
        );
        assert!(tight.steps > Some(0) && tight.rhs_evals > tight.steps);
        let loose = compare(
            &case(m, h),
            &config(MethodName::Dopri5, 1e-4),
            &mut NoObserver,
        )
        .unwrap();
        assert!(
            loose.max_state_error > 100.0 * tight.max_state_error,
            "{label}: loose {:e} vs tight {:e}",
            loose.max_state_error,
            tight.max_state_error
        );
        // The drifts of the loose run show too.
        assert!(loose.drift.h > tight.drift.h);
    }
}

/// Collects the records.
#[derive(Default)]
struct Collect(Vec<SampleRecord>, usize);
impl Observer for Collect {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        self.0.push(*r);
        Ok(())
    }
    fn should_stop(&self) -> bool {
        self.1 > 0 && self.0.len() >= self.1
    }
}

#[test]
fn records_are_consistent_and_a_run_can_be_stopped() {
    let c = case(0.3, -0.375);
    let mut all = Collect::default();
    let report = compare(&c, &config(MethodName::Dop853, 1e-10), &mut all).unwrap();
    assert_eq!(all.0.len(), 41);
    for (k, r) in all.0.iter().enumerate() {
        assert_eq!(r.index, k);
        assert!((r.t - 20.0 * k as f64 / 40.0).abs() < 1e-12);
        // The exact motion keeps H = h; the integrated one is near it.
        assert!((r.exact.h + 0.375).abs() < 1e-14);
        assert!(r.errors.state_error <= report.max_state_error);
    }
    // At t = 0 the only error is the rounding of the start to f64 (half an ulp of values ≲ 2).
    assert!(all.0[0].errors.state_error <= 2.3e-16);
    assert_eq!(report.final_state_error, all.0[40].errors.state_error);
    let mut stop = Collect(Vec::new(), 10);
    let partial = compare(&c, &config(MethodName::Dop853, 1e-10), &mut stop).unwrap();
    assert!(!partial.complete);
    assert!(partial.samples_compared < 41 && partial.samples_compared >= 10);
}

#[test]
fn high_precision_runs_are_measured_against_a_finer_reference() {
    let mut c = case(0.3, -0.375);
    c.samples = 5;
    let cfg = config(MethodName::TaylorMp, 1e-40).with_digits(50).unwrap();
    let r = compare(&c, &cfg, &mut NoObserver).unwrap();
    assert!(r.reference_digits > r.digits + 15);
    assert!(
        r.max_state_error < 1e-35,
        "taylor-mp 50 digits: {:e}",
        r.max_state_error
    );
    assert!(r.max_state_error > 0.0);
}

#[test]
fn bad_cases_are_rejected() {
    let mut c = case(0.3, -0.375);
    c.t_end = rsts_closed_form::Decimal::parse("-1").unwrap();
    let e = compare(&c, &config(MethodName::Dop853, 1e-10), &mut NoObserver).unwrap_err();
    assert!(e.to_string().contains("t-end"), "{e}");
    let e = compare(
        &case(0.0, 2.0),
        &config(MethodName::Dop853, 1e-10),
        &mut NoObserver,
    )
    .unwrap_err();
    assert!(e.to_string().contains("Σ"), "{e}");
}

/// A user's own integrator, defined outside the project: explicit Euler with a fixed step.
struct Euler {
    step: f64,
}

impl rsts_dynamics::integrators::Propagator<f64> for Euler {
    fn name(&self) -> &'static str {
        "euler"
    }
    fn propagate_grid(
        &self,
        problem: &rsts_dynamics::integrators::Problem<f64>,
        grid: &rsts_dynamics::integrators::OutputGrid,
    ) -> Result<rsts_dynamics::integrators::Solution<f64>, rsts_dynamics::DynamicsError> {
        let field = rsts_dynamics::VectorField::new(&problem.fields);
        let mut y = problem.initial.to_array();
        let mut states = vec![problem.initial.clone()];
        let mut steps = 0;
        for k in 1..grid.samples {
            let dt = grid.time(k) - grid.time(k - 1);
            let n = (dt / self.step).ceil().max(1.0) as usize;
            for _ in 0..n {
                let mut dy = [0.0; 9];
                field.eval_into(&y, &mut dy);
                for i in 0..9 {
                    y[i] += dt / n as f64 * dy[i];
                }
                steps += 1;
            }
            states.push(rsts_dynamics::State::from_slice(&y));
        }
        Ok(rsts_dynamics::integrators::Solution {
            method: "euler",
            times: grid.times(),
            states,
            stats: rsts_dynamics::integrators::Stats {
                accepted_steps: steps,
                rhs_evals: steps,
                ..Default::default()
            },
        })
    }
}

/// Any Propagator<f64> is measured like a built-in method: compare and bench take it, name it,
/// and find Euler's first-order error (halving the step halves it) far above RK4's.
#[test]
fn a_user_defined_propagator_is_compared_and_benchmarked() {
    use rsts_harness::{compare_integrator, measure_integrator, CompareOptions, Propagated};
    let c = {
        let mut c = case(0.3, -0.375);
        c.t_end = rsts_closed_form::Decimal::from_f64(2.0_f64).unwrap();
        c.samples = 21;
        c
    };
    let opts = CompareOptions::default();
    let mut coarse = Propagated::new(Euler { step: 1e-3 });
    let r1 = compare_integrator(&c, &mut coarse, &opts, &mut NoObserver).unwrap();
    let mut fine = Propagated::new(Euler { step: 5e-4 }).named("euler-fine");
    let r2 = compare_integrator(&c, &mut fine, &opts, &mut NoObserver).unwrap();
    assert_eq!(
        (r1.method.as_str(), r2.method.as_str()),
        ("euler", "euler-fine")
    );
    assert_eq!(r1.samples_compared, 21);
    let ratio = r1.max_state_error / r2.max_state_error;
    assert!((1.8..2.2).contains(&ratio), "first order: ratio {ratio}");
    let steps = r1.steps.unwrap();
    assert!((2000..=2020).contains(&steps), "{steps} steps");
    let rk4 = compare(&c, &config(MethodName::Rk4, 1e-12), &mut NoObserver).unwrap();
    assert!(
        rk4.max_state_error < 1e-3 * r1.max_state_error,
        "rk4 {:e}, euler {:e}",
        rk4.max_state_error,
        r1.max_state_error
    );

    let reference = rsts_harness::Reference::new(&c, 200).unwrap();
    let row = measure_integrator(&reference, &mut coarse, 2).unwrap();
    assert_eq!(row.method, "euler");
    assert!(row.tolerance.is_nan(), "no tolerances given");
    assert!(
        (row.max_error - r1.max_state_error).abs() < 1e-3 * r1.max_state_error,
        "bench {:e} vs compare {:e}",
        row.max_error,
        r1.max_state_error
    );
}

/// compare = produce + analyse: one uninterrupted run analysed sample by sample gives the same
/// report as compare_integrator with one piece.
#[test]
fn compare_is_produce_then_analyse() {
    use rsts_dynamics::integrators::Problem;
    use rsts_harness::{
        analyse, compare_integrator, reference_bits, run_info, Analysis, CompareOptions, Integrator,
    };
    let c = case(-0.7092, 1.5643);
    let mut cfg = config(MethodName::TaylorF64, 1e-11);
    let one = CompareOptions { pieces: 1 };
    let report = compare_integrator(&c, &mut cfg, &one, &mut NoObserver).unwrap();
    let bits = reference_bits(&cfg);
    let analysis = Analysis::for_case(&c, bits, run_info(&cfg)).unwrap();
    let start = analysis.exact_state(&rug::Float::with_val(bits, 0));
    let problem = Problem {
        fields: analysis.fields().clone(),
        initial: start,
    };
    let grid = c.grid().unwrap();
    let traj = cfg.integrate(&problem, &grid.times()).unwrap();
    let times: Vec<rug::Float> = traj
        .times
        .iter()
        .map(|&t| rug::Float::with_val(bits, t))
        .collect();
    let produced = analyse(analysis, &times, &traj.states, &mut NoObserver).unwrap();
    assert_eq!(report.max_state_error, produced.max_state_error);
    assert_eq!(report.drift, produced.drift);
    assert_eq!(report.samples_compared, produced.samples_compared);
    assert_eq!(report.steps, Some(traj.stats.accepted_steps));
    // States analysed without their run: the cost is not known.
    assert_eq!(produced.steps, None);
    // In 64 pieces the integrator restarts: another trajectory, the same accuracy class.
    let pieces = compare(&c, &cfg, &mut NoObserver).unwrap();
    assert_ne!(pieces.steps, report.steps);
    assert!(pieces.max_state_error < 100.0 * report.max_state_error.max(1e-12));
}
