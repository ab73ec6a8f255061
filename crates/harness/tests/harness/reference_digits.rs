//! Rows of the reference at D digits: H, K, G are the constants of N computed once per table
//! (H = h, K = r⁴m², G = (p²h + r⁴m)/2, exact from the f64 inputs, rounded once). Before, each
//! row evaluated H, K, G from its own state; those values must agree with the constants to the
//! working precision (1e-95 relative at 100 digits) on random times over every camera of
//! a = 1, b = 0.5, camera V's fourth torus, a field pair far from b = a/2 and a point within
//! 1e-9 of Σ. The check has teeth: a state moved by 1e-92 of its scale fails it.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rug::Float;

use rsts_closed_form::EXAMPLE_POINTS_A1_B05;
use rsts_dynamics::fields::Fields;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::State;
use rsts_harness::reference::ReferenceTable;
use rsts_harness::Case;

fn case(a: f64, b: f64, m: f64, h: f64, torus: usize) -> Case {
    Case::binary([a, b, m, h], torus, [0.7, 2.1], 1.0, 1).unwrap()
}

/// The largest difference between the row's H, K, G and the integrals of its state, relative
/// to max(1, |value|).
fn deviation(fields: &Fields<Float>, row: &[Float]) -> f64 {
    let state = State::from_slice(&row[1..10]);
    let i = integrals(fields, &state);
    [i.h, i.k, i.g]
        .iter()
        .zip(&row[10..13])
        .map(|(x, y)| {
            let d = Float::with_val(x.prec(), x - y).to_f64().abs();
            d / y.to_f64().abs().max(1.0)
        })
        .fold(0.0, f64::max)
}

#[test]
fn rows_at_100_digits_carry_the_integrals_of_their_state() {
    let mut cases: Vec<(String, Case)> = EXAMPLE_POINTS_A1_B05
        .iter()
        .map(|(camera, m, h)| (format!("{camera:?}"), case(1.0, 0.5, *m, *h, 0)))
        .collect();
    cases.push((
        "camera V, torus 3".into(),
        case(1.0, 0.5, -0.7092, 1.5643, 3),
    ));
    cases.push(("b = 0.999, m < 0".into(), case(1.0, 0.999, -0.5, 1.5, 0)));
    cases.push((
        "1e-9 above h = −r²m + 2b".into(),
        case(1.0, 0.5, 0.0, 1.0 + 1e-9, 0),
    ));
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut worst: f64 = 0.0;
    for (what, case) in &cases {
        let table = ReferenceTable::new(case, &[1e6], Some(100)).unwrap();
        let fields = table.analysis().fields();
        for k in 0..40 {
            let t = match k % 3 {
                0 => rng.gen_range(0.0..1e6),
                1 => rng.gen_range(-50.0..50.0),
                _ => rng.gen_range(0..1_000_000u64) as f64,
            };
            let row = table.row(t).unwrap();
            let dev = deviation(fields, &row);
            assert!(dev < 1e-95, "{what}: t = {t:e}: H, K, G off by {dev:e}");
            worst = worst.max(dev);
            if k == 0 {
                // Teeth: a state 1e-92 away (β₁) no longer has these integrals.
                let mut moved = row.clone();
                let step = Float::with_val(moved[7].prec(), 1e-92);
                moved[7] += step;
                let dev = deviation(fields, &moved);
                assert!(dev > 1e-95, "{what}: a moved state passes ({dev:e})");
            }
        }
        // H is the case's h, exactly.
        assert_eq!(
            table.row(0.5).unwrap()[10],
            case.motion.h.to_f64(),
            "{what}"
        );
    }
    eprintln!("largest relative difference of H, K, G: {worst:e}");
}
