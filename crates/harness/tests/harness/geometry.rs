//! The geometry of the error (issue 11): synthetic trajectories with a known split (a pure
//! phase shift, a pure departure off N) come back as such; real runs split as the normal type
//! says (elliptic I+: drift along the torus, ~t²; hyperbolic V: departure from N, e^{λt}); the
//! split is consistent with the state error at every sample; MPFR runs are measured in their
//! own precision.

use rsts_closed_form::manifold::NormalType;
use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_dynamics::State;
use rsts_harness::growth::Model;
use rsts_harness::{analyse, compare, Analysis, Case, NoObserver, Observer, RunInfo, SampleRecord};
use rug::Float;

fn case(m: f64, h: f64, t_end: f64, samples: usize) -> Case {
    Case::binary([1.0, 0.5, m, h], 0, [0.4, 1.3], t_end, samples).unwrap()
}

fn config(method: MethodName, tol: f64) -> MethodConfig {
    MethodConfig::new(method, Tolerances::new(tol, tol).unwrap(), None).unwrap()
}

fn info(digits: u32) -> RunInfo {
    RunInfo {
        method: "synthetic".into(),
        rtol: None,
        atol: None,
        digits,
    }
}

const BITS: u32 = 200;

fn times(c: &Case) -> Vec<Float> {
    (0..c.samples)
        .map(|k| Float::with_val(BITS, c.t_end_f64() * k as f64 / (c.samples - 1) as f64))
        .collect()
}

#[derive(Default)]
struct Records(Vec<SampleRecord>);
impl Observer for Records {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        self.0.push(*r);
        Ok(())
    }
}

#[test]
fn a_time_shift_is_a_pure_phase_error() {
    // The exact motion τ late: on N (distance ~ round-off), phase error ν·τ on both angles.
    let c = case(-0.7092, 1.5643, 10.0, 21);
    let tau = 1e-6;
    let a = Analysis::for_case(&c, BITS, info(15)).unwrap();
    let nu = a.motion().frequencies().map(|x| x.to_f64());
    let ts = times(&c);
    let states: Vec<State<Float>> = ts
        .iter()
        .map(|t| a.exact_state(&(t.clone() + Float::with_val(BITS, tau))))
        .collect();
    let mut rec = Records::default();
    let r = analyse(a, &ts, &states, &mut rec).unwrap();
    for s in &rec.0 {
        let e = &s.errors;
        assert!(
            e.distance_from_n < 1e-14,
            "t = {}: off N by {:e}",
            s.t,
            e.distance_from_n
        );
        for (i, (got, nu)) in e.phase_error.iter().zip(nu).enumerate() {
            let want = nu * tau;
            assert!(
                (got - want).abs() < 1e-6 * want + 1e-14,
                "t = {}: Δψ{} = {got:e}, ν τ = {want:e}",
                s.t,
                i + 1
            );
        }
        assert!((e.along_n - e.state_error).abs() < 1e-3 * e.state_error + 1e-15);
    }
    let split = r.error_split.unwrap();
    assert_eq!(split.dominant, "drift along the torus", "{split:?}");
}

#[test]
fn a_move_off_n_is_a_pure_departure() {
    // The exact motion moved by 1e-9 along ω₃ (off N: d ≠ 0): departure ≈ the move's normal
    // part, phases unchanged to first order.
    let c = case(0.3, -0.375, 10.0, 21);
    let a = Analysis::for_case(&c, BITS, info(15)).unwrap();
    let ts = times(&c);
    let eps = 1e-9;
    let states: Vec<State<Float>> = ts
        .iter()
        .map(|t| {
            let mut s = a.exact_state(t);
            s.omega[2] += eps;
            s
        })
        .collect();
    let mut rec = Records::default();
    analyse(a, &ts, &states, &mut rec).unwrap();
    for s in &rec.0 {
        let e = &s.errors;
        assert!(
            e.distance_from_n > 1e-12 && e.distance_from_n <= eps * (1.0 + 1e-6),
            "t = {}: {:e}",
            s.t,
            e.distance_from_n
        );
        assert!(e.phase_error[0].abs() < 1e-8 && e.phase_error[1].abs() < 1e-8);
        assert!(e.x_phi > 1e-13, "|X_Φ| = {:e}", e.x_phi);
    }
}

#[test]
fn elliptic_runs_drift_along_the_torus_and_hyperbolic_runs_depart_from_n() {
    let mut rec = Records::default();
    let ell = compare(
        &case(0.3, -0.375, 1000.0, 2001),
        &config(MethodName::Dop853, 1e-12),
        &mut rec,
    )
    .unwrap();
    let normal = ell.normal.as_ref().unwrap();
    assert_eq!(normal.kind, NormalType::Elliptic);
    assert!(normal.distance_from_n.max < 1e-9, "{normal:?}");
    let phase = ell.phase_error.as_ref().unwrap().growth.unwrap();
    assert_eq!(phase.kind, Model::Polynomial);
    assert!((phase.exponent - 2.0).abs() < 0.3, "{phase:?}");
    let split = ell.error_split.as_ref().unwrap();
    assert_eq!(split.dominant, "drift along the torus");
    assert!(split.summary.contains("quadratic"), "{}", split.summary);
    // The parts bound the state error at every sample (max-norms: triangle inequality), and
    // the departure is at most the error itself (the exact state is a point of N).
    for s in &rec.0 {
        let e = &s.errors;
        assert!(
            e.state_error <= (e.along_n + e.distance_from_n) * (1.0 + 1e-6) + 1e-15,
            "t = {}",
            s.t
        );
        assert!(
            e.distance_from_n <= 3.0 * e.state_error + 1e-15,
            "t = {}",
            s.t
        );
    }
    let hyp = compare(
        &case(-0.7092, 1.5643, 300.0, 1501),
        &config(MethodName::Dop853, 1e-12),
        &mut NoObserver,
    )
    .unwrap();
    let normal = hyp.normal.as_ref().unwrap();
    assert_eq!(normal.kind, NormalType::Hyperbolic);
    let g = normal.growth.unwrap();
    assert_eq!(g.kind, Model::Exponential, "{normal:?}");
    // docs/stability.md: the state error grows like e^{0.23…0.26 t} at this point.
    assert!(g.rate > 0.18 && g.rate < 0.3, "{g:?}");
    let split = hyp.error_split.as_ref().unwrap();
    assert_eq!(split.dominant, "departure from N", "{split:?}");
    assert!(split.summary.contains("normally hyperbolic"));
}

