//! The tori of one (m, h) are mirror images (src/motion/symmetry.rs): S_x and S_s2 are
//! symmetries of the equations (exactly, term by term, also in f64), and in every camera the
//! state of torus k is the torus-0 state with the signs of `torus_image_signs`, at the same
//! angles and times, to the working precision (40 digits).

use crate::common;
use common::{motion_mp, phase_vec, CAMERA_POINTS};

use rsts_closed_form::motion::symmetry::{MIRROR_S2, MIRROR_X};
use rsts_closed_form::TorusChoice;
use rsts_dynamics::{Fields, VectorField};
use rug::Float;

fn apply(signs: &[i8; 9], x: &[f64; 9]) -> [f64; 9] {
    std::array::from_fn(|k| f64::from(signs[k]) * x[k])
}

/// f(Sx) = S f(x) bit for bit at states of no special kind, for both mirrors and their product;
/// a sign pattern that is not a symmetry (ω₁ alone) fails it.
#[test]
fn the_mirrors_are_symmetries_of_the_equations() {
    let field = VectorField::new(&Fields::new(1.0, 0.5).unwrap());
    let both: [i8; 9] = std::array::from_fn(|k| MIRROR_X[k] * MIRROR_S2[k]);
    let mut only_w1 = [1i8; 9];
    only_w1[0] = -1;
    let states = [
        [0.3, -0.7, 1.1, 0.6, -0.48, 0.64, 0.8, 0.36, -0.48],
        [-1.2, 0.05, -0.4, 0.0, 0.6, -0.8, 1.0, 0.0, 0.0],
    ];
    let equivariant =
        |s: &[i8; 9], x: &[f64; 9]| field.eval(&apply(s, x)) == apply(s, &field.eval(x));
    for x in &states {
        for s in [&MIRROR_X, &MIRROR_S2, &both] {
            assert!(equivariant(s, x), "{s:?} at {x:?}");
        }
        assert!(!equivariant(&only_w1, x), "ω₁ alone at {x:?}");
    }
}

/// Every camera, every torus, three times and phases (0.7, 2.1): torus k is torus 0 mirrored,
/// to 1e-30 at 40 digits; and the signs are not all + beyond torus 0 (the copies are distinct).
#[test]
fn every_torus_is_torus_0_mirrored() {
    let mut copies = 0;
    for (label, m, h) in CAMERA_POINTS {
        let choice = |torus| TorusChoice {
            torus,
            phase1: 0.7,
            phase2: 2.1,
        };
        let (m, h) = (m.to_string(), h.to_string());
        let zero = motion_mp("1", "0.5", &m, &h, 40, choice(0));
        assert_eq!(zero.torus_image_signs(), [1; 9]);
        for torus in 1..zero.tori {
            let k = motion_mp("1", "0.5", &m, &h, 40, choice(torus));
            let signs = k.torus_image_signs();
            assert_ne!(signs, [1; 9], "{label} torus {torus}");
            for t in [0.0, 1.3, 7.9] {
                let t = Float::with_val(zero.constants.a.prec(), t);
                let (x0, xk) = (phase_vec(&zero.at(&t)), phase_vec(&k.at(&t)));
                for i in 0..9 {
                    let mirrored = Float::with_val(200, &x0[i] * i32::from(signs[i]));
                    let d = Float::with_val(200, &xk[i] - &mirrored);
                    assert!(
                        d.clone().abs() < 1e-30,
                        "{label} torus {torus} t = {t} component {i}: {d}"
                    );
                }
            }
            copies += 1;
        }
    }
    // II±, III: 2 tori; IV±, V, VI: 4.
    assert_eq!(copies, 3 + 4 * 3);
}
