//! Ensembles: the motions drawn (reproducible, in their cameras, on existing tori), the refusals,
//! the percentiles against order statistics, and each motion measured exactly as a comparison
//! in one piece measures it.

use rsts_closed_form::diagram::camera_at;
use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice};
use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_harness::bench::{bench_ensemble, EnsemblePlan, Quiet};
use rsts_harness::ensemble::{draw_ensemble, percentile, EnsembleError, SplitMix64, MAX_MOTIONS};
use rsts_harness::{
    compare_integrator, BenchMethod, BenchRequest, Case, CompareOptions, NoObserver,
};

fn camera(label: &str) -> Camera {
    label.parse().unwrap()
}

#[test]
fn motions_lie_in_their_cameras_on_existing_tori_and_repeat_with_the_seed() {
    let cameras = [Camera::IPlus, Camera::V, Camera::VI, Camera::IIMinus];
    let e = draw_ensemble(1.0, 0.5, &cameras, 12, 7).unwrap();
    assert_eq!((e.n, e.seed, e.motions.len()), (12, 7, 12));
    for (k, mo) in e.motions.iter().enumerate() {
        let c = cameras[k % cameras.len()];
        assert_eq!(mo.camera, c.label(), "round robin over the cameras");
        assert_eq!(camera_at(1.0, 0.5, mo.m, mo.h), Some(c), "{mo:?}");
        let motion = ExplicitMotion::<f64>::new(1.0, 0.5, mo.m, mo.h, TorusChoice::default())
            .expect("admissible, off Σ");
        assert_eq!(motion.camera, c);
        assert!(mo.torus < motion.tori, "{mo:?}: {} tori", motion.tori);
        for p in [mo.phase1, mo.phase2] {
            assert!((0.0..std::f64::consts::TAU).contains(&p), "{p}");
        }
    }
    assert_eq!(draw_ensemble(1.0, 0.5, &cameras, 12, 7).unwrap(), e);
    let other = draw_ensemble(1.0, 0.5, &cameras, 12, 8).unwrap();
    assert!(other.motions.iter().zip(&e.motions).all(|(a, b)| a != b));
    // All nine cameras by default, the thin camera V included.
    let all = draw_ensemble(1.0, 0.5, &[], 9, 1).unwrap();
    let labels: Vec<&str> = all.motions.iter().map(|m| m.camera.as_str()).collect();
    assert_eq!(
        labels,
        Camera::ALL.iter().map(|c| c.label()).collect::<Vec<_>>()
    );
}

#[test]
fn bad_ensembles_are_refused_naming_the_option() {
    let count = |n| draw_ensemble(1.0, 0.5, &[], n, 1).unwrap_err();
    assert_eq!(count(0).parameters(), ["ensemble"]);
    assert_eq!(count(MAX_MOTIONS + 1).parameters(), ["ensemble"]);
    assert!(draw_ensemble(1.0, 0.5, &[], MAX_MOTIONS, 1).is_ok());
    let twice = draw_ensemble(1.0, 0.5, &[Camera::V, Camera::V], 2, 1).unwrap_err();
    assert_eq!(
        twice,
        EnsembleError::Cameras("camera V is given twice".into())
    );
    // For b ≪ a camera I+ is a sliver along Σ: no point keeps a cell's width from it.
    let none = draw_ensemble(1.0, 0.01, &[camera("I+"), camera("IV+")], 2, 1).unwrap_err();
    assert_eq!(none.parameters(), ["cameras"]);
    assert!(none.to_string().contains("camera I+ "), "{none}");
    assert!(!none.to_string().contains("IV+"), "{none}");
    assert_eq!(
        draw_ensemble(1.0, 0.0, &[], 2, 1).unwrap_err().parameters(),
        ["a", "b"]
    );
}

/// For n = 20k + 1 values the type-7 percentiles at 5 %, 50 % and 95 % fall exactly on ranks
/// k, 10k and 19k of the sorted list: checked on random lists against the sort alone.
#[test]
fn percentiles_at_exact_ranks_are_order_statistics() {
    let mut rng = SplitMix64::new(3);
    for k in 1..6 {
        let n = 20 * k + 1;
        let v: Vec<f64> = (0..n).map(|_| rng.uniform() * 1e3 - 500.0).collect();
        let mut sorted = v.clone();
        sorted.sort_by(f64::total_cmp);
        assert_eq!(percentile(&v, 0.05), sorted[k]);
        assert_eq!(percentile(&v, 0.5), sorted[10 * k]);
        assert_eq!(percentile(&v, 0.95), sorted[19 * k]);
    }
}

