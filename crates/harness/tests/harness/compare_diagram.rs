//! The diagram of a comparison (`rsts compare --svg`): its curves are the report's figures at
//! every sample (their largest values are the report's maxima), and it says which run it is.

use rsts_dynamics::integrators::{MethodConfig, MethodName, Tolerances};
use rsts_harness::compare_diagram::{chart, write_svg, Recorder};
use rsts_harness::{compare, Case, NoObserver};

fn peak(points: &[(f64, f64)]) -> f64 {
    points.iter().map(|p| p.1).fold(0.0, f64::max)
}

#[test]
fn the_curves_peak_at_the_reports_maxima_and_the_title_names_the_run() {
    let case = Case::binary([1.0, 0.5, 0.3, -0.375], 0, [0.0, 0.0], 20.0, 201).unwrap();
    let config = MethodConfig::new(
        MethodName::Dopri5,
        Tolerances::new(1e-8, 1e-9).unwrap(),
        None,
    )
    .unwrap();
    let mut inner = NoObserver;
    let mut recorder = Recorder::new(&mut inner, 201);
    let report = compare(&case, &config, &mut recorder).unwrap();
    let s = &recorder.series;
    for curve in [&s.state_error, &s.drift_h, &s.drift_k, &s.drift_g] {
        assert_eq!(curve.len(), 201);
        assert_eq!(curve.first().unwrap().0, 0.0);
        assert_eq!(curve.last().unwrap().0, 20.0);
    }
    assert_eq!(peak(&s.state_error), report.max_state_error);
    assert_eq!(peak(&s.drift_h), report.drift.h);
    assert_eq!(peak(&s.drift_k), report.drift.k);
    assert_eq!(peak(&s.drift_g), report.drift.g);
    assert_eq!(s.state_error.last().unwrap().1, report.final_state_error);

    let c = chart(&case.motion, &report, s);
    let (title, subtitle) = c.title.split_once('\n').unwrap();
    assert_eq!(
        title,
        "dopri5 at rtol = 1e-8, atol = 1e-9 against the exact motion"
    );
    assert_eq!(
        subtitle,
        "camera I+: a = 1, b = 0.5, m = 0.3, h = −0.375, torus 0"
    );
    assert_eq!(c.series.len(), 4);
    assert!(c.series.iter().all(|s| !s.label.contains("throughout")));

    let dir = std::env::temp_dir().join(format!("rsts-diagram-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("compare.svg");
    write_svg(&path, &case.motion, &report, s).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{svg:.80}"
    );
    assert!(svg.contains("time t") && svg.contains("drift of K"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_curve_that_is_zero_throughout_says_so() {
    let case = Case::binary([1.0, 0.5, 0.3, -0.375], 0, [0.0, 0.0], 1.0, 3).unwrap();
    let config = MethodConfig::new(
        MethodName::Dop853,
        Tolerances::new(1e-12, 1e-12).unwrap(),
        None,
    )
    .unwrap();
    let mut inner = NoObserver;
    let mut recorder = Recorder::new(&mut inner, 3);
    let report = compare(&case, &config, &mut recorder).unwrap();
    let mut series = recorder.series.clone();
    for p in &mut series.drift_k {
        p.1 = 0.0;
    }
    let c = chart(&case.motion, &report, &series);
    assert_eq!(c.series[2].label, "drift of K: |K(t) − K(0)|: 0 throughout");
    assert!(!c.series[0].label.contains("throughout"));
}
