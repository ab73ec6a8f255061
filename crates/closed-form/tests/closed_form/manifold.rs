//! The facts about N that issue 11 hands over, each checked at 50 digits before use: the invariant
//! relations F₁ = ρ² Im Q, F₂ = ρ² f₂ and the partial integral M vanish (equal m) on closed-form
//! states in every camera, torus and sign of the radicals, and are of order one off N;
//! dQ/dt = i f₂ Q along the Euler–Poisson field at random states; the regular distance d(x) = |X_Φ|
//! vanishes on N, is of the order of a perturbation off it, stays regular where s₁ passes
//! through infinity (where F₁, F₂ go blind) and commutes with the flow ([X_H, X_Φ] = 0); the
//! normal type λ² = −4r⁴mℓ² of the field of K − 2mL.

use crate::common;
use common::*;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::manifold::distance::{
    field_of, gradient, hamiltonian_field, stretches, Energy, PhaseFunction, Phi,
};
use rsts_closed_form::manifold::normal::linearisation;
use rsts_closed_form::manifold::{distance, m_of_integrals, normal_type, NormalType, Relations};
use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};
use rsts_dynamics::dual::Dual;
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::cross;
use rsts_dynamics::{Fields, Real, State, VectorField};
use rug::Float;

const DIGITS: u32 = 50;

fn bits() -> u32 {
    bits_for_digits(DIGITS)
}

fn state_of(e: &ExplicitState<Float>) -> State<Float> {
    State {
        omega: e.omega.clone(),
        alpha: e.alpha.clone(),
        beta: e.beta.clone(),
    }
}

fn fields_of(m: &ExplicitMotion<Float>) -> Fields<Float> {
    Fields {
        a: m.constants.a.clone(),
        b: m.constants.b.clone(),
    }
}

/// A random state: ω in [−1, 1]³, (α, β) a random rotation of (e₁, e₂).
fn random_state(rng: &mut ChaCha8Rng, bits: u32) -> State<Float> {
    let f = |x: f64| Float::with_val(bits, x);
    let omega = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0)));
    let v: [Float; 3] = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0)));
    let norm = |u: &[Float; 3]| {
        (u[0].clone().square() + u[1].clone().square() + u[2].clone().square()).sqrt()
    };
    let n = norm(&v);
    let alpha: [Float; 3] = std::array::from_fn(|i| v[i].clone() / &n);
    let w: [Float; 3] = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0)));
    let c = cross(&alpha, &w);
    let nc = norm(&c);
    let beta = std::array::from_fn(|i| c[i].clone() / &nc);
    State { omega, alpha, beta }
}

/// The state moved by `eps` along a random direction tangent to the constraints (ω + δω, and
/// α, β rotated by a small angle), with the relative size of the move.
fn perturbed(rng: &mut ChaCha8Rng, s: &State<Float>, eps: f64) -> (State<Float>, f64) {
    let bits = s.omega[0].prec();
    let f = |x: f64| Float::with_val(bits, x);
    let dw: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0) * eps);
    let th: [Float; 3] = std::array::from_fn(|_| f(rng.gen_range(-1.0..1.0) * eps));
    // Rotation by the vector th (exact orthogonal matrix via Rodrigues to keep the constraints).
    let angle = (th[0].clone().square() + th[1].clone().square() + th[2].clone().square()).sqrt();
    let axis: [Float; 3] = std::array::from_fn(|i| th[i].clone() / &angle);
    let (sn, cs) = (angle.clone().sin(), angle.clone().cos());
    let rot = |v: &[Float; 3]| -> [Float; 3] {
        let kxv = cross(&axis, v);
        let kv = axis[0].clone() * &v[0] + axis[1].clone() * &v[1] + axis[2].clone() * &v[2];
        std::array::from_fn(|i| {
            v[i].clone() * &cs + kxv[i].clone() * &sn + axis[i].clone() * &kv * (f(1.0) - &cs)
        })
    };
    let moved = State {
        omega: std::array::from_fn(|i| s.omega[i].clone() + f(dw[i])),
        alpha: rot(&s.alpha),
        beta: rot(&s.beta),
    };
    let da: Vec<f64> = (0..3)
        .flat_map(|i| {
            [
                (moved.alpha[i].clone() - &s.alpha[i]).to_f64(),
                (moved.beta[i].clone() - &s.beta[i]).to_f64(),
            ]
        })
        .collect();
    let size =
        (dw.iter().map(|x| x * x).sum::<f64>() + da.iter().map(|x| x * x).sum::<f64>()).sqrt();
    (moved, size)
}

