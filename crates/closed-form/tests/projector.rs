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
