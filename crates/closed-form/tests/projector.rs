//! The early exit of `Projector::project_within` (stop 28) keeps the answer of the full
//! iteration: on states off the torus in every camera (shifted tori, noise from 1e-9 to 1,
//! guesses up to half a radian off), it finds a nearest point exactly when `project` finds one
//! with |δm|, |δh| ≤ the bound, and the same one, bit for bit.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::manifold::{Projector, TorusMap};
use rsts_closed_form::{ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};

const BOUND: f64 = 1e-2;

#[test]
fn project_within_finds_the_nearest_points_project_finds_within_the_bound() {
    let mut rng = ChaCha8Rng::seed_from_u64(2028);
    let (mut inside, mut outside) = (0, 0);
    for &(_, m, h) in EXAMPLE_POINTS_A1_B05.iter() {
        let choice = |torus| TorusChoice {
            torus,
            phase1: 0.0,
            phase2: 0.0,
        };
        let Ok(motion) = ExplicitMotion::new(1.0, 0.5, m, h, choice(0)) else {
            continue;
        };
        let projector = Projector::new(&motion).unwrap();
        for _ in 0..1500 {
            // A point of a shifted torus (shift 1e-4 … 0.3 of |m|, |h| + 0.05), plus noise.
            let shift = |x: f64, rng: &mut ChaCha8Rng| {
                let size = 10f64.powf(rng.gen_range(-4.0..-0.5)) * (x.abs() + 0.05);
                x + if rng.gen_bool(0.5) { size } else { -size }
            };
            let (m2, h2) = (shift(m, &mut rng), shift(h, &mut rng));
            let Ok(other) = ExplicitMotion::new(1.0, 0.5, m2, h2, choice(0)) else {
                continue;
            };
            let psi: [f64; 2] = std::array::from_fn(|_| rng.gen_range(0.0..std::f64::consts::TAU));
            let noise = 10f64.powf(rng.gen_range(-9.0..0.0));
            let mut target = TorusMap::of_motion(&other).state_at(&psi);
            for x in &mut target {
                *x += noise * rng.gen_range(-1.0..1.0);
            }
            let guess = psi.map(|p| p + rng.gen_range(-0.5..0.5));
            let full = projector
                .project(&target, &guess)
                .filter(|p| p.dm.abs() <= BOUND && p.dh.abs() <= BOUND);
            let early = projector.project_within(&target, &guess, BOUND);
            match (&full, &early) {
                (Some(p), Some(q)) => {
                    assert_eq!(
                        [p.dm, p.dh, p.phases[0], p.phases[1]].map(f64::to_bits),
                        [q.dm, q.dh, q.phases[0], q.phases[1]].map(f64::to_bits)
                    );
                    inside += 1;
                }
                (None, None) => outside += 1,
                _ => panic!(
                    "({m}, {h}) → ({m2}, {h2}), noise {noise:e}: project {:?}, within {:?}",
                    full.map(|p| (p.dm, p.dh)),
                    early.map(|p| (p.dm, p.dh))
                ),
            }
        }
    }
    eprintln!("{inside} nearest points within the bound, {outside} beyond it");
    assert!(
        inside >= 100 && outside >= 100,
        "{inside} within, {outside} beyond"
    );
}