/// The points where the relations are checked: every camera (a = 1, b = 0.5) and four points of
/// a = 2, b = 0.3 on both sides of m = 0.
fn all_points() -> Vec<(&'static str, &'static str, String, String)> {
    let mut out: Vec<_> = CAMERA_POINTS
        .iter()
        .map(|(_, m, h)| ("1", "0.5", m.to_string(), h.to_string()))
        .collect();
    for (m, h) in [
        ("0.1", "-0.7"),
        ("-0.05", "0.45"),
        ("0.1", "0.45"),
        ("-0.4054", "2.2731"),
    ] {
        out.push(("2", "0.3", m.to_string(), h.to_string()));
    }
    out
}

/// Angles that put each of sn, cn (period 4K) or sn·cn (period 2K) of both variables in every
/// quadrant: every sign of every radical that changes sign on the torus.
const ANGLES: [f64; 4] = [0.4, 2.0, 3.5, 5.3];

#[test]
fn the_relations_vanish_on_n_in_every_camera_torus_and_sign_of_the_radicals() {
    let bits = bits();
    for (a, b, m, h) in all_points() {
        let probe = motion_mp(a, b, &m, &h, DIGITS, TorusChoice::default());
        for torus in 0..probe.tori {
            let motion = motion_mp(
                a,
                b,
                &m,
                &h,
                DIGITS,
                TorusChoice {
                    torus,
                    phase1: 0.0,
                    phase2: 0.0,
                },
            );
            let fields = fields_of(&motion);
            let c = &motion.constants;
            let mut signs = std::collections::HashSet::new();
            for p1 in ANGLES {
                for p2 in ANGLES {
                    let e = motion.at_angles(&mp(p1, bits), &mp(p2, bits));
                    let k = &e.coords;
                    signs.insert([&k.f1, &k.g1, &k.f2, &k.g2].map(|x| x.is_sign_positive()));
                    let s = state_of(&e);
                    let r = Relations::at(&fields, &s);
                    let [_, im_q] = r.q();
                    let what = format!(
                        "{a},{b},({m},{h}) {} torus {torus} ψ=({p1},{p2})",
                        motion.camera
                    );
                    for (name, v) in [
                        ("F1", r.big_f1.clone()),
                        ("F2", r.big_f2.clone()),
                        ("Im Q", im_q),
                        ("f2", r.f2()),
                        ("M - m", r.partial_integral(&fields) - &c.m),
                        ("(2G - p²H)/r⁴ - m", m_of_integrals(&fields, &s) - &c.m),
                        ("d", distance(&fields, &s).field),
                    ] {
                        assert!(
                            v.to_f64().abs() <= 1e-45,
                            "{what}: {name} = {:e}",
                            v.to_f64()
                        );
                    }
                }
            }
            // Each radical that changes sign on the torus took both signs; the constant ones one.
            let free = [motion.first.free_sign, motion.second.free_sign]
                .iter()
                .filter(|x| **x)
                .count();
            assert_eq!(
                signs.len(),
                1 << (4 - free),
                "{m},{h} torus {torus}: {signs:?}"
            );
        }
    }
}

#[test]
fn the_relations_are_of_order_one_off_n() {
    let bits = bits();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let fields = Fields {
        a: mp(1.0, bits),
        b: mp(0.5, bits),
    };
    let mut small = 0;
    let mut dist = Vec::new();
    for _ in 0..200 {
        let s = random_state(&mut rng, bits);
        let r = Relations::at(&fields, &s);
        let d = distance(&fields, &s).relative.to_f64();
        dist.push(d);
        if r.big_f1.to_f64().abs().max(r.big_f2.to_f64().abs()) < 1e-3 || d < 1e-3 {
            small += 1;
        }
    }
    dist.sort_by(f64::total_cmp);
    assert!(small <= 6, "{small} of 200 random states look on N");
    assert!(
        dist[100] > 0.05 && dist[100] < 50.0,
        "median d = {}",
        dist[100]
    );
}

