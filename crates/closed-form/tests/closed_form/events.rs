//! Exact event times: the roots are roots at 40 digits, none is missed or doubled against a dense
//! f64 sampling, turning points of s1, s2 sit at the ends of the oscillation segments, and a
//! near-tangent crossing (two roots 1e-8 apart, made by moving a phase by one ulp) is reported
//! as two crossings on one side of the tangency and as none on the other.

use rsts_closed_form::events::{exact_events, working_bits, Crossing, EventSpec, ExactEvent};
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rug::Float;

/// (a, b, m, h, torus): cameras I+, V (m < 0) and I+ at a higher energy.
const CASES: [(f64, f64, f64, f64, usize); 3] = [
    (1.0, 0.5, 0.3, -0.375, 0),
    (1.0, 0.5, -0.7092, 1.5643, 3),
    (1.0, 0.5, 0.3, 0.1, 0),
];

fn motion(
    c: (f64, f64, f64, f64, usize),
    phase1: f64,
    phase2: f64,
    bits: u32,
) -> ExplicitMotion<Float> {
    let f = |x: f64| Float::with_val(bits, x);
    let choice = TorusChoice {
        torus: c.4,
        phase1,
        phase2,
    };
    ExplicitMotion::new(f(c.0), f(c.1), f(c.2), f(c.3), choice).expect("motion")
}

fn all_specs() -> Vec<EventSpec> {
    rsts_closed_form::events::EVENT_NAMES
        .iter()
        .map(|n| n.parse().unwrap())
        .collect()
}

/// Component k (0..12: ω, α, β, γ) of the state at t.
fn component<T: rsts_dynamics::Real + rsts_closed_form::scalar::Scalar>(
    m: &ExplicitMotion<T>,
    t: &T,
    k: usize,
) -> T {
    let s = m.at(t);
    [&s.omega, &s.alpha, &s.beta, &s.gamma][k / 3][k % 3].clone()
}

fn events(m: &ExplicitMotion<Float>, specs: &[EventSpec], t1: f64) -> Vec<ExactEvent> {
    let bits = m.constants.a.prec();
    exact_events(
        m,
        specs,
        &Float::with_val(bits, 0.0),
        &Float::with_val(bits, t1),
    )
    .unwrap()
}

#[test]
fn roots_are_roots_and_none_is_missed_or_doubled() {
    let t_end = 30.0;
    for case in CASES {
        let bits = working_bits(Some(40));
        let exact = motion(case, 0.3, 0.0, bits);
        let found = events(&exact, &all_specs(), t_end);
        let fast = ExplicitMotion::new(case.0, case.1, case.2, case.3, exact.choice).unwrap();
        for k in 0..12 {
            let mine: Vec<&ExactEvent> = found.iter().filter(|e| e.name.index() == k).collect();
            for e in &mine {
                let g = component(&exact, &e.t, k).to_f64().abs();
                assert!(g < 1e-38, "case {case:?} {}: g(t) = {g:e}", e.name);
                assert_ne!(e.direction, Crossing::Tangent);
            }
            // Directions alternate.
            for w in mine.windows(2) {
                assert_ne!(w[0].direction, w[1].direction, "{case:?} {}", w[0].name);
            }
            // An independent count: sign changes on a dense f64 grid.
            let n = 60_000;
            let mut changes = 0;
            // (From just after 0: a root at t = 0 is outside the window.)
            let mut prev = component(&fast, &1e-9, k);
            for j in 1..=n {
                let g = component(&fast, &(t_end * j as f64 / n as f64), k);
                if (g > 0.0) != (prev > 0.0) {
                    changes += 1;
                }
                prev = g;
            }
            assert_eq!(mine.len(), changes, "case {case:?} component {k}");
        }
        // Turning points: the separated variable at an end of its segment, up at the least s.
        for (i, name) in [(0, "s1"), (1, "s2")] {
            let var = if i == 0 { &exact.first } else { &exact.second };
            let (lambda, mu) = var.segment();
            let turns: Vec<&ExactEvent> =
                found.iter().filter(|e| e.name.as_str() == name).collect();
            assert!(turns.len() >= 2, "{case:?} {name}");
            for e in turns {
                let c = exact.at(&e.t).coords;
                let v = if i == 0 { c.x } else { c.s2 };
                let at_lambda = Float::with_val(bits, &v - &lambda).abs().to_f64() < 1e-35;
                let at_mu = Float::with_val(bits, &v - &mu).abs().to_f64() < 1e-35;
                assert!(at_lambda || at_mu, "{case:?} {name} at {}", e.t.to_f64());
                // s2 least at λ; s1 = 1/x greatest at λ.
                let up = at_lambda == (i == 1);
                assert_eq!(e.direction, if up { Crossing::Up } else { Crossing::Down });
            }
        }
    }
}

