//! Identify a state (issue 11): closed form → identify → closed form reproduces the state, in f64
//! (1e-12) and at 50 digits (1e-40), in every camera and torus, at phases that put the radicals
//! in every sign, near each curve of Σ (1e-6) and where s₁ passes through infinity; the phases
//! found are the motion's ψ⁰ + νt; a state off N gets its distance; bad input is refused.

use crate::common;
use common::*;

use rsts_closed_form::manifold::{identify, Identified, IdentifyError};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Real, State};
use rug::Float;

fn state_of<T: Real>(e: &ExplicitState<T>) -> State<T> {
    State {
        omega: e.omega.clone(),
        alpha: e.alpha.clone(),
        beta: e.beta.clone(),
    }
}

/// |ψ − φ| modulo 2π.
fn angle_gap(x: f64, y: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let d = (x - y).rem_euclid(tau);
    d.min(tau - d)
}

fn max_gap<T: Real>(x: &State<T>, y: &State<T>) -> f64 {
    let (p, q) = (x.to_array(), y.to_array());
    (0..9)
        .map(|k| (p[k].clone() - &q[k]).abs().to_f64())
        .fold(0.0, f64::max)
}

/// Identify the closed-form state of `motion` at the angles ψ and check the round trip.
fn round_trip<T: Scalar>(
    motion: &ExplicitMotion<T>,
    psi: [T; 2],
    tol: f64,
    what: &str,
) -> Identified<T> {
    let state = state_of(&motion.at_angles(&psi[0], &psi[1]));
    let c = &motion.constants;
    let id = identify(&c.a, &c.b, &state).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(id.camera, motion.camera, "{what}");
    assert_eq!(id.torus, motion.choice.torus, "{what}: torus");
    assert_eq!(id.tori, motion.tori, "{what}");
    let scale = 1.0 + c.h.to_f64().abs() + c.m.to_f64().abs();
    assert!(
        (id.m.clone() - &c.m).abs().to_f64() <= tol * scale,
        "{what}: m"
    );
    assert!(
        (id.h.clone() - &c.h).abs().to_f64() <= tol * scale,
        "{what}: h"
    );
    assert!(
        id.distance.relative.to_f64() <= tol,
        "{what}: distance {:e}",
        id.distance.relative.to_f64()
    );
    assert!(
        id.residual.to_f64() <= tol,
        "{what}: residual {:e}",
        id.residual.to_f64()
    );
    // Forward again from what was found.
    let again = ExplicitMotion::new(
        c.a.clone(),
        c.b.clone(),
        id.m.clone(),
        id.h.clone(),
        TorusChoice {
            torus: id.torus,
            phase1: 0.0,
            phase2: 0.0,
        },
    )
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    let back = state_of(&again.at_angles(&id.phases[0], &id.phases[1]));
    let gap = max_gap(&back, &state);
    assert!(
        gap <= tol,
        "{what}: explicit → identify → explicit off by {gap:e}"
    );
    id
}

/// Angles through every quadrant of sn, cn (or sn·cn) of both variables, and the turning points.
const PHASES: [f64; 6] = [0.0, 0.4, std::f64::consts::FRAC_PI_2, 2.0, 3.5, 5.3];

fn tori_of(a: &str, b: &str, m: &str, h: &str) -> usize {
    motion_mp(a, b, m, h, 20, TorusChoice::default()).tori
}

#[test]
fn f64_round_trip_in_every_camera_torus_and_quadrant() {
    for (label, m, h) in CAMERA_POINTS {
        for torus in 0..tori_of("1", "0.5", &m.to_string(), &h.to_string()) {
            let choice = TorusChoice {
                torus,
                phase1: 0.0,
                phase2: 0.0,
            };
            let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
            for p1 in PHASES {
                for p2 in PHASES {
                    let what = format!("{label} torus {torus} ψ = ({p1}, {p2})");
                    let id = round_trip(&motion, [p1, p2], 1e-12, &what);
                    for (found, given) in id.phases.iter().zip([p1, p2]) {
                        assert!(
                            (0.0..std::f64::consts::TAU).contains(found),
                            "{what}: {found}"
                        );
                        let gap = angle_gap(*found, given);
                        assert!(gap < 1e-10, "{what}: phase {found} for {given}");
                    }
                }
            }
        }
    }
}

