//! The accuracy of the double-double state (ω, α, β at an f64 time, the reference of f64 data)
//! against the closed form at 40 digits in MPFR: for each camera of a = 1, b = 0.5 and `N`
//! random times (uniform in [0, 1e9), in [−1e3, 1e3), integers, skewed towards 0), the largest
//! difference of each value divided by that value's largest magnitude over the times, in units
//! of 2⁻¹⁰⁶ (the double-double grid at 1).
//!
//!     cargo run --release -p rsts-closed-form --example dd_accuracy -- [N per camera]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::{ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rsts_dynamics::scalar::{bits_for_digits, DoubleDouble};
use rug::Float;

fn main() {
    let per_camera: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(12_000);
    let bits = bits_for_digits(40);
    let choice = TorusChoice {
        torus: 0,
        phase1: 0.7,
        phase2: 2.1,
    };
    let unit = 2f64.powi(-106);
    let mut worst = 0f64;
    println!("camera  max |dd − mpfr|/scale over ω, α, β, in units of 2⁻¹⁰⁶ ({per_camera} times)");
    for (c, (camera, m, h)) in EXAMPLE_POINTS_A1_B05.iter().enumerate() {
        let d = DoubleDouble::from_f64_exact;
        let dd = ExplicitMotion::new_until(d(1.0), d(0.5), d(*m), d(*h), choice, 1e9).unwrap();
        let f = |x: f64| Float::with_val(bits, x);
        let mp = ExplicitMotion::new_until(f(1.0), f(0.5), f(*m), f(*h), choice, 1e9).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(c as u64);
        let mut err = [0f64; 9];
        let mut scale = [0f64; 9];
        for k in 0..per_camera {
            let t = match k % 4 {
                0 => rng.gen_range(0.0..1e9),
                1 => rng.gen_range(-1e3..1e3),
                2 => rng.gen_range(0..1_000_000_000u64) as f64,
                _ => 1e9 * rng.gen::<f64>().powi(8),
            };
            let a = dd.body_at_f64(t);
            let b = mp.body_at(&f(t));
            let xs = a.omega.iter().chain(&a.alpha).chain(&a.beta);
            let ys = b.omega.iter().chain(&b.alpha).chain(&b.beta);
            for (j, (x, y)) in xs.zip(ys).enumerate() {
                let diff = Float::with_val(bits, &x.to_float(bits) - y).to_f64().abs();
                err[j] = err[j].max(diff);
                scale[j] = scale[j].max(y.to_f64().abs());
            }
        }
        let rel = (0..9)
            .map(|j| err[j] / scale[j].max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        worst = worst.max(rel);
        println!("{:<7} {:.1}", camera.label(), rel / unit);
    }
    println!("all     {:.1}", worst / unit);
}
