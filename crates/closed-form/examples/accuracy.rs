//! Accuracy of the f64 closed form against the 60-digit one, and the Euler–Poisson residual of the
//! 50-digit closed form, at a point of every camera and next to every curve of Σ.
//!
//!     cargo run --release -p rsts-closed-form --example accuracy

use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Fields, Real, VectorField};
use rug::Float;

const CHOICE: TorusChoice = TorusChoice {
    torus: 0,
    phase1: 0.7,
    phase2: 2.1,
};

fn state<T: Real>(s: &rsts_closed_form::ExplicitState<T>) -> [f64; 9] {
    let v = [&s.omega, &s.alpha, &s.beta];
    std::array::from_fn(|k| v[k / 3][k % 3].to_f64())
}

fn main() {
    let (a, b) = (1.0, 0.5);
    let d = 1e-9;
    let cameras = rsts_closed_form::EXAMPLE_POINTS_A1_B05.map(|(c, m, h)| (c.label(), m, h));
    let near_sigma: [(&str, f64, f64); 7] = [
        ("1e-9 above h = r²m − 2a", 1.0, -1.25 + d),
        ("1e-9 above h = −r²m − 2b", 0.0, -1.0 + d),
        ("1e-9 inside ℓ² = 0", -1.0, 1.75 - d),
        ("1e-9 below h = r²m + 2a", 0.0, 2.0 - d),
        ("1e-9 above h = r²m + 2a", 0.0, 2.0 + d),
        ("1e-9 below h = −r²m + 2b", 0.0, 1.0 - d),
        ("1e-9 above h = −r²m + 2b", 0.0, 1.0 + d),
    ];
    let points = cameras.iter().chain(near_sigma.iter()).copied();
    let times = [0.0, 3.0, 100.0, 1e4, 1e6];
    println!("a = {a}, b = {b}, torus 0, phases (0.7, 2.1)");
    println!("| point | camera | k² (x, s2) | max |f64 − 60 digits| over t ∈ {{0, 3, 1e2, 1e4, 1e6}} | EP residual at 50 digits, t = 3 |");
    println!("|---|---|---|---|---|");
    for (name, m, h) in points {
        let lo = ExplicitMotion::new(a, b, m, h, CHOICE).unwrap();
        let bits = bits_for_digits(60);
        let f = |x: f64| Float::with_val(bits, x);
        let hi = ExplicitMotion::new(f(a), f(b), f(m), f(h), CHOICE).unwrap();
        let err = times
            .iter()
            .map(|&t| {
                let (x, y) = (state(&lo.at(&t)), state(&hi.at(&f(t))));
                (0..9).map(|k| (x[k] - y[k]).abs()).fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        let b50 = bits_for_digits(50);
        let g = |x: f64| Float::with_val(b50, x);
        let mid = ExplicitMotion::new(g(a), g(b), g(m), g(h), CHOICE).unwrap();
        let sd = mid.at_with_derivative(&g(3.0));
        let v = [&sd.omega, &sd.alpha, &sd.beta];
        let x: [Float; 9] = std::array::from_fn(|k| v[k / 3][k % 3].re.clone());
        let fx = VectorField::new(&Fields { a: g(a), b: g(b) }).eval(&x);
        let res = (0..9)
            .map(|k| (v[k / 3][k % 3].eps.clone() - &fx[k]).abs().to_f64())
            .fold(0.0, f64::max);
        println!(
            "| {name} (m = {m}, h = {h}) | {} | {:.3e}, {:.3e} | {err:.1e} | {res:.1e} |",
            lo.camera, lo.first.modulus.k2, lo.second.modulus.k2
        );
    }
}