#[test]
fn the_distance_is_of_the_order_of_a_perturbation_off_n() {
    let bits = bits();
    for (label, m, h) in CAMERA_POINTS {
        let motion = motion_mp(
            "1",
            "0.5",
            &m.to_string(),
            &h.to_string(),
            DIGITS,
            TorusChoice::default(),
        );
        let fields = fields_of(&motion);
        let s = state_of(&motion.at(&mp(1.7, bits)));
        // Six random directions, each at 1e-8 and 1e-20: d/|δ| is the same at both sizes
        // (linear in δ), at most 1 (the gain is the largest stretch of X_Φ), and near 1 for some
        // direction (a random direction has a random share normal to N; along N, d stays 0).
        let mut best = 0.0f64;
        for dir in 0..6u64 {
            let ratio = |eps: f64| {
                let mut r = ChaCha8Rng::seed_from_u64(100 + dir);
                let (p, size) = perturbed(&mut r, &s, eps);
                distance(&fields, &p).distance.to_f64() / size
            };
            let (r8, r20) = (ratio(1e-8), ratio(1e-20));
            assert!(
                (r8 / r20 - 1.0).abs() < 1e-5,
                "{label}: d/|δ| = {r8} at 1e-8, {r20} at 1e-20"
            );
            assert!(r20 > 1e-4 && r20 <= 1.0 + 1e-9, "{label}: d/|δ| = {r20}");
            best = best.max(r20);
        }
        assert!(best > 0.3, "{label}: d/|δ| at most {best}");
    }
}

#[test]
fn x_phi_stretches_exactly_two_normal_directions_and_one_goes_weak_as_m_goes_to_0() {
    // The derivative of X_Φ along the six directions of the constraint surface has rank 2 on N
    // (the normal space of N there); the weaker of the two stretches vanishes with m (the normal
    // pair ±λ, λ² = −4r⁴mℓ², degenerates at m = 0): d is of the order of a perturbation off N,
    // but in that direction with a constant that goes to 0 with m.
    let bits = bits();
    let ratio = |m: &str, h: &str| {
        let motion = motion_mp("1", "0.5", m, h, DIGITS, TorusChoice::default());
        let s = state_of(&motion.at(&mp(1.7, bits))).map(|x| x.to_f64());
        let fields = Fields { a: 1.0, b: 0.5 };
        let st = stretches(&fields, &s);
        for k in 2..6 {
            assert!(st[k] < 1e-12 * st[0], "({m}, {h}): stretches {st:?}");
        }
        st[1] / st[0]
    };
    for (label, m, h) in CAMERA_POINTS {
        let r = ratio(&m.to_string(), &h.to_string());
        assert!(r > 0.02, "{label}: σ2/σ1 = {r}");
    }
    let (r3, r4) = (ratio("0.001", "2.0706"), ratio("0.0001", "2.0706"));
    assert!(
        r3 < 0.02 && r4 < 0.2 * r3,
        "σ2/σ1 = {r3} at m = 1e-3, {r4} at m = 1e-4"
    );
}

#[test]
fn dq_dt_is_i_f2_q_at_random_states() {
    let bits = bits();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (a, b) in [(1.0, 0.5), (2.0, 0.3)] {
        let fields = Fields {
            a: mp(a, bits),
            b: mp(b, bits),
        };
        let dual_fields = Fields {
            a: Dual::constant(fields.a.clone()),
            b: Dual::constant(fields.b.clone()),
        };
        for _ in 0..20 {
            let s = random_state(&mut rng, bits);
            let x = s.to_array();
            let fx = VectorField::new(&fields).eval(&x);
            let moving: [Dual<Float>; DIM] =
                std::array::from_fn(|k| Dual::new(x[k].clone(), fx[k].clone()));
            let r = Relations::at(&dual_fields, &State::from_slice(&moving));
            let [re, im] = r.q();
            let f2 = r.f2().re;
            // i f₂ Q = (−f₂ Im Q, f₂ Re Q).
            let err_re = (re.eps.clone() + f2.clone() * &im.re).abs().to_f64();
            let err_im = (im.eps.clone() - f2.clone() * &re.re).abs().to_f64();
            let size = re.eps.to_f64().abs() + im.eps.to_f64().abs();
            assert!(size > 1e-3, "dQ/dt is not exercised ({size})");
            assert!(
                err_re < 1e-44 && err_im < 1e-44,
                "dQ/dt − i f2 Q = ({err_re:e}, {err_im:e})"
            );
            // A wrong rate (ω₃ instead of f₂) fails.
            let w3 = s.omega[2].clone();
            let wrong = (im.eps.clone() - w3 * &re.re).abs().to_f64();
            assert!(wrong > 1e-6, "the identity check cannot fail: {wrong:e}");
            // |Q|² = K.
            let k = rsts_dynamics::integrals(&fields, &s).k;
            let q2 = re.re.clone().square() + im.re.clone().square();
            assert!((q2 - k).abs().to_f64() < 1e-44);
        }
    }
}