/// Every row of the ensemble is the comparison of its motion in one piece: the same error to
/// the bit, the same steps and evaluations; the bands summarise the rows per method and
/// tolerance (type-7 percentiles of three values, worked by hand).
#[test]
fn each_motion_is_measured_as_a_comparison_in_one_piece() {
    let base = Case {
        t_end: 3.0,
        samples: 7,
        ..Case::default_i_plus()
    };
    let plan = EnsemblePlan {
        n: 3,
        seed: 11,
        cameras: vec![Camera::IPlus, Camera::V, Camera::III],
    };
    let request = BenchRequest {
        case: base.clone(),
        methods: [
            MethodName::Dop853,
            MethodName::TaylorF64,
            MethodName::TaylorDd,
        ]
        .map(BenchMethod::BuiltIn)
        .into(),
        tolerances: vec![1e-9, 1e-20],
        repeats: 1,
        digits: None,
        events: Vec::new(),
    };
    let report = bench_ensemble(request, &plan, &mut Quiet).unwrap();
    let e = report.ensemble.as_ref().unwrap();
    assert_eq!(e, &draw_ensemble(1.0, 0.5, &plan.cameras, 3, 11).unwrap());
    // dop853 and taylor-f64 skip 1e-20 (below their round-off): 4 runs per motion.
    assert_eq!(report.rows.len(), 12);
    for r in &report.rows {
        let k = r.motion.expect("every row names its motion");
        let case = e.case(&base, k);
        let method = r.method.parse::<MethodName>().unwrap();
        let tol = Tolerances::new(r.tolerance, r.tolerance).unwrap();
        let mut config = MethodConfig::new(method, tol, None).unwrap();
        let report = compare_integrator(
            &case,
            &mut config,
            &CompareOptions { pieces: 1 },
            &mut NoObserver,
        )
        .unwrap();
        assert_eq!(
            r.max_error.to_bits(),
            report.max_state_error.to_bits(),
            "motion {k} {} at {:e}: {:e} against {:e}",
            r.method,
            r.tolerance,
            r.max_error,
            report.max_state_error
        );
        assert!(r.max_error > 0.0);
        assert!(
            r.steps.is_some() && r.rhs_evals.is_some(),
            "a built-in counts"
        );
        assert_eq!(r.steps, report.steps);
        assert_eq!(r.rhs_evals, report.rhs_evals);
    }
    assert_eq!(report.bands.len(), 4);
    for band in &report.bands {
        let of: Vec<_> = report
            .rows
            .iter()
            .filter(|r| r.method == band.method && r.tolerance == band.tolerance)
            .collect();
        let mut errors: Vec<f64> = of.iter().map(|r| r.max_error).collect();
        errors.sort_by(f64::total_cmp);
        assert_eq!(band.motions, 3);
        assert_eq!(band.error_median, errors[1]);
        // r = 0.05·2 = 0.1 and r = 0.95·2 = 1.9 between the three sorted values.
        let p05 = errors[0] + 0.1 * (errors[1] - errors[0]);
        let p95 = errors[1] + 0.9 * (errors[2] - errors[1]);
        assert!((band.error_p05 - p05).abs() <= 1e-15 * p05, "{band:?}");
        assert!((band.error_p95 - p95).abs() <= 1e-15 * p95, "{band:?}");
        let mut times: Vec<f64> = of.iter().map(|r| r.integration_seconds).collect();
        times.sort_by(f64::total_cmp);
        assert_eq!(band.time_median, times[1]);
    }
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["ensemble"]["n"], 3);
    assert_eq!(json["ensemble"]["seed"], 11);
    assert_eq!(json["rows"][4]["motion"], 1);
    for key in ["m", "h", "torus", "phase1", "phase2", "camera"] {
        assert!(json["ensemble"]["motions"][0].get(key).is_some(), "{key}");
    }
    for key in [
        "method",
        "tolerance",
        "error_p05",
        "error_median",
        "error_p95",
        "time_median",
    ] {
        assert!(json["bands"][0].get(key).is_some(), "{key}");
    }
}
