//! Time per step of taylor-f64 / taylor-dd on one code path (for profiling and the
//! measurements in docs/taylor.md):
//!
//! ```sh
//! cargo run --release -p rsts-dynamics --example taylor_steps -- f64 1e-13 avx2 300
//! ```
//!
//! Arguments: `f64|dd`, tolerance, path (`avx512|avx2|portable|auto`, or `generic`: the
//! generic stepper, which runs uncompensated here — the lane kernel needs the compensated
//! state), runs (best of; default 300), samples (default 101). The case is the criterion
//! benchmark's: a = 1, b = 0.5, ω = (0.4, −0.7, 1.1), α = (cos 0.3, sin 0.3, 0),
//! β = (−sin 0.3, cos 0.3, 0), T = 100, 101 samples. Prints steps, best and median µs per step
//! (the integrator's own clock) and ω₁ at T with all its digits (the paths' bits compared).

use rsts_dynamics::integrators::{OutputGrid, Problem, Propagator, SimdPath, Taylor, Tolerances};
use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::{Fields, State};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scalar = args.first().map(String::as_str).unwrap_or("f64");
    let tol: f64 = args.get(1).map_or(1e-13, |s| s.parse().expect("tolerance"));
    let path = args.get(2).map(String::as_str).unwrap_or("auto");
    let runs: usize = args.get(3).map_or(300, |s| s.parse().expect("runs"));
    let samples: usize = args.get(4).map_or(101, |s| s.parse().expect("samples"));
    let mut taylor = Taylor::new(Tolerances::new(tol, tol).unwrap());
    match path {
        "auto" => {}
        "generic" => taylor = taylor.uncompensated(),
        _ => taylor = taylor.with_simd(path.parse::<SimdPath>().unwrap()),
    }
    let (s, c) = 0.3f64.sin_cos();
    let problem = Problem {
        fields: Fields::new(1.0, 0.5).unwrap(),
        initial: State {
            omega: [0.4, -0.7, 1.1],
            alpha: [c, s, 0.0],
            beta: [-s, c, 0.0],
        },
    };
    let grid = OutputGrid::new(100.0, samples).unwrap();
    let mut times = Vec::with_capacity(runs);
    let mut steps = 0;
    let mut last = String::new();
    for _ in 0..runs {
        let stats = if scalar == "dd" {
            let p = rsts_dynamics::integrators::map_problem(&problem, |x| {
                DoubleDouble::from_f64_exact(*x)
            });
            let solution = taylor.propagate_grid(&p, &grid).unwrap();
            last = solution.states.last().unwrap().omega[0].to_string();
            solution.stats
        } else {
            let solution = taylor.propagate_grid(&problem, &grid).unwrap();
            last = format!("{:e}", solution.states.last().unwrap().omega[0]);
            solution.stats
        };
        steps = stats.accepted_steps;
        times.push(stats.integration_seconds);
    }
    times.sort_by(f64::total_cmp);
    let us = |t: f64| t * 1e6 / steps as f64;
    println!(
        "taylor-{scalar} {tol:e} path {}: {steps} steps, best {:.3} µs/step, median {:.3} µs/step, \
         ω₁(T) = {last}",
        if path == "generic" {
            "generic".to_string()
        } else {
            taylor.simd_path().unwrap().to_string()
        },
        us(times[0]),
        us(times[times.len() / 2])
    );
}
