//! The written-out gradients of H, K, G and Φ (manifold::phi_field, stop 28) against the jet
//! gradients of the one definition of the integrals (rsts_dynamics::integrals) at random states
//! off N, in f64 (to a few ulps of the size of the terms) and at 200 bits (to 1e-50); the
//! written-out derivative of X_Φ (manifold::field_derivative) against its jet derivative; and the
//! gain from the Gram matrix against the largest singular value of the SVD.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::manifold::distance::{
    constraint_columns, gain, gradient, gram, stretches, Energy, Kowalevski, PhaseFunction, Phi,
};
use rsts_closed_form::manifold::field_derivative::{phi_field_derivative, PhiFieldDerivative};
use rsts_closed_form::manifold::phi_field::{
    integral_gradients, phi_field_derivative_jet, phi_gradient,
};
use rsts_dynamics::integrals::third;
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::cross;
use rsts_dynamics::{Fields, Real, State};
use rug::Float;

/// G (the jet differentiates its definition).
struct Third;
impl PhaseFunction for Third {
    fn eval<S: Real>(&self, fields: &Fields<S>, s: &State<S>) -> S {
        third(fields, s)
    }
}

/// A random state at `bits` bits: ω in [−1.5, 1.5]³, (α, β) orthonormal; fields a > b > 0.
fn random<T: Real>(rng: &mut ChaCha8Rng, bits: u32) -> (Fields<T>, State<T>) {
    let f = |x: f64| T::from_f64(x, bits);
    let a = rng.gen_range(0.5..2.0);
    let b = a * rng.gen_range(0.05..0.95);
    let omega = std::array::from_fn(|_| f(rng.gen_range(-1.5..1.5)));
    let norm = |u: &[T; 3]| (u[0].square() + u[1].square() + u[2].square()).sqrt();
    let v: [T; 3] = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0)));
    let n = norm(&v);
    let alpha: [T; 3] = std::array::from_fn(|i| v[i].clone() / &n);
    let w: [T; 3] = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0)));
    let c = cross(&alpha, &w);
    let nc = norm(&c);
    let beta: [T; 3] = std::array::from_fn(|i| c[i].clone() / &nc);
    (Fields { a: f(a), b: f(b) }, State { omega, alpha, beta })
}

/// max over components of |x − y| / scale.
fn worst<T: Real>(x: &[T; DIM], y: &[T; DIM], scale: f64) -> f64 {
    (0..DIM)
        .map(|k| (x[k].clone() - &y[k]).abs().to_f64() / scale)
        .fold(0.0, f64::max)
}

fn size<T: Real>(x: &[T; DIM]) -> f64 {
    x.iter().map(|c| c.abs().to_f64()).fold(0.0, f64::max)
}

/// Largest relative difference of ∇H, ∇K, ∇G and ∇Φ (hand against jet) over `n` random states;
/// each relative to the size of its terms (for Φ: r⁴|∇K| + 2|L|(2|∇G| + p²|∇H|)).
fn largest_gaps<T: Real>(bits: u32, n: usize) -> [f64; 4] {
    let mut rng = ChaCha8Rng::seed_from_u64(28);
    let mut gaps = [0.0f64; 4];
    for _ in 0..n {
        let (fields, s) = random::<T>(&mut rng, bits);
        let hand = integral_gradients(&fields, &s);
        let jet_h = gradient(&Energy, &fields, &s);
        let jet_k = gradient(&Kowalevski, &fields, &s);
        let jet_g = gradient(&Third, &fields, &s);
        let (sh, sk, sg) = (size(&jet_h), size(&jet_k), size(&jet_g));
        let i = rsts_dynamics::integrals::integrals(&fields, &s);
        let (p2, r4) = (fields.p2().to_f64(), fields.r2().square().to_f64());
        let l = 2.0 * i.g.to_f64() - p2 * i.h.to_f64();
        let sphi = r4 * sk + 2.0 * l.abs() * (2.0 * sg + p2 * sh);
        let phi = phi_gradient(&fields, &s);
        let jet_phi = gradient(&Phi, &fields, &s);
        let now = [
            worst(&hand.h, &jet_h, sh),
            worst(&hand.k, &jet_k, sk),
            worst(&hand.g, &jet_g, sg),
            worst(&phi, &jet_phi, sphi),
        ];
        for (g, x) in gaps.iter_mut().zip(now) {
            *g = g.max(x);
        }
    }
    gaps
}