#[test]
fn phases_along_a_motion_are_psi0_plus_nu_t() {
    for (label, m, h) in CAMERA_POINTS {
        let choice = TorusChoice {
            torus: 0,
            phase1: 0.7,
            phase2: 2.1,
        };
        let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
        let nu = motion.frequencies();
        for t in [0.0, 0.37, 5.3, 41.0] {
            let state = state_of(&motion.at(&t));
            let id = identify(&1.0, &0.5, &state).unwrap();
            for i in 0..2 {
                let expected = [0.7, 2.1][i] + nu[i] * t;
                // Period 2K in u (a free sign): the state repeats after half a turn of the
                // parameter, which is a whole turn of ψ by the convention of TorusChoice.
                let gap = angle_gap(id.phases[i], expected);
                assert!(
                    gap < 1e-9,
                    "{label} t = {t}: ψ{} = {} expected {expected} (gap {gap:e})",
                    i + 1,
                    id.phases[i]
                );
            }
        }
    }
}

#[test]
fn fifty_digit_round_trip_in_every_camera_and_torus() {
    let bits = bits_for_digits(50);
    for (label, m, h) in CAMERA_POINTS {
        let (m, h) = (m.to_string(), h.to_string());
        for torus in 0..tori_of("1", "0.5", &m, &h) {
            let choice = TorusChoice {
                torus,
                phase1: 0.0,
                phase2: 0.0,
            };
            let motion = motion_mp("1", "0.5", &m, &h, 50, choice);
            for (p1, p2) in [(0.4, 2.0), (2.0, 5.3), (3.5, 0.4), (5.3, 3.5)] {
                let what = format!("{label} torus {torus} ψ = ({p1}, {p2}), 50 digits");
                let id = round_trip(
                    &motion,
                    [p1, p2].map(|x| Float::with_val(bits, x)),
                    1e-40,
                    &what,
                );
                for (found, given) in id.phases.iter().zip([p1, p2]) {
                    let gap = (found.clone() - Float::with_val(bits, given))
                        .abs()
                        .to_f64();
                    assert!(gap < 1e-40, "{what}: phase off by {gap:e}");
                }
            }
        }
    }
}

/// h at distance δ from a curve of Σ at m, on the admissible side (as the validation suites
/// place them).
fn near_sigma(delta: f64) -> Vec<(&'static str, f64, f64)> {
    let (a, b) = (1.0f64, 0.5f64);
    let (r2, p2) = (a * a - b * b, a * a + b * b);
    vec![
        ("outer-a", 1.0, r2 * 1.0 - 2.0 * a + delta),
        ("outer-b", 0.2, -r2 * 0.2 - 2.0 * b + delta),
        // ℓ² = 2p²m² + 2hm + 1 = δ
        ("hyperbola", -1.0, (delta - 1.0 - 2.0 * p2) / -2.0),
        ("inner-a-below", 0.3, r2 * 0.3 + 2.0 * a - delta),
        ("inner-a-above", 0.3, r2 * 0.3 + 2.0 * a + delta),
        ("inner-b-below", 0.3, -r2 * 0.3 + 2.0 * b - delta),
        ("inner-b-above", 0.3, -r2 * 0.3 + 2.0 * b + delta),
    ]
}

#[test]
fn round_trip_within_1e_6_of_sigma() {
    let bits = bits_for_digits(50);
    for (curve, m, h) in near_sigma(1e-6) {
        let probe = ExplicitMotion::new(1.0, 0.5, m, h, TorusChoice::default()).unwrap();
        for torus in 0..probe.tori {
            let choice = TorusChoice {
                torus,
                phase1: 0.0,
                phase2: 0.0,
            };
            let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
            for (p1, p2) in [(0.4, 2.0), (3.5, 5.3), (1.2, 4.4)] {
                let what = format!("{curve} ({m}, {h}) torus {torus} ψ = ({p1}, {p2})");
                round_trip(&motion, [p1, p2], 1e-12, &what);
            }
            let f = |x: f64| Float::with_val(bits, x);
            let motion = ExplicitMotion::new(f(1.0), f(0.5), f(m), f(h), choice).unwrap();
            round_trip(
                &motion,
                [f(0.4), f(2.0)],
                1e-40,
                &format!("{curve} torus {torus}, 50 digits"),
            );
        }
    }
}

