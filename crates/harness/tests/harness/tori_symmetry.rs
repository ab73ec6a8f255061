//! The tori of one (m, h) are mirror images under sign changes that are symmetries of the
//! equations (rsts_closed_form::motion::symmetry): a built-in integrator, whose every operation
//! commutes with a sign change (round-to-nearest is symmetric), makes the mirrored errors on
//! every torus — the same report to the last bit, which is why validation/nightly.toml keeps
//! one torus per (m, h).

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_harness::{compare, Case, NoObserver, Report};

fn run(m: f64, h: f64, torus: usize, phase1: f64, method: MethodName, tol: f64) -> Report {
    let case = Case::binary([1.0, 0.5, m, h], torus, [phase1, 2.1], 20.0, 41).unwrap();
    let config = MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap();
    let mut r = compare(&case, &config, &mut NoObserver).unwrap();
    // The only figure that is not the motion's: the clock.
    r.integration_seconds = None;
    r
}

#[test]
fn an_integrator_makes_the_same_errors_on_every_torus_of_a_point() {
    let methods = [
        (MethodName::Dop853, 1e-10),
        (MethodName::Dopri5, 1e-8),
        (MethodName::Rk4, 1e-6),
        (MethodName::TaylorF64, 1e-12),
        (MethodName::TaylorDd, 1e-20),
    ];
    // II+ (2 tori, the mirror of s₂), V and VI (4 tori: both mirrors and their product).
    for (m, h, tori) in [(0.05, 1.058, 2), (-0.7092, 1.5643, 4), (-2.9877, 3.2858, 4)] {
        for (method, tol) in methods {
            let first = run(m, h, 0, 0.7, method, tol);
            assert!(
                first.max_state_error > 0.0 && first.drift.h > 0.0,
                "{first:?}"
            );
            for torus in 1..tori {
                let copy = run(m, h, torus, 0.7, method, tol);
                assert_eq!(copy, first, "m = {m}, h = {h}, {method:?}, torus {torus}");
            }
            // Not a figure that ignores the motion: another start on the same torus differs.
            let moved = run(m, h, 1, 0.7 + 1e-3, method, tol);
            assert_ne!(moved.max_state_error, first.max_state_error, "{method:?}");
        }
    }
}
