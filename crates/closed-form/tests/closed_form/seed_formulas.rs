//! Every formula of the seed (eqs. 1.3, 1.4, 2.5, 2.6–2.8, 3.1, Q′, Q″), as implemented, checked at
//! 50 digits against the Euler–Poisson equations, the constraints and the integrals, in every
//! camera, on every torus, at several times.

use crate::common;
use common::*;
use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::bits_for_digits;

#[test]
fn every_formula_holds_in_every_camera_and_torus() {
    for (label, m, h) in CAMERA_POINTS {
        let probe = motion_mp(
            "1",
            "0.5",
            &m.to_string(),
            &h.to_string(),
            50,
            TorusChoice::default(),
        );
        assert_eq!(probe.camera.label(), label, "camera of (m, h) = ({m}, {h})");
        let expected_tori = match probe.camera {
            Camera::IPlus | Camera::IMinus => 1,
            Camera::IIPlus | Camera::IIMinus | Camera::III => 2,
            _ => 4,
        };
        assert_eq!(probe.tori, expected_tori, "tori in {label}");
        for torus in 0..probe.tori {
            let choice = TorusChoice {
                torus,
                phase1: 0.7,
                phase2: 2.1,
            };
            let motion = motion_mp("1", "0.5", &m.to_string(), &h.to_string(), 50, choice);
            for t in [0.0, 0.37, 5.3] {
                assert_all_below(&motion, t, 1e-45, &format!("{label} torus {torus}"));
            }
        }
    }
}

#[test]
fn another_field_ratio_and_both_signs_of_m() {
    // a = 2, b = 0.3: points on both sides of m = 0 in cameras I and II.
    for (m, h, label) in [
        ("0.1", "-0.7", "I+"),
        ("-0.05", "0.45", "I-"),
        ("0.1", "0.45", "II+"),
        ("-0.4054", "2.2731", "II-"),
    ] {
        let motion = motion_mp(
            "2",
            "0.3",
            m,
            h,
            50,
            TorusChoice {
                torus: 0,
                phase1: 1.0,
                phase2: 4.0,
            },
        );
        assert_eq!(motion.camera.label(), label);
        assert_all_below(&motion, 1.3, 1e-45, label);
    }
}

#[test]
fn the_checks_catch_a_wrong_sign_and_a_wrong_constant() {
    // Build the state with one radical's sign flipped everywhere: the formulas then describe a
    // curve that is not a solution, and the Euler–Poisson residual must be large.
    let bits = bits_for_digits(50);
    let motion = motion_mp(
        "1",
        "0.5",
        "0.3",
        "-0.375",
        50,
        TorusChoice {
            torus: 0,
            phase1: 0.7,
            phase2: 2.1,
        },
    );
    let ok = residuals(&motion, 0.37);
    assert!(ok[0].1 < 1e-45);
    let flipped = motion.at_with_derivative(&mp(0.37, bits));
    // ω₁ ∝ F₂: flipping F₂ alone flips ω₁ but not the α, β built from F₁F₂·G₁G₂ consistently.
    let mut x = phase_vec(&flipped);
    x[0] = -x[0].clone();
    let fields = rsts_dynamics::Fields {
        a: motion.constants.a.clone(),
        b: motion.constants.b.clone(),
    };
    let re: [rug::Float; 9] = std::array::from_fn(|k| x[k].re.clone());
    let fx = rsts_dynamics::VectorField::new(&fields).eval(&re);
    let res = (0..9)
        .map(|k| (x[k].eps.clone() - &fx[k]).abs().to_f64())
        .fold(0.0, f64::max);
    assert!(
        res > 1e-3,
        "a flipped ω₁ must violate the equations, residual {res:e}"
    );
    // A wrong energy constant is caught by the H = h check.
    let wrong = ExplicitMotion::new(
        motion.constants.a.clone(),
        motion.constants.b.clone(),
        motion.constants.m.clone(),
        motion.constants.h.clone(),
        TorusChoice::default(),
    )
    .unwrap();
    let s = wrong.at(&mp(0.0, bits));
    let st = rsts_dynamics::State::from_slice(&phase_vec(&s));
    let hh = rsts_dynamics::integrals::energy(&fields, &st);
    assert!((hh.clone() - &motion.constants.h).abs().to_f64() < 1e-45);
    assert!((hh - mp(-0.375 + 1e-9, bits)).abs().to_f64() > 1e-10);
}

#[test]
fn thousand_digits() {
    // The same code at 1000 digits: every check holds far below f64's range (residuals are
    // reported as f64, so this asserts < 1e-300; 50-digit runs above assert < 1e-45).
    let motion = motion_mp(
        "1",
        "0.5",
        "-0.7092",
        "1.5643",
        1000,
        TorusChoice {
            torus: 3,
            phase1: 0.2,
            phase2: 5.0,
        },
    );
    assert_eq!(motion.camera.label(), "V");
    assert_all_below(&motion, 7.25, 1e-300, "V at 1000 digits");
}
