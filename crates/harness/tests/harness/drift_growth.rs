//! Growth laws of the invariants (issue 18 item 7): an implicit midpoint rule, which keeps H and
//! the constraints (quadratic invariants) up to round-off, is not called `linear`; RK4 with a big
//! step drifts linearly or faster. Each exponent is checked against a fit computed by a few
//! lines of Python over every sample (skipped with a message when python3 is missing).

use std::process::Command;

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_dynamics::{Fields, State, VectorField};
use rsts_harness::drift_growth::{GrowthKind, GrowthLaw};
use rsts_harness::{analyse, compare, Analysis, Case, Observer, Report, RunInfo, SampleRecord};
use rug::Float;

/// Collects (t, drift of H, K, G, constraints) of every sample.
#[derive(Default)]
struct Drifts(Vec<[f64; 5]>);
impl Observer for Drifts {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        let e = &r.errors;
        self.0
            .push([r.t, e.drift_h, e.drift_k, e.drift_g, e.constraint_drift]);
        Ok(())
    }
}

fn case(t_end: f64, samples: usize) -> Case {
    {
        let mut c = Case::default_i_plus();
        c.t_end = rsts_closed_form::Decimal::from_f64(t_end).unwrap();
        c.samples = samples;
        c
    }
}

/// The implicit midpoint rule y₁ = y₀ + h f((y₀ + y₁)/2), solved by fixed-point iteration to
/// round-off, `per_sample` steps of `h` between samples.
fn implicit_midpoint(c: &Case, h: f64, per_sample: usize) -> (Vec<f64>, Vec<State<f64>>) {
    let field = VectorField::new(&Fields::new(c.motion.a.to_f64(), c.motion.b.to_f64()).unwrap());
    let (motion, _) = c.reference_motion(200).unwrap();
    let start = motion.at(&Float::with_val(200, 0));
    let mut y: [f64; 9] =
        std::array::from_fn(|k| [&start.omega, &start.alpha, &start.beta][k / 3][k % 3].to_f64());
    let mut times = vec![0.0];
    let mut states = vec![State::from_slice(&y)];
    for k in 1..c.samples {
        for _ in 0..per_sample {
            let mut next = y;
            for _ in 0..100 {
                let mid: [f64; 9] = std::array::from_fn(|i| 0.5 * (y[i] + next[i]));
                let f = field.eval(&mid);
                let new: [f64; 9] = std::array::from_fn(|i| y[i] + h * f[i]);
                let done = new == next;
                next = new;
                if done {
                    break;
                }
            }
            y = next;
        }
        times.push(h * (k * per_sample) as f64);
        states.push(State::from_slice(&y));
    }
    (times, states)
}

/// The exponent of C·t^p fitted by Python over every sample: the running maximum of column `k`
/// from T/20 on, least squares of ln(envelope) against ln t.
fn python_exponent(test: &str, drifts: &[[f64; 5]], k: usize) -> Option<f64> {
    let data: String = drifts
        .iter()
        .map(|r| format!("{:e} {:e}\n", r[0], r[k]))
        .collect();
    let script = r#"
import math, sys
rows = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
env, pts, T = 0.0, [], rows[-1][0]
for t, e in rows:
    env = max(env, e)
    if t >= T / 20 and env > 0:
        pts.append((math.log(t), math.log(env)))
n = len(pts); mx = sum(x for x, _ in pts) / n; my = sum(y for _, y in pts) / n
print(sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts))
"#;
    let mut child = match Command::new("python3")
        .args(["-c", script])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => {
            rsts_io::report_skip(test, &format!("python3 not found ({e})"));
            return None;
        }
    };
    use std::io::Write;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(data.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    Some(
        String::from_utf8(out.stdout)
            .unwrap()
            .trim()
            .parse()
            .unwrap(),
    )
}

fn laws(r: &Report) -> [(&'static str, GrowthLaw); 4] {
    let g = r.drift.growth.expect("growth laws after the run");
    [
        ("H", g.h.unwrap()),
        ("K", g.k.unwrap()),
        ("G", g.g.unwrap()),
        ("constraints", g.constraints.unwrap()),
    ]
}

/// Our exponents (fitted over a log-spaced summary) agree with Python's over every sample.
fn check_against_python(test: &str, report: &Report, drifts: &[[f64; 5]]) {
    for (k, (name, law)) in laws(report).iter().enumerate() {
        let Some(p) = python_exponent(test, drifts, k + 1) else {
            return;
        };
        assert!(
            (law.exponent - p).abs() < 0.12,
            "{name}: ours {law:?}, Python {p}"
        );
    }
}

#[test]
fn implicit_midpoint_keeps_h_and_the_constraints_and_is_not_linear() {
    let c = case(400.0, 1601);
    let (times, states) = implicit_midpoint(&c, 0.05, 5);
    let info = RunInfo {
        method: "implicit-midpoint".into(),
        rtol: None,
        atol: None,
        digits: 15,
    };
    let bits = 200;
    let times: Vec<Float> = times.iter().map(|&t| Float::with_val(bits, t)).collect();
    let states: Vec<State<Float>> = states
        .iter()
        .map(|s| s.map(|&x| Float::with_val(bits, x)))
        .collect();
    let mut drifts = Drifts::default();
    let analysis = Analysis::for_case(&c, bits, info).unwrap();
    let report = analyse(analysis, &times, &states, &mut drifts).unwrap();
    let [h, _, _, constraints] = laws(&report);
    for (name, law) in [h, constraints] {
        assert!(
            matches!(law.kind, GrowthKind::Bounded | GrowthKind::RandomWalk),
            "{name}: {law:?}, drift of H {:e}",
            report.drift.h
        );
    }
    // Kept to round-off while the state error is far above it (second order, h = 0.05).
    assert!(report.drift.h < 1e-13, "{:e}", report.drift.h);
    assert!(
        report.max_state_error > 1e-5,
        "{:e}",
        report.max_state_error
    );
    check_against_python("implicit_midpoint_is_not_linear", &report, &drifts.0);
}

#[test]
fn rk4_with_a_big_step_drifts_linearly_or_faster() {
    let c = case(2000.0, 2001);
    let config = MethodConfig::new(
        MethodName::Rk4,
        Tolerances::new(1e-6, 1e-6).unwrap(),
        Some(0.2),
    )
    .unwrap();
    let mut drifts = Drifts::default();
    let report = compare(&c, &config, &mut drifts).unwrap();
    let [(_, h), _, _, _] = laws(&report);
    assert!(
        matches!(h.kind, GrowthKind::Linear | GrowthKind::Faster),
        "{h:?}"
    );
    check_against_python("rk4_drifts_linearly", &report, &drifts.0);
}
