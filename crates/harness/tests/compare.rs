//! The harness measures real errors: tight runs in every camera are accurate, a loose run is
//! reported as loose, and the reported figures are consistent with each other.

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_harness::{compare, Case, NoObserver, Observer, SampleRecord};

fn case(m: f64, h: f64) -> Case {
    Case {
        a: 1.0,
        b: 0.5,
        m,
        h,
        torus: 0,
        phase1: 0.4,
        phase2: 1.3,
        t_end: 20.0,
        samples: 41,
    }
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
        assert!(tight.steps > 0 && tight.rhs_evals > tight.steps);
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
    c.t_end = f64::NAN;
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
