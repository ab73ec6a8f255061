//! The tabulated torus of the projector (stop 29) against the closed form: in every camera and
//! torus, its separated points (v, F, G) are within two ulps of their size of the 160-bit
//! values, its states at least as close to them as the f64 AGM path's, and its derivative
//! columns (∂/∂ψ₁, ∂/∂ψ₂, ∂/∂m, ∂/∂h) those of the AGM path over dual numbers and jets; also
//! 1e-9 from Σ, where a modulus is within 1e-9 of 1 (sn steepens: up to 512 cells).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_closed_form::manifold::{Projector, TorusMap};
use rsts_closed_form::{ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use rsts_dynamics::Real;
use rug::Float;

const BITS: u32 = 160;

/// Every torus of every camera point and two points 1e-9 from Σ (a = 1, b = ½: the hyperbola
/// ℓ² = 0 and the inner curve h = 2b − r²m): (label, motion in f64, motion at 160 bits).
fn tori() -> Vec<(String, ExplicitMotion<f64>, ExplicitMotion<Float>)> {
    let near_sigma = [
        ("hyperbola", -1.0, (1e-9 - 1.0 - 2.0 * 1.25) / -2.0),
        ("inner-b", 0.3, -0.75 * 0.3 + 1.0 - 1e-9),
    ];
    let mut out = Vec::new();
    let cameras = EXAMPLE_POINTS_A1_B05.map(|(c, m, h)| (c.to_string(), m, h));
    let near = near_sigma.map(|(c, m, h)| (c.to_string(), m, h));
    for (label, m, h) in cameras.into_iter().chain(near) {
        for torus in 0..4 {
            let choice = TorusChoice {
                torus,
                phase1: 0.0,
                phase2: 0.0,
            };
            let Ok(motion) = ExplicitMotion::new(1.0, 0.5, m, h, choice) else {
                continue;
            };
            let f = |x: f64| Float::with_val(BITS, x);
            let fine = ExplicitMotion::new(f(1.0), f(0.5), f(m), f(h), choice).unwrap();
            out.push((format!("{label} ({m}, {h}) torus {torus}"), motion, fine));
        }
    }
    out
}

#[test]
fn the_table_is_within_two_ulps_and_as_accurate_as_the_agm_path_in_every_camera() {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let tori = tori();
    assert!(tori.len() >= 20, "{} tori", tori.len());
    for (what, motion, fine) in &tori {
        let projector = Projector::new(motion).unwrap();
        let table = projector
            .table()
            .unwrap_or_else(|| panic!("{what}: no table"));
        let (agm, exact) = (TorusMap::of_motion(motion), TorusMap::of_motion(fine));
        let (mut table_err, mut agm_err, mut size) = (0.0f64, 0.0f64, 0.0f64);
        let mut point_err = [[0.0f64; 3]; 2];
        let mut point_size = [[0.0f64; 3]; 2];
        for _ in 0..400 {
            let psi: [f64; 2] = std::array::from_fn(|_| rng.gen_range(0.0..std::f64::consts::TAU));
            let truth = exact.state_at(&psi.map(|p| Float::with_val(BITS, p)));
            let (t, a) = (table.state_at(&psi), agm.state_at(&psi));
            for k in 0..9 {
                let x = truth[k].to_f64();
                table_err = table_err.max((t[k] - x).abs());
                agm_err = agm_err.max((a[k] - x).abs());
                size = size.max(x.abs());
            }
            for i in 0..2 {
                let p = table.point(i, psi[i]);
                let q = exact.point(i, &Float::with_val(BITS, psi[i]));
                for (j, (x, y)) in [(p.v, q.v), (p.f, q.f), (p.g, q.g)].iter().enumerate() {
                    point_err[i][j] = point_err[i][j].max((x - y.to_f64()).abs());
                    point_size[i][j] = point_size[i][j].max(y.to_f64().abs());
                }
            }
        }
        for i in 0..2 {
            for j in 0..3 {
                let ulps = point_err[i][j] / (point_size[i][j] * f64::EPSILON);
                assert!(
                    ulps <= 2.0,
                    "{what}: variable {i} function {j}: {ulps:.2} ulps"
                );
            }
        }
        // The state: the formulas' own rounding in f64 on top of the points (the AGM path errs
        // by up to 4e-15·|x|).
        assert!(
            table_err <= agm_err.max(2e-15 * size) && table_err <= 3e-15 * size,
            "{what}: table {table_err:e}, AGM path {agm_err:e}, |x| {size}"
        );
    }
}

#[test]
fn the_derivative_columns_are_those_of_the_agm_path() {
    let mut rng = ChaCha8Rng::seed_from_u64(2029);
    for (what, motion, _) in &tori() {
        // 1e-9 from Σ the f64 jets of the AGM path lose digits (|∂C/∂m| ~ 1e7).
        let tolerance = if what.starts_with(['I', 'V']) {
            1e-9
        } else {
            1e-7
        };
        let projector = Projector::new(motion).unwrap();
        let table = projector.table().unwrap();
        for _ in 0..200 {
            let psi: [f64; 2] = std::array::from_fn(|_| rng.gen_range(0.0..std::f64::consts::TAU));
            let (_, columns) = table.state_and_derivatives(&psi);
            let agm = projector.agm_derivatives(&psi);
            for (c, (x, y)) in columns.iter().zip(&agm).enumerate() {
                let norm = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let gap = x
                    .iter()
                    .zip(y)
                    .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
                assert!(
                    gap <= tolerance * norm.max(1.0),
                    "{what} ψ = {psi:?}: column {c} off by {gap:e} (|column| {norm:e})"
                );
            }
        }
    }
}
