use super::*;

fn case(t_end: f64, samples: usize) -> Case {
    {
        let mut c = Case::default_i_plus();
        c.t_end = rsts_closed_form::Decimal::from_f64(t_end).unwrap();
        c.samples = samples;
        c
    }
}

/// A synthetic sweep: C·h⁴·(1 + 40h²) above, a noisy floor of 1e-13 below. The window is
/// the asymptotic middle; the floor and the pre-asymptotic steps are excluded with why, and the
/// fitted slope is within 0.1 of 4. (A window that kept the floor would give a slope far
/// below 4; one that kept the large steps, far above.)
#[test]
fn the_window_leaves_out_the_floor_and_the_pre_asymptotic_steps() {
    let steps = halvings(0.5, 12);
    let noise = [
        1.3, 0.7, 1.1, 0.9, 1.2, 0.8, 1.0, 1.4, 0.6, 1.0, 1.1, 0.9, 1.2,
    ];
    let errors: Vec<f64> = steps
        .iter()
        .zip(noise)
        .map(|(&h, n)| 1e-3 * h.powi(4) * (1.0 + 40.0 * h * h) + 1e-13 * n)
        .collect();
    // Round-off expected: 1e-13 at every step (the floor's level).
    let round_off = vec![1e-13; steps.len()];
    let fit = fit_order(&steps, &errors, &round_off).unwrap();
    assert!((fit.order - 4.0).abs() < 0.1, "{fit:?}");
    assert!(fit.order_stderr < 0.1, "{fit:?}");
    let why = |h: f64| {
        fit.excluded
            .iter()
            .find(|e| e.step == h)
            .map(|e| e.why.clone())
            .unwrap_or_default()
    };
    assert!(why(0.5).starts_with("pre-asymptotic"), "{fit:?}");
    assert!(why(steps[12]).starts_with("round-off floor"), "{fit:?}");
    assert!(fit.window[0] > steps[12] && fit.window[1] < 0.5, "{fit:?}");
    // Too few points, and a sweep with no window (the error never falls).
    assert!(fit_order(&steps[..2], &errors[..2], &round_off[..2]).is_err());
    let flat = vec![1e-10; steps.len()];
    assert!(fit_order(&steps, &flat, &round_off)
        .unwrap_err()
        .contains("no asymptotic window"));
}

/// The least-squares slope and standard error of an exact line are the line's; of a known
/// set they are the textbook values (x = 0, 1, 2, 3; y = 0, 1, 1, 3: slope 0.9, stderr
/// sqrt(0.7/2/5) = 0.3742).
#[test]
fn least_squares_of_known_points() {
    let (p, s, c) = least_squares(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]);
    assert!((p - 2.0).abs() < 1e-15 && s.abs() < 1e-7 && (c - 1.0).abs() < 1e-15);
    let (p, s, _) = least_squares(&[(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 3.0)]);
    assert!((p - 0.9).abs() < 1e-12, "{p}");
    assert!((s - (0.07f64).sqrt()).abs() < 1e-12, "{s}");
}

/// The built-in methods at fixed steps come out at their orders: rk4 4, dopri5 5, dop853 8,
/// taylor-f64 at order 6 six; every sample is the end of a step.
#[test]
fn built_in_methods_have_their_orders() {
    let c = case(4.0, 5);
    for (method, order, steps, p) in [
        (MethodName::Rk4, None, halvings(0.5, 5), 4.0),
        (MethodName::Dopri5, None, halvings(0.5, 4), 5.0),
        (MethodName::Dop853, None, halvings(1.0, 3), 8.0),
        (MethodName::TaylorF64, Some(6), halvings(0.5, 4), 6.0),
    ] {
        let plan = ConvergencePlan::new(c.clone(), &steps).unwrap();
        let mut m = FixedStepMethod::new(method, order, 50).unwrap();
        let report = convergence(&plan, &mut [&mut m]).unwrap();
        let fit = &report.fits[0];
        assert!(
            (fit.order - p).abs() < 0.3,
            "{method}: {fit:?} {:?}",
            report.rows
        );
        let r = &report.rows[1];
        assert_eq!(r.steps, (4.0 / r.step).round() as u64, "{r:?}");
        assert!(r.final_error <= r.max_error);
    }
    assert!(FixedStepMethod::new(MethodName::TaylorDd, None, 50).is_err());
}

/// An integrator that ignores the step is refused, named.
#[test]
fn an_integrator_that_ignores_the_step_is_refused() {
    struct Deaf(FixedStepMethod);
    impl FixedStepIntegrator for Deaf {
        fn name(&self) -> String {
            "deaf".into()
        }
        fn working_bits(&self) -> u32 {
            53
        }
        fn integrate_at(
            &mut self,
            _step: f64,
            problem: &Problem<Float>,
            times: &[f64],
        ) -> Result<Trajectory, HarnessError> {
            self.0.integrate_at(0.01, problem, times)
        }
    }
    let plan = ConvergencePlan::new(case(2.0, 3), &halvings(0.5, 3)).unwrap();
    let mut deaf = Deaf(FixedStepMethod::new(MethodName::Rk4, None, 50).unwrap());
    let e = convergence(&plan, &mut [&mut deaf])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("deaf") && e.contains("do not change with the step"),
        "{e}"
    );
}

/// Steps are checked and made whole fractions of the sample spacing.
#[test]
fn steps_are_checked_and_fitted_to_the_grid() {
    let plan = ConvergencePlan::new(case(2.0, 3), &[0.3, 0.5, 0.2, 0.25]).unwrap();
    assert_eq!(
        plan.steps,
        vec![0.5, 0.25, 0.2],
        "0.3 becomes 1/4 of the spacing 1"
    );
    assert_eq!(
        ConvergencePlan::new(case(2.0, 3), &[0.4, 0.5, 0.2])
            .unwrap()
            .steps,
        vec![0.5, 1.0 / 3.0, 0.2]
    );
    assert!(ConvergencePlan::new(case(2.0, 3), &[2.0, 0.5, 0.25]).is_err());
    assert!(ConvergencePlan::new(case(2.0, 3), &[0.5, 0.5, 0.25]).is_err());
    assert!(ConvergencePlan::new(case(2.0, 3), &[0.5, -0.1, 0.25]).is_err());
}

/// No order for a Taylor method: refused with an order suggested (old text: "taylor-f64 at
/// fixed steps needs a fixed order (--order P)"); the default sweep is 8 halvings from
/// min(0.5, the sample spacing), and a plan of it fits rk4 at order 4.
#[test]
fn taylor_without_order_is_given_one_and_the_default_sweep_runs() {
    let e = FixedStepMethod::new(MethodName::TaylorF64, None, 50).unwrap_err();
    assert!(e.to_string().contains("try --order 8"), "{e}");
    let e = FixedStepMethod::new(MethodName::TaylorDd, None, 50).unwrap_err();
    assert!(e.to_string().contains("try --order 16"), "{e}");
    let c = case(10.0, 11);
    let steps = ConvergencePlan::default_steps(&c);
    assert_eq!(steps, halvings(0.5, 8));
    assert_eq!(
        ConvergencePlan::default_steps(&case(1.0, 11)),
        halvings(0.1, 8)
    );
    let plan = ConvergencePlan::new(c, &steps).unwrap();
    let mut m = FixedStepMethod::new(MethodName::Rk4, None, 50).unwrap();
    let report = convergence(&plan, &mut [&mut m]).unwrap();
    assert!(
        (report.fits[0].order - 4.0).abs() < 0.1,
        "{:?}",
        report.fits[0]
    );
}
