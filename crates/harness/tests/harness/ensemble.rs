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
    let base = Case::default_i_plus().with_grid(rsts_closed_form::Decimal::parse("3").unwrap(), 7);
    let plan = EnsemblePlan {
        n: 3,
        seed: 11,
        cameras: vec![Camera::IPlus, Camera::V, Camera::III],
        shard: None,
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

/// The report's JSON without what the clock decides: the rows' times and the bands' time
/// percentiles.
fn without_times(report: &rsts_harness::BenchReport) -> serde_json::Value {
    let mut v = serde_json::to_value(report).unwrap();
    for (list, keys) in [
        (
            "rows",
            &[
                "integration_seconds",
                "time_min",
                "time_median",
                "time_max",
                "wall_seconds",
            ][..],
        ),
        ("bands", &["time_p05", "time_median", "time_p95"][..]),
    ] {
        for item in v[list].as_array_mut().unwrap() {
            for key in keys {
                item.as_object_mut().unwrap().remove(*key);
            }
        }
    }
    v
}

/// A scratch directory of this test process.
fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!(
        "rsts-harness-ensemble-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An ensemble of 40 motions run in 4 shards (through their JSON files, as `rsts bench merge`
/// reads them) merges into the unsharded run's report: the same rows in the same order, fits
/// and error bands to the bit, the time bands the percentiles of the shards' own times. A row
/// altered after its shard was written is refused, and one altered with its digest forged
/// makes a report that is not the unsharded one; shards of another request, binary or count,
/// a shard missing or given twice, a whole report and an empty file are refused, naming them.
#[test]
fn forty_motions_in_four_shards_merge_into_the_unsharded_report() {
    use rsts_harness::bench::{bench_merge, BenchMergeRequest, BenchReport};
    use rsts_harness::ensemble::bands;
    use rsts_harness::shard::{digest, Shard};

    let request = |repeats: usize| BenchRequest {
        case: {
            let mut c = Case::default_i_plus();
            c.t_end = rsts_closed_form::Decimal::from_f64(2.0_f64).unwrap();
            c.samples = 5;
            c
        },
        methods: [MethodName::Dop853, MethodName::TaylorF64]
            .map(BenchMethod::BuiltIn)
            .into(),
        tolerances: vec![1e-9, 1e-12],
        repeats,
        digits: None,
        events: Vec::new(),
    };
    let plan = |shard: Option<Shard>| EnsemblePlan {
        n: 40,
        seed: 2013,
        cameras: Vec::new(),
        shard,
    };
    let whole = bench_ensemble(request(1), &plan(None), &mut Quiet).unwrap();
    assert_eq!(whole.rows.len(), 40 * 4);
    assert!(whole.shard.is_none());

    let dir = scratch("shards");
    let write = |name: &str, report: &BenchReport| {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string_pretty(report).unwrap()).unwrap();
        path
    };
    let mut files = Vec::new();
    let mut shards = Vec::new();
    for k in 1..=4 {
        let sh = Shard { k, n: 4 };
        let part = bench_ensemble(request(1), &plan(Some(sh)), &mut Quiet).unwrap();
        let motions: Vec<usize> = part.rows.iter().map(|r| r.motion.unwrap()).collect();
        assert_eq!(motions.len(), 10 * 4, "shard {sh}: its 10 motions");
        assert!(
            motions.iter().all(|m| m % 4 == k - 1),
            "shard {sh}: {motions:?}"
        );
        assert_eq!(part.shard.as_ref().unwrap().shard(), sh);
        assert_eq!(
            part.ensemble, whole.ensemble,
            "every shard draws the whole ensemble"
        );
        files.push(write(&format!("shard-{k}.json"), &part));
        shards.push(part);
    }
    // In any order.
    let given = |files: Vec<std::path::PathBuf>| BenchMergeRequest { shards: files };
    let mut reversed = files.clone();
    reversed.reverse();
    let merged = bench_merge(&given(reversed)).unwrap();
    assert!(merged.notes.is_empty(), "{:?}", merged.notes);
    let merged = merged.report;
    assert_eq!(without_times(&merged), without_times(&whole));
    assert_eq!(merged.labels, whole.labels);
    assert_eq!(merged.bands.len(), 4);
    for (m, w) in merged.bands.iter().zip(&whole.bands) {
        assert_eq!(
            (&m.method, m.tolerance, m.motions),
            (&w.method, w.tolerance, 40)
        );
        for (x, y) in [
            (m.error_p05, w.error_p05),
            (m.error_median, w.error_median),
            (m.error_p95, w.error_p95),
        ] {
            assert_eq!(x.to_bits(), y.to_bits(), "{m:?} against {w:?}");
        }
        // The time band: percentiles of the shards' own times of that method and tolerance.
        let times: Vec<f64> = shards
            .iter()
            .flat_map(|s| &s.rows)
            .filter(|r| r.method == m.method && r.tolerance == m.tolerance)
            .map(|r| r.integration_seconds)
            .collect();
        assert_eq!(times.len(), 40);
        assert_eq!(m.time_median.to_bits(), percentile(&times, 0.5).to_bits());
        assert_eq!(m.time_p95.to_bits(), percentile(&times, 0.95).to_bits());
    }
    assert_eq!(merged.fits, whole.fits);

    // Shard 2 altered: the row at the lower middle of dop853's 1e-9 band, one ulp up.
    let band = &whole.bands[0];
    let mut errors: Vec<(f64, usize)> = whole
        .rows
        .iter()
        .filter(|r| r.method == band.method && r.tolerance == band.tolerance)
        .map(|r| (r.max_error, r.motion.unwrap()))
        .collect();
    errors.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (_, motion) = errors[19];
    let k = motion % 4 + 1;
    let mut altered = shards[k - 1].clone();
    let row = altered
        .rows
        .iter_mut()
        .find(|r| {
            r.motion == Some(motion) && r.method == band.method && r.tolerance == band.tolerance
        })
        .unwrap();
    row.max_error = f64::from_bits(row.max_error.to_bits() + 1);
    let mut with_altered = files.clone();
    with_altered[k - 1] = write("altered.json", &altered);
    let err = bench_merge(&given(with_altered.clone()))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&format!("shard {k}/4"))
            && err.contains("altered.json")
            && err.contains("altered afterwards"),
        "{err}"
    );
    // Its digest forged to match: the merge goes through, but it is not the unsharded report.
    let info = altered.shard.as_mut().unwrap();
    info.rows = digest(serde_json::to_string(&altered.rows).unwrap().as_bytes());
    with_altered[k - 1] = write("forged.json", &altered);
    let forged = bench_merge(&given(with_altered)).unwrap().report;
    assert_ne!(without_times(&forged), without_times(&whole));
    assert_ne!(
        forged.bands[0].error_median.to_bits(),
        whole.bands[0].error_median.to_bits(),
        "the median moved with its row"
    );
    assert_eq!(
        forged.bands[1..],
        bands(&whole.rows)[1..]
            .iter()
            .map(|b| {
                let mut b = b.clone();
                let f = forged
                    .bands
                    .iter()
                    .find(|f| f.method == b.method && f.tolerance == b.tolerance)
                    .unwrap();
                (b.time_p05, b.time_median, b.time_p95) = (f.time_p05, f.time_median, f.time_p95);
                b
            })
            .collect::<Vec<_>>()[..],
        "the other bands are untouched"
    );

    let refused =
        |paths: Vec<std::path::PathBuf>| bench_merge(&given(paths)).unwrap_err().to_string();
    // Another request: shard 3 with two repeats.
    let other = bench_ensemble(request(2), &plan(Some(Shard { k: 3, n: 4 })), &mut Quiet).unwrap();
    let mut mixed = files.clone();
    mixed[2] = write("other-request.json", &other);
    let err = refused(mixed);
    assert!(
        err.contains("different requests") && err.contains("other-request.json"),
        "{err}"
    );
    // Another binary.
    let mut rebuilt = shards[3].clone();
    rebuilt.environment.commit = "0123456789ab".into();
    let mut mixed = files.clone();
    mixed[3] = write("rebuilt.json", &rebuilt);
    let err = refused(mixed);
    assert!(
        err.contains("different binaries") && err.contains("rebuilt.json"),
        "{err}"
    );
    // Another count: shard 1 of 5.
    let fifth = bench_ensemble(request(1), &plan(Some(Shard { k: 1, n: 5 })), &mut Quiet).unwrap();
    let err = refused(vec![write("fifth.json", &fifth), files[1].clone()]);
    assert!(err.contains("different counts"), "{err}");
    // Missing, twice.
    let err = refused(vec![files[0].clone(), files[1].clone(), files[3].clone()]);
    assert!(err.contains("missing shard(s) 3/4"), "{err}");
    let err = refused(vec![
        files[0].clone(),
        files[1].clone(),
        files[1].clone(),
        files[2].clone(),
        files[3].clone(),
    ]);
    assert!(err.contains("shard 2/4 given twice"), "{err}");
    // A whole report, an empty file, a file that is not JSON.
    let err = refused(vec![write("whole.json", &whole)]);
    assert!(
        err.contains("whole.json is a whole report, not a shard"),
        "{err}"
    );
    let empty = dir.join("empty.json");
    std::fs::write(&empty, "").unwrap();
    let err = refused(vec![files[0].clone(), empty]);
    assert!(err.contains("empty.json: empty"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
