//! What tells, before the projector's Gauss–Newton loop, a sample that gets a nearest point on N
//! from one that does not (stop 31, docs/benchmarks.md "Saturated samples (stop 31)"): for each
//! row of an f64 trajectory CSV (t, ω, α, β, …) of the motion (a, b) = (1, 0.5), (m, h) on torus
//! `torus`, the projection from the exact angles νt (a cold start, the projector alone) with
//! shifts of the torus up to 1e-2, and the quantiles of |X_Φ| and of the state error of both kinds.
//!
//! Usage: cargo run --release -p rsts-closed-form --example saturated_samples -- FILE.csv M H TORUS

use rsts_closed_form::manifold::distance::field_norm;
use rsts_closed_form::manifold::{Projector, TorusMap};
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::{Fields, State};

/// One line of quantiles of `values`.
fn quantiles(values: &mut [f64], name: &str) {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n == 0 {
        println!("{name}: none");
        return;
    }
    let at = |p: usize| values[(p * n / 100).min(n - 1)];
    println!(
        "{name} ({n} samples): min {:.2e}, 10 % {:.2e}, median {:.2e}, 90 % {:.2e}, max {:.2e}",
        values[0],
        at(10),
        at(50),
        at(90),
        values[n - 1]
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 5 {
        eprintln!("usage: saturated_samples FILE.csv M H TORUS");
        std::process::exit(2);
    }
    let number = |i: usize| -> f64 {
        args[i].parse().unwrap_or_else(|_| {
            eprintln!("not a number: {}", args[i]);
            std::process::exit(2)
        })
    };
    let (m, h, torus) = (number(2), number(3), number(4) as usize);
    let text = std::fs::read_to_string(&args[1]).unwrap_or_else(|e| {
        eprintln!("{}: {e}", args[1]);
        std::process::exit(2)
    });
    let fields = Fields { a: 1.0, b: 0.5 };
    let choice = TorusChoice {
        torus,
        phase1: 0.0,
        phase2: 0.0,
    };
    let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap_or_else(|e| {
        eprintln!("no motion at (m, h) = ({m}, {h}), torus {torus}: {e}");
        std::process::exit(2)
    });
    let nu = motion.frequencies();
    let map = TorusMap::of_motion(&motion);
    let projector = Projector::new(&motion).unwrap_or_else(|e| {
        eprintln!("no projector for the torus of (m, h) = ({m}, {h}): {e}");
        std::process::exit(2)
    });
    let two_pi = 2.0 * std::f64::consts::PI;
    // [x_phi, state error] of the samples with and without a nearest point.
    let mut kinds: [[Vec<f64>; 2]; 2] = Default::default();
    for (i, line) in text.lines().enumerate().skip(1) {
        let row: Vec<f64> = line.split(',').filter_map(|x| x.parse().ok()).collect();
        if row.len() < 10 {
            eprintln!("line {}: fewer than 10 numbers", i + 1);
            std::process::exit(2);
        }
        let x: [f64; 9] = std::array::from_fn(|k| row[k + 1]);
        let psi = nu.map(|n| (n * row[0]).rem_euclid(two_pi));
        let exact = map.state_at(&psi);
        let error = (0..9).map(|k| (x[k] - exact[k]).abs()).fold(0.0, f64::max);
        let x_phi = field_norm(&fields, &State::from_slice(&x));
        let near = projector.project_within(&x, &psi, 1e-2).is_some();
        let kind = &mut kinds[usize::from(!near)];
        kind[0].push(x_phi);
        kind[1].push(error);
    }
    for (k, name) in ["a nearest point", "no nearest point"].iter().enumerate() {
        quantiles(&mut kinds[k][0], &format!("|X_Φ|, {name}"));
        quantiles(&mut kinds[k][1], &format!("state error, {name}"));
    }
}