#[test]
fn the_field_of_h_is_the_euler_poisson_field_and_commutes_with_the_field_of_phi() {
    let bits = bits();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let fields = Fields {
        a: mp(1.0, bits),
        b: mp(0.5, bits),
    };
    let dual_fields = Fields {
        a: Dual::constant(fields.a.clone()),
        b: Dual::constant(fields.b.clone()),
    };
    for _ in 0..5 {
        let s = random_state(&mut rng, bits);
        let x = s.to_array();
        let xh = hamiltonian_field(&s, &gradient(&Energy, &fields, &s));
        let ep = VectorField::new(&fields).eval(&x);
        for k in 0..DIM {
            assert!(
                (xh[k].clone() - &ep[k]).abs().to_f64() < 1e-45,
                "X_H ≠ Euler–Poisson at {k}"
            );
        }
        // [X_H, X_Φ] = D X_Φ·X_H − D X_H·X_Φ = 0: d(x) is carried by the flow like a tangent
        // vector (Φ is an integral).
        let xphi = field_of(&Phi, &fields, &s);
        let along = |v: &[Float; DIM]| -> State<Dual<Float>> {
            let d: [Dual<Float>; DIM] =
                std::array::from_fn(|k| Dual::new(x[k].clone(), v[k].clone()));
            State::from_slice(&d)
        };
        let dphi_xh = field_of(&Phi, &dual_fields, &along(&xh));
        let dh_xphi = VectorField::new(&dual_fields).eval(&along(&xphi).to_array());
        let scale = xphi.iter().map(|c| c.to_f64().abs()).fold(0.0, f64::max);
        assert!(scale > 1e-3);
        for k in 0..DIM {
            let bracket = (dphi_xh[k].eps.clone() - &dh_xphi[k].eps).abs().to_f64();
            assert!(bracket < 1e-43 * scale, "[X_H, X_Φ]_{k} = {bracket:e}");
        }
        // A function that is not an integral (ω₃²) has a field that does not commute: the
        // check can fail.
        let w3 = field_of(&Omega3Squared, &fields, &s);
        let d_w3 = field_of(&Omega3Squared, &dual_fields, &along(&xh));
        let dh_w3 = VectorField::new(&dual_fields).eval(&along(&w3).to_array());
        let off = (0..DIM)
            .map(|k| (d_w3[k].eps.clone() - &dh_w3[k].eps).abs().to_f64())
            .fold(0.0, f64::max);
        assert!(off > 1e-3, "[X_H, X_ω3²] = {off:e}");
    }
}

struct Omega3Squared;
impl PhaseFunction for Omega3Squared {
    fn eval<S: Real>(&self, _: &Fields<S>, s: &State<S>) -> S {
        s.omega[2].square()
    }
}