#[test]
fn a_near_tangent_crossing_is_two_events_and_its_neighbour_none() {
    // beta2 over (0, 6] on camera I+ (h = 0.1): the number of crossings jumps by two where the line
    // (psi1, psi2) = (p, 0.4) + nu t is tangent to the zero curve of beta2 on the torus. Bisect
    // p down to adjacent f64 values.
    let case = CASES[2];
    let bits = working_bits(Some(40));
    let spec: Vec<EventSpec> = vec!["beta2".parse().unwrap()];
    let at = |p: f64| motion(case, p, 0.4, bits);
    let count = |p: f64| events(&at(p), &spec, 6.0).len();
    let grid: Vec<f64> = (0..48)
        .map(|j| j as f64 * std::f64::consts::TAU / 48.0)
        .collect();
    let (mut lo, mut hi) = grid
        .windows(2)
        .map(|w| (w[0], w[1]))
        .find(|&(x, y)| count(y) == count(x) + 2)
        .expect("a phase where two crossings appear");
    let n_lo = count(lo);
    while f64::from_bits(lo.to_bits() + 1) < hi {
        let mid = 0.5 * (lo + hi);
        if count(mid) == n_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let before = events(&at(lo), &spec, 6.0);
    let after = events(&at(hi), &spec, 6.0);
    assert_eq!(after.len(), before.len() + 2);
    // The new pair: the two closest events of `after`.
    let (i, gap) = after
        .windows(2)
        .enumerate()
        .map(|(i, w)| (i, Float::with_val(bits, &w[1].t - &w[0].t).to_f64()))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap();
    assert!(gap < 1e-6 && gap > 0.0, "gap {gap:e}");
    let (t_a, t_b) = (&after[i].t, &after[i + 1].t);
    assert_ne!(after[i].direction, after[i + 1].direction);
    // Genuine: alpha3 vanishes at both (40 digits) and has the other sign between them.
    let m = at(hi);
    let mid = Float::with_val(bits, t_a + t_b) / 2u32;
    let g_mid = component(&m, &mid, 7).to_f64();
    let g_out = component(&m, &Float::with_val(bits, t_a - gap), 7).to_f64();
    assert!(g_mid * g_out < 0.0, "{g_mid:e} {g_out:e}");
    for t in [t_a, t_b] {
        assert!(component(&m, t, 7).to_f64().abs() < 1e-38);
    }
}

/// The count `rsts events` sizes its output by before computing (one event per grid cell of a
/// component, the turning points counted) holds with room on every camera of the quick suite:
/// each name alone, T = 300. The largest share of a component is printed (docs/events.md quotes
/// it).
#[test]
fn the_output_estimate_bounds_the_events_found() {
    use rsts_closed_form::events::EventSearch;
    let cameras = [
        (0.3, -0.375, 0),
        (-1.9244, 0.4503, 0),
        (0.05, 1.058, 1),
        (-0.5573, 1.463, 1),
        (-2.9877, 1.2605, 0),
        (0.05, 2.0706, 2),
        (-0.3295, 1.7668, 3),
        (-0.7092, 1.5643, 3),
        (-2.9877, 3.2858, 1),
        (1e-7, -0.375, 0),
        (0.3, 0.1, 0),
    ];
    let bits = working_bits(None);
    let (t0, t1) = (Float::with_val(bits, 0.0), Float::with_val(bits, 300.0));
    let mut worst: (f64, String) = (0.0, String::new());
    for (m, h, torus) in cameras {
        let mo = motion((1.0, 0.5, m, h, torus), 0.0, 0.0, bits);
        for spec in all_specs() {
            let search = EventSearch::new(&mo, &[spec], &t0, &t1).unwrap();
            let found = exact_events(&mo, &[spec], &t0, &t1).unwrap().len() as f64;
            let share = found / search.most_events();
            assert!(
                share <= 1.0,
                "{m} {h} {}: {found} of {}",
                spec.name,
                search.most_events()
            );
            // The turning points are counted, not estimated: only the components have room.
            if spec.name.index() < 12 && share > worst.0 {
                worst = (share, format!("m {m}, h {h}, torus {torus}, {}", spec.name));
            }
        }
    }
    eprintln!(
        "largest share of the estimate for a component: {:.3} ({})",
        worst.0, worst.1
    );
    assert!(worst.0 < 0.9, "{worst:?}");
}
