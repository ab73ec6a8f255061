//! The early exit of `Projector::project_within` (stop 28) keeps the answer of the full
//! iteration: on states off the torus in every camera (shifted tori, noise from 1e-9 to 1,
//! guesses up to half a radian off), it finds a nearest point exactly when `project` finds one
//! with |δm|, |δh| ≤ the bound, and the same one, bit for bit; in f64 and at 30 digits (MPFR,
//! where an f64 pass precedes the refinement).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::manifold::{Projector, TorusMap};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::{ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rug::Float;

const BOUND: f64 = 1e-2;

/// (nearest points within the bound, beyond it) over `per_camera` random states per camera at
/// `bits` bits; panics where `project_within` and `project` + the bound disagree.
fn agreement<T: Scalar>(bits: u32, per_camera: usize) -> (usize, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(2028);
    let (mut inside, mut outside) = (0, 0);
    let lit = |x: f64| T::from_f64(x, bits);
    let choice = TorusChoice {
        torus: 0,
        phase1: 0.0,
        phase2: 0.0,
    };
    for &(_, m, h) in EXAMPLE_POINTS_A1_B05.iter() {
        let motion_at =
            |m: f64, h: f64| ExplicitMotion::new(lit(1.0), lit(0.5), lit(m), lit(h), choice);
        let Ok(motion) = motion_at(m, h) else {
            continue;
        };
        let projector = Projector::new(&motion).unwrap();
        for _ in 0..per_camera {
            // A point of a shifted torus (shift 1e-4 … 0.3 of |m|, |h| + 0.05), plus noise.
            let shift = |x: f64, rng: &mut ChaCha8Rng| {
                let size = 10f64.powf(rng.gen_range(-4.0..-0.5)) * (x.abs() + 0.05);
                x + if rng.gen_bool(0.5) { size } else { -size }
            };
            let (m2, h2) = (shift(m, &mut rng), shift(h, &mut rng));
            let Ok(other) = motion_at(m2, h2) else {
                continue;
            };
            let psi: [f64; 2] = std::array::from_fn(|_| rng.gen_range(0.0..std::f64::consts::TAU));
            let noise = 10f64.powf(rng.gen_range(-9.0..0.0));
            let mut target = TorusMap::of_motion(&other).state_at(&psi.map(lit));
            for x in &mut target {
                *x += lit(noise * rng.gen_range(-1.0..1.0));
            }
            let guess = psi.map(|p| lit(p + rng.gen_range(-0.5..0.5)));
            let small = |x: &T| x.abs().to_f64() <= BOUND;
            let full = projector
                .project(&target, &guess)
                .filter(|p| small(&p.dm) && small(&p.dh));
            let early = projector.project_within(&target, &guess, BOUND);
            match (&full, &early) {
                (Some(p), Some(q)) => {
                    let decimals = |x: &[&T; 4]| x.map(|v| v.to_decimal(40));
                    assert_eq!(
                        decimals(&[&p.dm, &p.dh, &p.phases[0], &p.phases[1]]),
                        decimals(&[&q.dm, &q.dh, &q.phases[0], &q.phases[1]])
                    );
                    inside += 1;
                }
                (None, None) => outside += 1,
                _ => panic!(
                    "({m}, {h}) → ({m2}, {h2}), noise {noise:e}: project {:?}, within {:?}",
                    full.map(|p| (p.dm.to_f64(), p.dh.to_f64())),
                    early.map(|p| (p.dm.to_f64(), p.dh.to_f64()))
                ),
            }
        }
    }
    (inside, outside)
}

#[test]
fn project_within_finds_the_nearest_points_project_finds_within_the_bound() {
    let (inside, outside) = agreement::<f64>(53, 1500);
    eprintln!("f64: {inside} nearest points within the bound, {outside} beyond it");
    assert!(
        inside >= 1000 && outside >= 1000,
        "{inside} within, {outside} beyond"
    );
}

#[test]
fn project_within_agrees_at_30_digits() {
    let (inside, outside) = agreement::<Float>(132, 25);
    eprintln!("30 digits: {inside} nearest points within the bound, {outside} beyond it");
    assert!(
        inside >= 20 && outside >= 20,
        "{inside} within, {outside} beyond"
    );
}

