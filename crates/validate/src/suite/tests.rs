use super::*;

#[test]
fn grid_expands_to_sorted_unique_ids() {
    let s = Suite::parse(
        r#"
name = "t"
[defaults]
t_end = 1.0
samples = 3
[[case]]
name = "V"
camera = "V"
m = -0.7092
h = 1.5643
tori = "all"
methods = ["dop853", "dopri5"]
tolerances = [1e-8, 1e-10]
"#,
        "x",
    )
    .unwrap();
    // 4 tori × (1 closed-form + 2 methods × 2 tolerances).
    assert_eq!(s.runs.len(), 20);
    let ids: Vec<&str> = s.runs.iter().map(|r| r.id.as_str()).collect();
    let mut sorted = ids.clone();
    sorted.sort();
    assert_eq!(ids, sorted);
    assert!(ids.contains(&"V/t3/dopri5@1e-10"));
    assert!(ids.contains(&"V/t0/closed-form"));
    assert!(s.runs.iter().all(|r| r.camera == "V"));
}

#[test]
fn placements_land_where_asked() {
    let (a, b) = (1.0, 0.5);
    let place = |p: Placement, m: Option<f64>| place_h("t", a, b, m, &p).unwrap();
    let near = |c: &str, side: Option<&str>| Placement {
        near: Some(c.into()),
        side: side.map(String::from),
        delta: Some(1e-6),
        ..Placement::default()
    };
    assert_eq!(place(near("outer-a", None), Some(1.0)).1, 0.75 - 2.0 + 1e-6);
    assert_eq!(
        place(near("inner-b", Some("below")), Some(0.0)).1,
        1.0 - 1e-6
    );
    let (m, h) = place(near("hyperbola", None), Some(-1.0));
    let ell2 = 2.0 * 1.25 * m * m + 2.0 * h * m + 1.0;
    assert!((ell2 - 2e-6).abs() < 1e-12, "{ell2}");
    let (m, h) = place(
        Placement {
            ell: Some(1e-6),
            ..Placement::default()
        },
        Some(-1.0),
    );
    let ell2 = 2.0 * 1.25 * m * m + 2.0 * h * m + 1.0;
    assert!((ell2.sqrt() - 1e-6).abs() < 1e-9, "{ell2}");
    for p in ["p1", "p2", "p3", "p4"] {
        let (m, h) = place(
            Placement {
                equilibrium: Some(p.into()),
                delta: Some(1e-3),
                ..Placement::default()
            },
            None,
        );
        ExplicitMotion::new(a, b, m, h, TorusChoice::default())
            .unwrap_or_else(|e| panic!("{p} at ({m}, {h}): {e}"));
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let err = |text: &str| Suite::parse(text, "x").unwrap_err().to_string();
    assert!(err("[[case]\n").contains("TOML") || err("[[case]\n").contains("expected"));
    let base = "[[case]]\nname = \"c\"\nm = 0.3\nh = -0.375\n";
    assert!(err(&format!("{base}methods = [\"euler\"]\n")).contains("unknown method 'euler'"));
    assert!(err(&format!("{base}tolerances = [-1.0]\n")).contains("rtol"));
    assert!(err(&format!("{base}camera = \"V\"\n")).contains("not V"));
    assert!(err(&format!("{base}tori = 3\n")).contains("torus 3 does not exist"));
    assert!(err(&format!("{base}bogus = 1\n")).contains("bogus"));
    assert!(err("[[case]]\nname = \"c\"\nm = 0.0\nh = 2.0\n").contains("h = r²m + 2a"));
    assert!(err("name = \"x\"\n").contains("no [[case]]"));
    assert!(err(&format!("{base}{}", base)).contains("used twice"));
    assert!(err(&format!("{base}[case.thresholds]\nmax_drift = 0.0\n")).contains("max_drift"));
}

/// A TOML error names line and column and shows 40 characters either side of the place, the
/// quoted value cut: a 200 kB line is not printed (it used to be, twice).
#[test]
fn toml_errors_do_not_repeat_long_lines() {
    let long = "x".repeat(200_000);
    let text = format!("name = \"t\"\n[defaults]\nt_end = \"{long}\"\n");
    let e = Suite::parse(&text, "x").unwrap_err().detail();
    assert!(
        e.len() < 400,
        "{} characters: {}",
        e.len(),
        &e[..400.min(e.len())]
    );
    assert!(e.starts_with("line 3, column 9: "), "{e}");
    assert!(e.contains("(200000 characters)"), "{e}");
    let e = Suite::parse(&format!("name = \"t\"\nbad {long}\n"), "x")
        .unwrap_err()
        .detail();
    assert!(e.len() < 400 && e.starts_with("line 2, column "), "{e}");
}
