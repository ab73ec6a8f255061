use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_dynamics::{Fields, VectorField};
use rug::Float;

fn residual(mo: &ExplicitMotion<Float>, t: f64) -> f64 {
    let bits = 200;
    let s = mo.at_with_derivative(&Float::with_val(bits, t));
    let x: [Float; 9] = std::array::from_fn(|k| {
        let v = [&s.omega, &s.alpha, &s.beta][k / 3];
        v[k % 3].re.clone()
    });
    let dx: [Float; 9] = std::array::from_fn(|k| {
        let v = [&s.omega, &s.alpha, &s.beta][k / 3];
        v[k % 3].eps.clone()
    });
    let f = VectorField::new(&Fields {
        a: mo.constants.a.clone(),
        b: mo.constants.b.clone(),
    });
    let fx = f.eval(&x);
    (0..9)
        .map(|k| (dx[k].clone() - &fx[k]).abs().to_f64())
        .fold(0.0, f64::max)
}

fn main() {
    let a: f64 = std::env::var("A")
        .map(|s| s.parse().unwrap())
        .unwrap_or(1.0);
    let b: f64 = std::env::var("B")
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.5);
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    if args.len() == 2 {
        let mo = ExplicitMotion::new(
            Float::with_val(200, a),
            Float::with_val(200, b),
            Float::with_val(200, args[0]),
            Float::with_val(200, args[1]),
            TorusChoice::default(),
        );
        match mo {
            Ok(mo) => {
                println!(
                    "{} tori {} res {:e} {:e}",
                    mo.camera,
                    mo.tori,
                    residual(&mo, 0.3),
                    residual(&mo, 2.7)
                );
            }
            Err(e) => println!("{e}"),
        }
        return;
    }
    let mut seen = std::collections::HashMap::new();
    for i in 0..80 {
        for j in 0..80 {
            let m = -3.0 + 6.0 * i as f64 / 79.0 + 0.0123;
            let h = -3.0 + 8.0 * j as f64 / 79.0 + 0.00731;
            if let Ok(mo) = ExplicitMotion::new(a, b, m, h, TorusChoice::default()) {
                seen.entry(mo.camera.label()).or_insert((m, h, mo.tori));
            }
        }
    }
    for (k, v) in &seen {
        println!("{k}: m={} h={} tori={}", v.0, v.1, v.2);
    }
}
