//! An external integrator for rsts in one file: the classical fourth-order Runge–Kutta method
//! with a fixed step, speaking the `rsts-integrator/1` protocol (docs/own-integrator.md).
//!
//! It reads one JSON request on stdin, integrates the Euler–Poisson equations of the Kowalevski
//! top in two fields from the initial state through the requested times, and writes the states
//! as JSON on stdout. Nothing of rsts is used: only `serde_json`.
//!
//! ```sh
//! cargo build --release -p example-adapter-rk4
//! target/release/rsts compare --exec target/release/example-adapter-rk4 --rtol 1e-10 --t-end 20 --samples 201
//! ```
//!
//! The step is the request's `"step"` when it has one (a convergence study, `rsts convergence`),
//! else rtol^(1/4) (at most 0.01), shortened so that every interval between two requested times
//! is a whole number of steps; `--step H` sets it instead (and the request's step is ignored).
//! `--tableau heun|kutta3|rk4-wrong-weight|rk4-off-weight|rk4-near` runs another explicit Runge–Kutta method instead of
//! the classical RK4 (known orders, for tests of observed-order fits).
//!
//! Events (docs/events.md): when the request asks for `"events"` (components of ω, α, β, γ),
//! each step's event function is interpolated by the cubic Hermite polynomial of its values and
//! derivatives (from the equations) at both ends, and a sign change at the step's ends is refined
//! by bisection on that cubic. `--drop-event K` leaves out the K-th event found (0-based): a
//! faulty event finder, for testing the checks.
//!
//! Dense output (`"dense": K` in the request, `rsts compare --dense K`): the answer also carries
//! `"stats": {"step_times": [...]}` and `"dense"`: in each step, the K samples of the
//! interpolant at t₀ + j·h/(K + 1) and the step's end. The interpolant is the cubic Hermite
//! polynomial (order 3, error O(h⁴) like the step's); `--interpolant linear` uses the chord
//! instead (error O(h²)): a dense output of lower order than the method, for testing the check;
//! `--ignore-dense` answers without them (an adapter that does not know `dense`).

use std::io::{Read, Write};
use std::time::Instant;

use serde_json::{json, Value};

type State = [f64; 9];

/// dω/dt, dα/dt, dβ/dt for inertia diag(2, 2, 1), fields a (along α) and b (along β).
fn rhs(a: f64, b: f64, y: &State) -> State {
    let [w1, w2, w3, a1, a2, a3, b1, b2, b3] = *y;
    [
        0.5 * w2 * w3 + 0.5 * b * b3,
        -0.5 * w1 * w3 - 0.5 * a * a3,
        a * a2 - b * b1,
        a2 * w3 - a3 * w2,
        a3 * w1 - a1 * w3,
        a1 * w2 - a2 * w1,
        b2 * w3 - b3 * w2,
        b3 * w1 - b1 * w3,
        b1 * w2 - b2 * w1,
    ]
}

/// An explicit Runge–Kutta method by its Butcher tableau: stage i uses a[i][..i], weights b.
struct Tableau {
    name: &'static str,
    a: &'static [&'static [f64]],
    b: &'static [f64],
}

/// The methods of `--tableau NAME`: the classical RK4 (default), Heun's method (order 2),
/// Kutta's third-order method, and RK4 with one weight misplaced (b = 1/6, 1/2, 1/6, 1/6: the
/// conditions of orders 1 and 2 still hold, Σ bᵢaᵢⱼcⱼ = 1/8 ≠ 1/6 fails, so its order is 2).
/// Two more for the floor and regime checks (issue 33): `rk4-off-weight`, the weight of k2 off
/// by 4e-10 (Σbᵢ ≠ 1: an error floor ~1e-9, far above round-off), and `rk4-near`, the weights
/// of k2 and k3 off by ±4e-5 (Σbᵢaᵢⱼcⱼ = 1/6 − 1e-5: order 4, then order 2 at small steps).
const TABLEAUS: [Tableau; 6] = [
    Tableau {
        name: "rk4",
        a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
        b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    },
    Tableau {
        name: "heun",
        a: &[&[], &[1.0]],
        b: &[0.5, 0.5],
    },
    Tableau {
        name: "kutta3",
        a: &[&[], &[0.5], &[-1.0, 2.0]],
        b: &[1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    },
    Tableau {
        name: "rk4-wrong-weight",
        a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
        b: &[1.0 / 6.0, 0.5, 1.0 / 6.0, 1.0 / 6.0],
    },
    Tableau {
        name: "rk4-off-weight",
        a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
        b: &[1.0 / 6.0, 1.0 / 3.0 + 4e-10, 1.0 / 3.0, 1.0 / 6.0],
    },
    Tableau {
        name: "rk4-near",
        a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
        b: &[1.0 / 6.0, 1.0 / 3.0 + 4e-5, 1.0 / 3.0 - 4e-5, 1.0 / 6.0],
    },
];

/// One step of `t` from y.
fn rk_step(t: &Tableau, a: f64, b: f64, y: &State, h: f64) -> State {
    let mut k: Vec<State> = Vec::with_capacity(t.b.len());
    for row in t.a {
        let stage: State = std::array::from_fn(|i| {
            y[i] + h * row.iter().zip(&k).map(|(c, k)| c * k[i]).sum::<f64>()
        });
        k.push(rhs(a, b, &stage));
    }
    std::array::from_fn(|i| y[i] + h * t.b.iter().zip(&k).map(|(c, k)| c * k[i]).sum::<f64>())
}

/// The value after `flag` on the command line.
fn option(args: &[String], flag: &str) -> Result<Option<String>, String> {
    match args.iter().position(|s| s == flag) {
        Some(i) => Ok(Some(
            args.get(i + 1)
                .ok_or(format!("{flag} needs a value"))?
                .clone(),
        )),
        None => Ok(None),
    }
}

/// A number given as a JSON number or a decimal string.
fn num(v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => n.as_f64().ok_or("bad number".into()),
        Value::String(s) => s.parse().map_err(|_| format!("'{s}' is not a number")),
        _ => Err(format!("expected a number, got {v}")),
    }
}

