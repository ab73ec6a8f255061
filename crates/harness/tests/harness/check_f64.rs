//! f64 data analysed in f64 and double-double (`Analysis::sample_all_f64`, what `rsts check`
//! of an f64 file runs) report what the same samples widened to MPFR report
//! (`Analysis::sample_all`, the path of every other caller): the whole report, to its last
//! printed digit but for the geometry's last digits (a warm start of its projector), on a
//! perturbed trajectory of each normal type (elliptic I+, hyperbolic V).

#[path = "support/geometry_digits.rs"]
mod geometry_digits;
use geometry_digits::assert_same_but_the_geometrys_last_digits;

use rsts_dynamics::State;
use rsts_harness::{Analysis, Case, NoObserver, RunInfo};
use rug::Float;

fn info() -> RunInfo {
    RunInfo {
        method: "f64 data".into(),
        rtol: None,
        atol: None,
        digits: 15,
    }
}

/// The exact states at `times`, rounded to f64 and perturbed by a wobble growing to `size`.
fn perturbed(case: &Case, bits: u32, times: &[f64], size: f64) -> Vec<[f64; 9]> {
    let exact = Analysis::for_case(case, bits, info()).unwrap();
    times
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            let s = exact
                .exact_state(&Float::with_val(bits, t))
                .to_array()
                .map(|x| x.to_f64());
            let grow = (t / times[times.len() - 1]).powi(2);
            std::array::from_fn(|i| s[i] + size * grow * ((k * 9 + i) as f64 * 0.731).sin())
        })
        .collect()
}

/// The JSON of the report of `states` analysed by the f64 path or by the MPFR one.
fn report(case: &Case, bits: u32, times: &[f64], states: &[[f64; 9]], f64_path: bool) -> String {
    let mut analysis = Analysis::for_case(case, bits, info()).unwrap();
    if f64_path {
        analysis
            .sample_all_f64(times, states, &mut NoObserver)
            .unwrap();
    } else {
        let wide = |x: &f64| Float::with_val(bits, *x);
        let t: Vec<Float> = times.iter().map(wide).collect();
        let s: Vec<State<Float>> = states
            .iter()
            .map(|x| State::from_slice(&x.each_ref().map(wide)))
            .collect();
        analysis.sample_all(&t, &s, &mut NoObserver).unwrap();
    }
    serde_json::to_string_pretty(&analysis.finish()).unwrap()
}

#[test]
fn f64_path_reports_the_mpfr_paths_digits() {
    let bits = 172;
    for (case, size) in [
        (Case::default_i_plus(), 1e-10),
        (
            {
                let mut c = Case::default_i_plus();
                c.motion.m = rsts_closed_form::Decimal::from_f64(-0.7092).unwrap();
                c.motion.h = rsts_closed_form::Decimal::from_f64(1.5643).unwrap();
                c.motion.torus = 2;
                c.t_end = rsts_closed_form::Decimal::from_f64(40.0_f64).unwrap();
                c
            },
            1e-12,
        ),
    ] {
        let times: Vec<f64> = (0..400).map(|k| 0.1 * k as f64).collect();
        let states = perturbed(&case, bits, &times, size);
        let f64_path = report(&case, bits, &times, &states, true);
        let mpfr_path = report(&case, bits, &times, &states, false);
        let parse = |s: &str| -> serde_json::Value { serde_json::from_str(s).unwrap() };
        assert_same_but_the_geometrys_last_digits(
            &parse(&f64_path),
            &parse(&mpfr_path),
            &format!("m = {}", case.motion.m.to_f64()),
        );
        // The comparison sees a change of one value of the last sample by one unit in the
        // last place.
        let mut moved = states.clone();
        moved[399][4] = moved[399][4].next_up();
        let other = report(&case, bits, &times, &moved, true);
        assert_ne!(
            other,
            mpfr_path,
            "m = {}: one ulp at one sample unseen",
            case.motion.m.to_f64()
        );
        assert!(f64_path.contains("\"distance_from_N\""), "{f64_path}");
    }
}