#[test]
fn an_mpfr_run_is_measured_in_its_own_precision() {
    let c = case(-0.7092, 1.5643, 5.0, 41);
    let mut cfg = config(MethodName::TaylorMp, 1e-30);
    cfg.digits = Some(40);
    let mut rec = Records::default();
    let r = compare(&c, &cfg, &mut rec).unwrap();
    let normal = r.normal.as_ref().unwrap();
    // Far below f64: the geometry is computed at the integrator's digits.
    assert!(
        normal.distance_from_n.max < 1e-26 && normal.distance_from_n.max > 0.0,
        "{normal:?}"
    );
    let phase = r.phase_error.as_ref().unwrap();
    assert!(phase.psi1.max < 1e-24 && phase.psi1.max > 0.0, "{phase:?}");
    // The first 32 samples and then every 2nd, and the last one, carry the geometry.
    let with: Vec<usize> = rec
        .0
        .iter()
        .filter(|s| s.errors.distance_from_n.is_finite())
        .map(|s| s.index)
        .collect();
    assert!(with.len() >= 36 && with.len() < 41, "{with:?}");
}

/// The warm start of the f64 geometry (each sample of a chunk projected from the nearest point
/// of the one before, `Geometry::evaluate_f64`) gives the samples of a dopri5 run of camera V
/// (m < 0, its error grows like e^{0.23 t} and saturates) the nearest points of the cold start
/// from the exact angles, to the round-off, and to the same samples: after the error has
/// saturated, a warm start from a large phase error would find other nearest points.
#[test]
fn the_warm_start_finds_the_nearest_points_of_the_cold_start() {
    use rsts_dynamics::integrators::Problem;
    use rsts_dynamics::scalar::DoubleDouble;
    use rsts_harness::geometry::{Geometry, WarmStart};
    use rsts_harness::Integrator;
    let c = case(-0.7092, 1.5643, 150.0, 3001);
    let a = Analysis::for_case(&c, BITS, info(15)).unwrap();
    let (motion, fields) = c.reference_motion(BITS).unwrap();
    let ts: Vec<f64> = times(&c).iter().map(|t| t.to_f64()).collect();
    let problem = Problem {
        fields,
        initial: a.exact_state(&Float::with_val(BITS, 0)),
    };
    let run = config(MethodName::Dopri5, 1e-9)
        .integrate(&problem, &ts)
        .unwrap();
    let geometry = Geometry::new(&motion, 15).unwrap();
    let mut warm = WarmStart::default();
    let (mut with, mut without, mut warm_starts) = (0, 0, 0);
    let mut largest = [0.0f64; 5];
    for (k, (t, state)) in ts.iter().zip(&run.states).enumerate() {
        if k % 64 == 0 {
            warm = WarmStart::default();
        }
        warm_starts += usize::from(warm.is_warm());
        let exact = a
            .exact_state(&Float::with_val(BITS, *t))
            .map(DoubleDouble::from_float);
        let x: [f64; 9] = state.map(|v| v.to_f64()).to_array();
        let g = geometry.evaluate_f64(*t, &x, &exact, &mut warm).unwrap();
        let cold = geometry
            .evaluate_f64(*t, &x, &exact, &mut WarmStart::default())
            .unwrap();
        match (g.phase_error, cold.phase_error) {
            (Some(p), Some(q)) => {
                let gaps = [
                    (p[0] - q[0]).abs().max((p[1] - q[1]).abs()),
                    (g.dm - cold.dm).abs().max((g.dh - cold.dh).abs()),
                    (g.distance_from_n - cold.distance_from_n).abs(),
                    (g.along_n - cold.along_n).abs(),
                    (g.x_phi - cold.x_phi).abs(),
                ];
                for (l, d) in largest.iter_mut().zip(gaps) {
                    *l = l.max(d);
                }
                assert!(gaps.iter().all(|d| *d < 1e-12), "t = {t}: {gaps:?}");
                with += 1;
            }
            (None, None) => without += 1,
            (p, q) => panic!("t = {t}: warm {p:?}, cold {q:?}"),
        }
    }
    eprintln!(
        "{with} samples with a nearest point ({warm_starts} warm starts), {without} without; \
         largest |Δψ|, |Δ(δm, δh)|, |Δdistance|, |Δalong|, |ΔX_Φ|: {largest:?}"
    );
    assert!(with >= 500 && without >= 500 && warm_starts * 2 >= with);
}