#[test]
fn the_distance_stays_regular_where_s1_passes_through_infinity() {
    // Camera V: x = 1/s₁ oscillates on [1/θ₂ (<0), 1/a] through 0. Find ψ₁ with x = 0 to 50
    // digits by bisection, then perturb by 1e-20: d responds like the perturbation, F₁ and F₂
    // (which carry the factor ρ² → 0 there) do not see it, and Im Q, f₂ are 0/0.
    let bits = bits();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for (m, h) in [
        ("-0.7092", "1.5643"),
        ("-1.9244", "0.4503"),
        ("-2.9877", "3.2858"),
    ] {
        let motion = motion_mp("1", "0.5", m, h, DIGITS, TorusChoice::default());
        let fields = fields_of(&motion);
        let x_at = |p: &Float| motion.at_angles(p, &mp(1.0, bits)).coords.x;
        // x goes from λ < 0 at ψ₁ = 0 to μ > 0 at a quarter (period 4K) or half (2K) turn.
        let turn = if motion.first.free_sign { 1.0 } else { 0.5 };
        let (mut lo, mut hi) = (mp(0.0, bits), mp(std::f64::consts::PI * turn, bits));
        assert!(
            x_at(&lo) < 0 && x_at(&hi) > 0,
            "x does not cross 0 at ({m}, {h})"
        );
        for _ in 0..200 {
            let mid = (lo.clone() + &hi) / mp(2.0, bits);
            if x_at(&mid) < 0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let e = motion.at_angles(&lo, &mp(1.0, bits));
        assert!(e.coords.x.to_f64().abs() < 1e-45);
        let s = state_of(&e);
        let r0 = Relations::at(&fields, &s);
        assert!(r0.rho2.to_f64() < 1e-85, "ρ² = {:e}", r0.rho2.to_f64());
        assert!(distance(&fields, &s).field.to_f64() < 1e-45);
        for _ in 0..4 {
            let (p, size) = perturbed(&mut rng, &s, 1e-20);
            let d = distance(&fields, &p).distance.to_f64();
            assert!(
                d > 1e-3 * size && d <= size * (1.0 + 1e-9),
                "({m}, {h}): d = {d:e} for |δ| = {size:e}"
            );
            let r = Relations::at(&fields, &p);
            let [_, im_q] = r.q();
            // F₁ = ρ² Im Q goes blind (O(δ²): ρ = O(δ) here) and the quotients Im Q, f₂ are
            // far from 0 although the state is within 1e-20 of N (f₂ = F₂/ρ² ~ 1/δ).
            assert!(
                r.big_f1.to_f64().abs() < 1e-6 * size,
                "F1 = {:e}",
                r.big_f1.to_f64()
            );
            assert!(im_q.to_f64().abs().max(r.f2().to_f64().abs()) > 1e-2);
        }
        // … while away from x = 0 the same perturbation is seen by F₁, F₂ at order δ.
        let s_far = state_of(&motion.at_angles(&mp(2.0, bits), &mp(1.0, bits)));
        let mut seen = 0.0f64;
        for _ in 0..4 {
            let (p, size) = perturbed(&mut rng, &s_far, 1e-20);
            let r = Relations::at(&fields, &p);
            seen = seen.max(r.big_f1.to_f64().abs().max(r.big_f2.to_f64().abs()) / size);
        }
        assert!(seen > 1e-3, "F1, F2 blind away from x = 0 too: {seen}");
    }
}

#[test]
fn the_normal_type_is_lambda2_equal_minus_4_r4_m_ell2() {
    let bits = bits();
    for (a, b, m, h) in all_points() {
        let motion = motion_mp(a, b, &m, &h, DIGITS, TorusChoice::default());
        let fields = fields_of(&motion);
        let c = &motion.constants;
        let normal = normal_type(c);
        let lambda2 = normal.lambda2.clone();
        let expected = if c.m.is_sign_negative() {
            NormalType::Hyperbolic
        } else {
            NormalType::Elliptic
        };
        assert_eq!(normal.kind, expected);
        for (p1, p2) in [(0.4, 2.0), (3.5, 5.3)] {
            let s = state_of(&motion.at_angles(&mp(p1, bits), &mp(p2, bits)));
            let j = linearisation(&fields, &s, &c.m);
            let mul = |x: &[[Float; DIM]; DIM], y: &[[Float; DIM]; DIM]| -> [[Float; DIM]; DIM] {
                std::array::from_fn(|i| {
                    std::array::from_fn(|k| {
                        (0..DIM).fold(mp(0.0, bits), |acc, l| acc + x[i][l].clone() * &y[l][k])
                    })
                })
            };
            let what = format!("{a},{b},({m},{h})");
            let scale = lambda2.to_f64().abs();
            assert!(scale > 1e-6, "{what}: λ² = {scale}");
            // The power sums tr Jᵏ, k = 1..9, determine the nine eigenvalues (Newton's
            // identities): tr Jᵏ = 2λᵏ for even k and 0 for odd k means eigenvalues ±λ and seven
            // zeros (J is not diagonalisable: its zero eigenvalue has Jordan blocks, the field of
            // K − 2mL vanishing on the level m of N only).
            let trace =
                |x: &[[Float; DIM]; DIM]| (0..DIM).fold(mp(0.0, bits), |acc, i| acc + &x[i][i]);
            let size = j
                .iter()
                .flatten()
                .map(|x| x.to_f64().abs())
                .fold(0.0, f64::max);
            let mut power = j.clone();
            for k in 1..=9 {
                let expected = if k % 2 == 0 {
                    (0..k / 2).fold(mp(2.0, bits), |acc, _| acc * &lambda2)
                } else {
                    mp(0.0, bits)
                };
                let err = (trace(&power) - expected).abs().to_f64();
                let tol = 1e-44 * (DIM as f64 * size).powi(k);
                assert!(
                    err < tol,
                    "{what}: tr J^{k} off by {err:e} (tolerance {tol:e})"
                );
                power = mul(&power, &j);
            }
            let j2 = mul(&j, &j);
            // A wrong m in K − 2mL moves the pair: the check can fail.
            let j_wrong = linearisation(&fields, &s, &(c.m.clone() * mp(1.01, bits)));
            let t2w = (trace(&mul(&j_wrong, &j_wrong)) / mp(2.0, bits) - &lambda2)
                .abs()
                .to_f64();
            let t2 = (trace(&j2) / mp(2.0, bits) - &lambda2).abs().to_f64();
            assert!(t2 < 1e-40 * scale);
            assert!(t2w > 1e-6 * scale, "{what}: a wrong m passes ({t2w:e})");
        }
    }
}