/// Value and time derivative of a named event function at a state (None: not a state function).
fn event_fn(name: &str, a: f64, b: f64, y: &State) -> Option<(f64, f64)> {
    let dy = rhs(a, b, y);
    let names = [
        "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
    ];
    if let Some(k) = names.iter().position(|n| *n == name) {
        return Some((y[k], dy[k]));
    }
    let k = ["gamma1", "gamma2", "gamma3"]
        .iter()
        .position(|n| *n == name)?;
    let cross = |u: [f64; 3], v: [f64; 3]| -> [f64; 3] {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let g = cross([y[3], y[4], y[5]], [y[6], y[7], y[8]]);
    let dg = cross(g, [y[0], y[1], y[2]]);
    Some((g[k], dg[k]))
}

/// The zero in (t0, t0 + h] of the cubic Hermite interpolant of (g, g') at both ends, when the
/// end values differ in sign and the direction is asked for.
fn hermite_zero(
    t0: f64,
    h: f64,
    (g0, d0): (f64, f64),
    (g1, d1): (f64, f64),
    dir: &str,
) -> Option<f64> {
    let up = g0 < 0.0 && g1 >= 0.0;
    let down = g0 > 0.0 && g1 <= 0.0;
    if !((up && dir != "down") || (down && dir != "up")) {
        return None;
    }
    let p = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * g0
            + (s3 - 2.0 * s2 + s) * h * d0
            + (3.0 * s2 - 2.0 * s3) * g1
            + (s3 - s2) * h * d1
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (p(mid) >= 0.0) == up {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(t0 + 0.5 * (lo + hi) * h)
}

fn run() -> Result<Value, String> {
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .map_err(|e| e.to_string())?;
    let req: Value = serde_json::from_str(&text).map_err(|e| format!("bad request: {e}"))?;
    if req["protocol"] != "rsts-integrator/1" {
        return Err(format!("unsupported protocol {}", req["protocol"]));
    }
    let (a, b) = (num(&req["a"])?, num(&req["b"])?);
    let mut y: State = [0.0; 9];
    for (k, key) in ["omega", "alpha", "beta"].iter().enumerate() {
        for i in 0..3 {
            y[3 * k + i] = num(&req["initial"][key][i])?;
        }
    }
    let times: Vec<f64> = req["times"]
        .as_array()
        .ok_or("no times")?
        .iter()
        .map(num)
        .collect::<Result<_, _>>()?;
    let args: Vec<String> = std::env::args().collect();
    let name = option(&args, "--tableau")?.unwrap_or_else(|| "rk4".into());
    let tableau = TABLEAUS.iter().find(|t| t.name == name).ok_or_else(|| {
        let known: Vec<&str> = TABLEAUS.iter().map(|t| t.name).collect();
        format!("unknown --tableau {name} (known: {})", known.join(", "))
    })?;
    // The step: --step H (fixed by the command line: the request's "step" is then ignored),
    // else the request's "step" (a convergence study), else rtol^(1/4) capped at 0.01.
    let step = match (option(&args, "--step")?, req.get("step")) {
        (Some(h), _) => h.parse().map_err(|_| "bad --step")?,
        (None, Some(h)) => num(h)?,
        (None, None) => num(&req["rtol"])?.powf(0.25).min(0.01),
    };
    if !(step.is_finite() && step > 0.0) {
        return Err(format!("the step must be positive, got {step}"));
    }
    let drop = match args.iter().position(|s| s == "--drop-event") {
        Some(i) => Some(
            args.get(i + 1)
                .and_then(|v| v.parse::<usize>().ok())
                .ok_or("--drop-event needs a whole number")?,
        ),
        None => None,
    };
    // (name, direction) of the events asked for that are functions of the state.
    let mut asked: Vec<(String, String)> = Vec::new();
    for e in req["events"].as_array().into_iter().flatten() {
        let name = e["name"]
            .as_str()
            .ok_or("an event without a name")?
            .to_string();
        let dir = e["direction"].as_str().unwrap_or("both").to_string();
        if event_fn(&name, a, b, &y).is_some() {
            asked.push((name, dir));
        } else {
            eprintln!("example-adapter-rk4: event {name} is not a function of the state; skipped");
        }
    }
    let dense = match req
        .get("dense")
        .filter(|_| !args.iter().any(|a| a == "--ignore-dense"))
    {
        Some(k) => Some(
            k.as_u64()
                .filter(|k| *k >= 1)
                .ok_or("\"dense\" must be a whole number >= 1")? as usize,
        ),
        None => None,
    };
    let linear = match option(&args, "--interpolant")?.as_deref() {
        None | Some("hermite") => false,
        Some("linear") => true,
        Some(other) => {
            return Err(format!(
                "unknown --interpolant {other} (known: hermite, linear)"
            ))
        }
    };
    let mut step_times = vec![times[0]];
    let mut dense_samples: Vec<Value> = Vec::new();
    let mut found: Vec<(String, f64)> = Vec::new();
    let sample =
        |t: f64, y: &State| json!({"t": t, "omega": &y[0..3], "alpha": &y[3..6], "beta": &y[6..9]});
    let started = Instant::now();
    let mut samples = vec![sample(times[0], &y)];
    let mut steps = 0u64;
    for w in times.windows(2) {
        let n = ((w[1] - w[0]) / step).ceil().max(1.0);
        let h = (w[1] - w[0]) / n;
        for j in 0..n as u64 {
            let next = rk_step(tableau, a, b, &y, h);
            let t0 = w[0] + j as f64 * h;
            for (name, dir) in &asked {
                let (e0, e1) = (event_fn(name, a, b, &y), event_fn(name, a, b, &next));
                if let (Some(e0), Some(e1)) = (e0, e1) {
                    if let Some(t) = hermite_zero(t0, h, e0, e1, dir) {
                        found.push((name.clone(), t));
                    }
                }
            }
            if let Some(k) = dense {
                let t1 = if j + 1 == n as u64 { w[1] } else { t0 + h };
                let (f0, f1) = (rhs(a, b, &y), rhs(a, b, &next));
                for i in 1..=k {
                    let t = t0 + (t1 - t0) * i as f64 / (k + 1) as f64;
                    let s = i as f64 / (k + 1) as f64;
                    let yi: State = std::array::from_fn(|c| {
                        if linear {
                            (1.0 - s) * y[c] + s * next[c]
                        } else {
                            let (s2, s3) = (s * s, s * s * s);
                            (2.0 * s3 - 3.0 * s2 + 1.0) * y[c]
                                + (s3 - 2.0 * s2 + s) * h * f0[c]
                                + (3.0 * s2 - 2.0 * s3) * next[c]
                                + (s3 - s2) * h * f1[c]
                        }
                    });
                    dense_samples.push(sample(t, &yi));
                }
                dense_samples.push(sample(t1, &next));
                step_times.push(t1);
            }
            y = next;
            steps += 1;
        }
        samples.push(sample(w[1], &y));
    }
    let seconds = started.elapsed().as_secs_f64();
    let mut answer = json!({
        "name": format!(
            "example-{}{}",
            tableau.name,
            if linear { "-linear" } else { "" }
        ),
        "version": concat!("example-adapter-rk4 ", env!("CARGO_PKG_VERSION")),
        "samples": samples,
        "stats": {"steps": steps, "rhs_evals": tableau.b.len() as u64 * steps, "integration_seconds": seconds},
    });
    if dense.is_some() {
        answer["stats"]["step_times"] = json!(step_times);
        answer["dense"] = Value::Array(dense_samples);
    }
    if req.get("events").is_some() {
        found.sort_by(|p, q| p.1.total_cmp(&q.1));
        if let Some(k) = drop {
            if k < found.len() {
                found.remove(k);
            }
        }
        let list: Vec<Value> = found
            .iter()
            .map(|(n, t)| json!({"name": n, "t": t}))
            .collect();
        answer["events"] = Value::Array(list);
    }
    Ok(answer)
}

fn main() {
    match run() {
        Ok(answer) => {
            let mut out = std::io::stdout().lock();
            serde_json::to_writer(&mut out, &answer).expect("stdout");
            writeln!(out).expect("stdout");
        }
        Err(e) => {
            eprintln!("example-adapter-rk4: {e}");
            std::process::exit(1);
        }
    }
}