#[test]
fn written_out_gradients_equal_the_jet_gradients_of_the_integrals_in_f64() {
    let gaps = largest_gaps::<f64>(53, 2000);
    eprintln!("f64: {gaps:?}");
    let ok = gaps.iter().all(|g| *g < 16.0 * f64::EPSILON);
    assert!(ok, "∇H, ∇K, ∇G, ∇Φ: {gaps:?} of their terms");
}

#[test]
fn written_out_gradients_equal_the_jet_gradients_of_the_integrals_at_200_bits() {
    let gaps = largest_gaps::<Float>(200, 200);
    let ok = gaps.iter().all(|g| *g < 1e-50);
    assert!(ok, "∇H, ∇K, ∇G, ∇Φ: {gaps:?} of their terms");
}

/// The Gram-matrix gain is the largest singular value of the SVD (to a few ulps).
#[test]
fn the_gain_is_the_largest_stretch() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut worst = 0.0f64;
    for _ in 0..2000 {
        let (fields, s) = random::<f64>(&mut rng, 53);
        let (g, sv) = (gain(&fields, &s), stretches(&fields, &s)[0]);
        assert!(sv > 0.0);
        worst = worst.max((g - sv).abs() / sv);
    }
    assert!(worst < 64.0 * f64::EPSILON, "gain vs SVD: {worst:e}");
    eprintln!("largest relative gap gain vs SVD: {worst:e}");
}

/// The written-out derivative of X_Φ (manifold::field_derivative, stop 30) against the jet
/// derivative of the written-out field along random directions of the whole phase space (every
/// term of ∇²Φ·δ moves) and along directions of δω or (δα, δβ) alone (the constraint
/// directions of the gain), to a few ulps of the largest entry.
#[test]
fn written_out_derivative_of_x_phi_equals_the_jet_derivative() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let mut worst = 0.0f64;
    for _ in 0..2000 {
        let (fields, s) = random::<f64>(&mut rng, 53);
        // Directions 0, 1: δω alone; 2, 3: (δα, δβ) alone; 4, 5: everything.
        let directions: [[f64; DIM]; 6] = std::array::from_fn(|j| {
            std::array::from_fn(|k| match (j / 2, k < 3) {
                (0, false) | (1, true) => 0.0,
                _ => rng.gen_range(-1.0..1.0),
            })
        });
        let hand = phi_field_derivative(&fields, &s, &directions);
        let jet = phi_field_derivative_jet(&fields, &s, &directions);
        let scale = jet.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..DIM {
            for j in 0..6 {
                worst = worst.max((hand[k][j] - jet[k][j]).abs() / scale);
            }
        }
    }
    eprintln!("written-out vs jet derivative of X_Φ: {worst:e} of the largest entry");
    assert!(worst < 1e-13, "{worst:e}");
}

/// The derivative of X_Φ along six directions at once (lane by lane, stop 31) is the same number
/// as along each direction alone, at random states along directions of δω or (δα, δβ) alone and
/// along any; and the gain's Gram matrix from it is the one from the columns one at a time.
#[test]
fn six_directions_at_once_are_the_numbers_of_one_at_a_time() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for case in 0..3000 {
        let (fields, s) = random::<f64>(&mut rng, 53);
        let kind = case % 3;
        let directions: [[f64; DIM]; 6] = std::array::from_fn(|_| {
            std::array::from_fn(|k| match (kind, k < 3) {
                (0, false) | (1, true) => 0.0,
                _ => rng.gen_range(-1.0..1.0),
            })
        });
        let d = PhiFieldDerivative::new(&fields, &s);
        let six = d.along_six(&directions);
        for (j, delta) in directions.iter().enumerate() {
            let one = d.along(delta);
            for k in 0..DIM {
                assert_eq!(six[k].0[j], one[k], "case {case}, direction {j}, entry {k}");
            }
        }
        let columns = constraint_columns(&fields, &s);
        let g = gram(&fields, &s);
        for p in 0..6 {
            for q in 0..=p {
                let mut sum = 0.0;
                for (x, y) in columns[p].iter().zip(&columns[q]) {
                    sum += x * y;
                }
                assert_eq!(g[p][q], sum, "case {case}, Gram entry ({p}, {q})");
            }
        }
    }
}