/// ψ₁ at which x = 1/s₁ = `target` on the way from λ < 0 to μ > 0 (bisection).
fn psi_at_x<T: Scalar>(motion: &ExplicitMotion<T>, target: f64) -> T {
    let bits = motion.constants.a.prec();
    let t = |x: f64| T::from_f64(x, bits);
    let turn = if motion.first.free_sign { 1.0 } else { 0.5 };
    let (mut lo, mut hi) = (t(0.0), t(std::f64::consts::PI * turn));
    let x_at = |p: &T| motion.at_angles(p, &t(1.0)).coords.x;
    assert!(x_at(&lo) < t(target) && x_at(&hi) > t(target));
    for _ in 0..(bits + 8) {
        let mid = (lo.clone() + &hi) / t(2.0);
        if x_at(&mid) < t(target) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[test]
fn round_trip_where_s1_passes_through_infinity() {
    // Every camera with m < 0 and s₁ through infinity, at x = 1/s₁ = 0 (to the precision) and
    // at x = ±1e-8.
    let bits = bits_for_digits(50);
    for (label, m, h) in CAMERA_POINTS
        .iter()
        .filter(|(l, _, _)| ["I-", "II-", "III", "IV-", "V", "VI"].contains(l))
    {
        let lo = ExplicitMotion::new(1.0, 0.5, *m, *h, TorusChoice::default()).unwrap();
        let f = |x: f64| Float::with_val(bits, x);
        let hi = ExplicitMotion::new(f(1.0), f(0.5), f(*m), f(*h), TorusChoice::default()).unwrap();
        for x in [0.0, 1e-8, -1e-8] {
            let p = psi_at_x(&lo, x);
            let what = format!("{label} at x = {x:e}");
            let id = round_trip(&lo, [p, 1.0], 1e-12, &what);
            assert!(
                angle_gap(id.phases[0], p) < 1e-10,
                "{what}: ψ1 {} vs {p}",
                id.phases[0]
            );
            let p = psi_at_x(&hi, x);
            let id = round_trip(
                &hi,
                [p.clone(), f(1.0)],
                1e-40,
                &format!("{what}, 50 digits"),
            );
            assert!((id.phases[0].clone() - &p).abs().to_f64() < 1e-40);
        }
    }
}

#[test]
fn a_state_off_n_gets_its_distance_and_the_phases_of_the_nearest_point() {
    let (m, h) = (-0.7092, 1.5643);
    let motion = ExplicitMotion::new(1.0, 0.5, m, h, TorusChoice::default()).unwrap();
    let on = state_of(&motion.at_angles(&1.1, &2.3));
    for delta in [1e-9, 1e-6, 1e-4] {
        let mut off = on.clone();
        // A move off N within the constraints: ω₃ and a rotation of (α, β) about e₃.
        off.omega[2] += delta;
        let (c, s) = (delta.cos(), delta.sin());
        for v in [&mut off.alpha, &mut off.beta] {
            let (x, y) = (v[0], v[1]);
            v[0] = c * x - s * y;
            v[1] = s * x + c * y;
        }
        let id = identify(&1.0, &0.5, &off).unwrap();
        let d = id.distance.distance;
        assert!(
            d <= 2.0 * delta && d > 1e-3 * delta,
            "δ = {delta:e}: distance {d:e}"
        );
        assert!(
            id.residual <= 3.0 * delta && id.residual > 1e-3 * delta,
            "δ = {delta:e}: residual {:e}",
            id.residual
        );
        assert!(
            angle_gap(id.phases[0], 1.1) < 100.0 * delta
                && angle_gap(id.phases[1], 2.3) < 100.0 * delta
        );
    }
}

#[test]
fn bad_input_is_refused_with_the_reason() {
    let motion = ExplicitMotion::new(1.0, 0.5, 0.3, -0.375, TorusChoice::default()).unwrap();
    let state = state_of(&motion.at(&1.0));
    let input = |r: Result<Identified<f64>, IdentifyError>| match r {
        Err(IdentifyError::Input(msg)) => msg,
        other => panic!("expected an input error, got {other:?}"),
    };
    assert!(input(identify(&0.5, &1.0, &state)).contains("a > b > 0"));
    assert!(input(identify(&1.0, &0.0, &state)).contains("a > b > 0"));
    assert!(input(identify(&f64::NAN, &0.5, &state)).contains("not a finite"));
    // Outside the documented ranges of a and b/a: refused at once (a = 1e300 searched for minutes).
    assert!(input(identify(&1e300, &0.5e300, &state)).contains("a = "));
    assert!(input(identify(&1.0, &1e-300, &state)).contains("b/a"));
    let mut bad = state.clone();
    bad.alpha[0] *= 1.01;
    assert!(input(identify(&1.0, &0.5, &bad)).contains("|alpha|"));
    let mut bad = state.clone();
    bad.omega[1] = f64::INFINITY;
    assert!(input(identify(&1.0, &0.5, &bad)).contains("finite"));
    // Far from N: either (m, h) has no torus, or the distance says so.
    let far = State {
        omega: [0.3, -0.2, 0.5],
        alpha: [1.0, 0.0, 0.0],
        beta: [0.0, 1.0, 0.0],
    };
    match identify(&1.0, &0.5, &far) {
        Err(IdentifyError::NoTorus { distance, .. }) => assert!(distance > 1e-3),
        Ok(id) => assert!(id.distance.relative > 1e-3 && id.residual > 1e-3),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn the_projector_finds_the_phases_and_the_torus_shift_of_a_nearby_state() {
    // A state of the torus (m + δm, h + δh) projected with the projector of (m, h): the phases,
    // δm and δh come back (to the O(δ²) of the first-order model), the departure is nil; moved off
    // N, the departure is the move.
    use rsts_closed_form::manifold::Projector;
    for (label, m, h) in CAMERA_POINTS {
        let tori = tori_of("1", "0.5", &m.to_string(), &h.to_string());
        let torus = tori - 1;
        let choice = TorusChoice {
            torus,
            phase1: 0.0,
            phase2: 0.0,
        };
        let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
        let projector = Projector::new(&motion).unwrap();
        let (dm, dh) = (3e-9, -2e-9);
        let near = ExplicitMotion::new(1.0, 0.5, m + dm, h + dh, choice).unwrap();
        let psi = [1.3, 4.1];
        let target = state_of(&near.at_angles(&psi[0], &psi[1])).to_array();
        let p = projector.project(&target, &[1.31, 4.08]).unwrap();
        let what = format!("{label} torus {torus}");
        assert!(
            angle_gap(p.phases[0], psi[0]) < 1e-9 && angle_gap(p.phases[1], psi[1]) < 1e-9,
            "{what}: {:?}",
            p.phases
        );
        // m + δm and h + δh are rounded to f64 (1e-16 relative).
        assert!(
            (p.dm - dm).abs() < 1e-13 && (p.dh - dh).abs() < 1e-13,
            "{what}: δm {:e} δh {:e}",
            p.dm,
            p.dh
        );
        assert!(p.departure < 1e-13, "{what}: departure {:e}", p.departure);
        // The exact state itself: nothing moves.
        let exact = state_of(&motion.at_angles(&psi[0], &psi[1])).to_array();
        let q = projector.project(&exact, &psi).unwrap();
        assert!(
            q.dm.abs() < 1e-14 && q.dh.abs() < 1e-14 && q.departure < 1e-14,
            "{what}"
        );
        // Off N by 1e-7 (ω₃): the departure sees (most of) it.
        let mut off = exact;
        off[2] += 1e-7;
        let r = projector.project(&off, &psi).unwrap();
        assert!(
            r.departure > 1e-9 && r.departure <= 1e-7 * (1.0 + 1e-6),
            "{what}: departure {:e}",
            r.departure
        );
    }
}
