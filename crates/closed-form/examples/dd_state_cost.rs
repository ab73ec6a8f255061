//! CPU time of the double-double state of an f64 time (ω, α, β: the reference of one sample of
//! f64 data, `ExplicitMotion::body_at_f64`) on the README's default case (camera I+) and on
//! camera V's third torus (m < 0), 4·10⁵ times over [0, 1000), the best of 5 rounds. The time
//! is the thread's CPU time (Linux; wall time elsewhere), so a loaded machine disturbs it less
//! than criterion's wall time. Each case twice: one state at a time (`body_at_f64`) and in
//! batches of 64 times, four at a time (`bodies_at_f64`, as `rsts check` evaluates a chunk).
//!
//!     cargo run --release -p rsts-closed-form --example dd_state_cost

use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::scalar::DoubleDouble;
use std::hint::black_box;

#[cfg(target_os = "linux")]
fn cpu_seconds() -> f64 {
    extern "C" {
        fn clock_gettime(clock: i32, ts: *mut [i64; 2]) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = [0i64; 2];
    // SAFETY: clock_gettime writes one timespec (two 64-bit fields on Linux x86-64/aarch64).
    unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts[0] as f64 + ts[1] as f64 * 1e-9
}

#[cfg(not(target_os = "linux"))]
fn cpu_seconds() -> f64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}

fn main() {
    let d = DoubleDouble::from_f64_exact;
    let n = 400_000;
    println!(
        "case                              path      µs per state (thread CPU time, best of 5)"
    );
    for (name, m, h, torus) in [
        ("I+ (m 0.3, h -0.375)", 0.3, -0.375, 0),
        ("V (m -0.7092, h 1.5643, torus 2)", -0.7092, 1.5643, 2),
    ] {
        let choice = TorusChoice {
            torus,
            ..TorusChoice::default()
        };
        let motion = ExplicitMotion::new_until(d(1.0), d(0.5), d(m), d(h), choice, 1000.0)
            .expect("an admissible case");
        let times: Vec<f64> = (0..n).map(|k| 1000.0 * k as f64 / n as f64).collect();
        let mut best = [f64::INFINITY; 2];
        let mut sum = 0.0;
        let mut out = Vec::with_capacity(64);
        for _ in 0..5 {
            let start = cpu_seconds();
            for &t in &times {
                let b = motion.body_at_f64(black_box(t));
                sum += b.omega[0].hi;
            }
            best[0] = best[0].min((cpu_seconds() - start) / n as f64 * 1e6);
            let start = cpu_seconds();
            for chunk in times.chunks(64) {
                out.clear();
                motion.bodies_at_f64(black_box(chunk), &mut out);
                sum += out[0].omega[0].hi;
            }
            best[1] = best[1].min((cpu_seconds() - start) / n as f64 * 1e6);
        }
        black_box(sum);
        println!("{name:<33} {:<9} {:.3}", "one", best[0]);
        println!("{name:<33} {:<9} {:.3}", "batch", best[1]);
    }
}
