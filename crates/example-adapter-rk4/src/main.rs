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
//! The step is rtol^(1/4) (at most 0.01), shortened so that every interval between two requested
//! times is a whole number of steps; `--step H` sets it instead.

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

fn rk4_step(a: f64, b: f64, y: &State, h: f64) -> State {
    let add = |y: &State, k: &State, c: f64| -> State { std::array::from_fn(|i| y[i] + c * k[i]) };
    let k1 = rhs(a, b, y);
    let k2 = rhs(a, b, &add(y, &k1, h / 2.0));
    let k3 = rhs(a, b, &add(y, &k2, h / 2.0));
    let k4 = rhs(a, b, &add(y, &k3, h));
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// A number given as a JSON number or a decimal string.
fn num(v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => n.as_f64().ok_or("bad number".into()),
        Value::String(s) => s.parse().map_err(|_| format!("'{s}' is not a number")),
        _ => Err(format!("expected a number, got {v}")),
    }
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
    let step = match args.iter().position(|s| s == "--step") {
        Some(i) => args
            .get(i + 1)
            .ok_or("--step needs a value")?
            .parse()
            .map_err(|_| "bad --step")?,
        None => num(&req["rtol"])?.powf(0.25).min(0.01),
    };
    let sample =
        |t: f64, y: &State| json!({"t": t, "omega": &y[0..3], "alpha": &y[3..6], "beta": &y[6..9]});
    let started = Instant::now();
    let mut samples = vec![sample(times[0], &y)];
    let mut steps = 0u64;
    for w in times.windows(2) {
        let n = ((w[1] - w[0]) / step).ceil().max(1.0);
        let h = (w[1] - w[0]) / n;
        for _ in 0..n as u64 {
            y = rk4_step(a, b, &y, h);
            steps += 1;
        }
        samples.push(sample(w[1], &y));
    }
    let seconds = started.elapsed().as_secs_f64();
    Ok(json!({
        "name": "example-rk4",
        "samples": samples,
        "stats": {"steps": steps, "rhs_evals": 4 * steps, "integration_seconds": seconds},
    }))
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
