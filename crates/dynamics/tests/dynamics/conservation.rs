//! The right-hand side conserves H, K, G and the geometric constraints: their derivative along the
//! vector field, computed exactly by forward-mode differentiation (dual numbers, dI/dt = ∇I·f),
//! vanishes to round-off at random states. A table with one sign flipped breaks it.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_dynamics::dual::Dual;
use rsts_dynamics::equations::{Component, Linear, Param, EULER_POISSON};
use rsts_dynamics::integrals::{energy, kowalevski, third};
use rsts_dynamics::state::DIM;
use rsts_dynamics::{Fields, State, VectorField};

/// A random state on the constraint manifold (α, β orthonormal) with |ω| ≲ 2.
fn random_state(rng: &mut ChaCha8Rng) -> State<f64> {
    let mut v = || -> [f64; 3] {
        [
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        ]
    };
    let omega = v().map(|x| 2.0 * x);
    let a = v();
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let alpha = a.map(|x| x / n);
    let c = v();
    let d = c[0] * alpha[0] + c[1] * alpha[1] + c[2] * alpha[2];
    let c = [
        c[0] - d * alpha[0],
        c[1] - d * alpha[1],
        c[2] - d * alpha[2],
    ];
    let n = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let beta = c.map(|x| x / n);
    State { omega, alpha, beta }
}

/// Derivatives along `field` of H, K, G, |α|², |β|², α·β at `s`.
fn lie_derivatives(fields: &Fields<f64>, field: &VectorField<f64>, s: &State<f64>) -> [f64; 6] {
    let x = s.to_array();
    let f = field.eval(&x);
    let xd: [Dual<f64>; DIM] = std::array::from_fn(|i| Dual::new(x[i], f[i]));
    let sd = State::from_slice(&xd);
    let fd = Fields {
        a: Dual::constant(fields.a),
        b: Dual::constant(fields.b),
    };
    let [c1, c2, c3] = sd.constraint_residuals();
    [
        energy(&fd, &sd).eps,
        kowalevski(&fd, &sd).eps,
        third(&fd, &sd).eps,
        c1.eps,
        c2.eps,
        c3.eps,
    ]
}

#[test]
fn integrals_and_constraints_are_conserved_by_the_vector_field() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..200 {
        let a = rng.gen_range(0.1..3.0);
        let b = rng.gen_range(0.0..=a);
        let fields = Fields::new(a, b).unwrap();
        let field = VectorField::new(&fields);
        let s = random_state(&mut rng);
        for (name, d) in ["H", "K", "G", "|alpha|^2", "|beta|^2", "alpha.beta"]
            .iter()
            .zip(lie_derivatives(&fields, &field, &s))
        {
            assert!(
                d.abs() < 1e-12 * (1.0 + a * a) * (1.0 + a * a),
                "d{name}/dt = {d:e} at a={a}, b={b}, {s:?}"
            );
        }
    }
}

#[test]
fn a_flipped_sign_in_the_equations_breaks_conservation() {
    // Flip the sign of the a-term in ω̇₂ (−½aα₃ → +½aα₃): H is no longer conserved.
    let mut broken = EULER_POISSON;
    broken[1] = Component {
        quadratic: EULER_POISSON[1].quadratic,
        linear: &[Linear {
            c: 0.5,
            param: Param::A,
            i: 5,
        }],
    };
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let fields = Fields::new(1.0, 0.5).unwrap();
    let field = VectorField::from_table(&fields, &broken);
    let s = random_state(&mut rng);
    let d = lie_derivatives(&fields, &field, &s);
    assert!(d[0].abs() > 1e-3, "dH/dt = {:e} should not vanish", d[0]);
    // And the intact table conserves H at the same state.
    let d_ok = lie_derivatives(&fields, &VectorField::new(&fields), &s);
    assert!(d_ok[0].abs() < 1e-13);
}

#[test]
fn jacobian_matches_forward_differentiation() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let fields = Fields::new(1.3, 0.4).unwrap();
    let field = VectorField::new(&fields);
    let x = random_state(&mut rng).to_array();
    let jac = field.jacobian(&x);
    let fd = Fields {
        a: Dual::constant(fields.a),
        b: Dual::constant(fields.b),
    };
    let dfield = VectorField::new(&fd);
    for i in 0..DIM {
        let xd: [Dual<f64>; DIM] =
            std::array::from_fn(|k| Dual::new(x[k], if k == i { 1.0 } else { 0.0 }));
        let col = dfield.eval(&xd);
        for (k, (c, row)) in col.iter().zip(&jac).enumerate() {
            assert!((c.eps - row[i]).abs() < 1e-14, "J[{k}][{i}]");
        }
    }
}