/// A warm start (`project_from` the nearest point of the sample before: its phase error added
/// to this sample's exact angles, its shift δm, δh) finds the nearest point of the cold start
/// from the exact angles to the round-off, with one evaluation of the derivatives (in 3/4 of
/// the cases at least: not where the shift of the torus times the first step is beyond the
/// round-off, see `CHORD` in project.rs) where the cold start needs two: in every camera, states of a torus shifted by 1e-9 to 1e-6 of the motion's
/// (m, h), phase errors of 1e-5 to 1e-3 rad, a departure off N of 1e-10 to 1e-7, the next
/// sample 0.011 and 0.017 rad further on.
#[test]
fn a_warm_start_finds_the_nearest_point_of_a_cold_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let tau = std::f64::consts::TAU;
    // In (−π, π].
    let wrap = |x: f64| x - tau * (x / tau).round();
    let choice = TorusChoice {
        torus: 0,
        phase1: 0.0,
        phase2: 0.0,
    };
    let (mut count, mut ones, mut largest) = (0, 0, [0.0f64; 6]);
    for &(_, m, h) in EXAMPLE_POINTS_A1_B05.iter() {
        let Ok(motion) = ExplicitMotion::new(1.0, 0.5, m, h, choice) else {
            continue;
        };
        let projector = Projector::new(&motion).unwrap();
        for _ in 0..200 {
            let mut size = |lo: f64, hi: f64| {
                let s = 10f64.powf(rng.gen_range(lo..hi));
                if rng.gen_bool(0.5) {
                    s
                } else {
                    -s
                }
            };
            let (m2, h2) = (
                m + size(-9.0, -6.0) * (m.abs() + 0.05),
                h + size(-9.0, -6.0) * (h.abs() + 0.05),
            );
            let error = [size(-5.0, -3.0), size(-5.0, -3.0)];
            let noise: [f64; 9] = std::array::from_fn(|_| size(-10.0, -7.0));
            let Ok(other) = ExplicitMotion::new(1.0, 0.5, m2, h2, choice) else {
                continue;
            };
            let torus = TorusMap::of_motion(&other);
            // The integrated state at the exact angles ψ: on the shifted torus at ψ + the phase
            // error, plus the departure.
            let state = |psi: [f64; 2]| {
                let mut x = torus.state_at(&[psi[0] + error[0], psi[1] + error[1]]);
                for (x, n) in x.iter_mut().zip(noise) {
                    *x += n;
                }
                x
            };
            let exact0: [f64; 2] = std::array::from_fn(|_| rng.gen_range(0.0..tau));
            let exact1 = [exact0[0] + 0.011, exact0[1] + 0.017];
            let before = projector
                .project_within(&state(exact0), &exact0, BOUND)
                .unwrap();
            let offset: [f64; 2] = std::array::from_fn(|i| wrap(before.phases[i] - exact0[i]));
            let target = state(exact1);
            let cold = projector.project_within(&target, &exact1, BOUND).unwrap();
            let from = [exact1[0] + offset[0], exact1[1] + offset[1]];
            let warm = projector
                .project_from(&target, &from, [before.dm, before.dh], BOUND)
                .unwrap();
            let what = format!("({m}, {h}) → ({m2}, {h2}), ψ {exact1:?}, error {error:?}");
            assert!(
                warm.jacobians <= cold.jacobians,
                "{what}: warm {}, cold {}",
                warm.jacobians,
                cold.jacobians
            );
            ones += usize::from(warm.jacobians == 1);
            let gaps = [
                (0..9)
                    .map(|k| (warm.point[k] - cold.point[k]).abs())
                    .fold(0.0, f64::max),
                wrap(warm.phases[0] - cold.phases[0]).abs(),
                wrap(warm.phases[1] - cold.phases[1]).abs(),
                (warm.dm - cold.dm).abs(),
                (warm.dh - cold.dh).abs(),
                (warm.departure - cold.departure).abs(),
            ];
            for (l, g) in largest.iter_mut().zip(gaps) {
                *l = l.max(g);
            }
            // The point to 1e-13, its angles and shift to 1e-12: the f64 iteration's own error (cold
            // and warm alike up to ~5e-14 from a 200-bit projection in the worst cases here).
            assert!(
                gaps[0] <= 1e-13 && gaps.iter().all(|g| *g <= 1e-12),
                "{what}: {gaps:?}"
            );
            count += 1;
        }
    }
    eprintln!(
        "{count} warm starts, {ones} with one evaluation of the derivatives; largest |Δpoint|, \
         |Δψ₁|, |Δψ₂|, |Δδm|, |Δδh|, |Δdeparture|: {largest:?}"
    );
    assert!(
        count >= 1000 && ones >= count * 3 / 4,
        "{count} warm starts, {ones} with one"
    );
}
