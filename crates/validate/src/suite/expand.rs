//! A case of a suite file placed on N and expanded into its runs.

use super::*;

/// The h of a placement at (a, b, m).
pub fn place_h(
    what: &str,
    a: f64,
    b: f64,
    m: Option<f64>,
    p: &Placement,
) -> Result<(f64, f64), ValidateError> {
    let err = |msg: String| ValidateError::Suite(format!("{what}: place: {msg}"));
    let (p2, r2) = (a * a + b * b, a * a - b * b);
    let given = [p.near.is_some(), p.ell.is_some(), p.equilibrium.is_some()]
        .iter()
        .filter(|x| **x)
        .count();
    if given != 1 {
        return Err(err(
            "give exactly one of near = CURVE, ell = L, equilibrium = pN".into(),
        ));
    }
    let delta = |required: bool| -> Result<f64, ValidateError> {
        match p.delta {
            Some(d) if d.is_finite() && d > 0.0 => Ok(d),
            Some(d) => Err(err(format!("delta must be positive and finite, got {d}"))),
            None if required => Err(err("delta is required".into())),
            None => Ok(0.0),
        }
    };
    let need_m = || m.ok_or_else(|| err("this placement needs m".into()));
    if let Some(curve) = &p.near {
        let m = need_m()?;
        let d = delta(true)?;
        let (h0, default_side) = match curve.as_str() {
            "outer-a" => (r2 * m - 2.0 * a, Some(1.0)),
            "outer-b" => (-r2 * m - 2.0 * b, Some(1.0)),
            "hyperbola" => {
                if m >= 0.0 {
                    return Err(err(format!("the hyperbola needs m < 0, got m = {m}")));
                }
                (-p2 * m - 0.5 / m, Some(-1.0))
            }
            "inner-a" => (r2 * m + 2.0 * a, None),
            "inner-b" => (-r2 * m + 2.0 * b, None),
            other => {
                return Err(err(format!(
                    "unknown curve '{other}' (outer-a, outer-b, hyperbola, inner-a, inner-b)"
                )))
            }
        };
        let sign = match (p.side.as_deref(), default_side) {
            (Some("above"), _) => 1.0,
            (Some("below"), _) => -1.0,
            (None, Some(s)) => s,
            (None, None) => return Err(err(format!("{curve}: side = \"above\" or \"below\""))),
            (Some(other), _) => {
                return Err(err(format!(
                    "side must be \"above\" or \"below\", got '{other}'"
                )))
            }
        };
        return Ok((m, h0 + sign * d));
    }
    if p.side.is_some() {
        return Err(err("side only goes with near = CURVE".into()));
    }
    if let Some(ell) = p.ell {
        let m = need_m()?;
        if p.delta.is_some() {
            return Err(err("delta does not go with ell".into()));
        }
        if !(ell.is_finite() && ell > 0.0) || m >= 0.0 || !m.is_finite() {
            return Err(err(format!(
                "ell needs ℓ > 0 and m < 0, got ℓ = {ell}, m = {m}"
            )));
        }
        return Ok((m, (ell * ell - 1.0 - 2.0 * p2 * m * m) / (2.0 * m)));
    }
    let name = p.equilibrium.as_deref().unwrap_or_default();
    let d = delta(true)?;
    if m.is_some() {
        return Err(err("an equilibrium placement sets m itself: drop m".into()));
    }
    Ok(match name {
        // The corner of the two outer lines; straight up is inside camera I+.
        "p1" => (1.0 / (a + b), -(a + b) + d),
        // Where h = −r²m + 2b ends on h = r²m − 2a: step right of it, just above the boundary.
        "p2" => (1.0 / (a - b) + d, r2 * (1.0 / (a - b) + d) - 2.0 * a + d),
        // Where h = r²m + 2a starts on h = −r²m − 2b: step left of it, just above the boundary.
        "p3" => (-1.0 / (a - b) - d, -r2 * (-1.0 / (a - b) - d) - 2.0 * b + d),
        // The crossing of the two inner lines; straight up.
        "p4" => (-1.0 / (a + b), a + b + d),
        other => {
            return Err(err(format!(
                "unknown equilibrium '{other}' (p1, p2, p3, p4)"
            )))
        }
    })
}

pub(super) fn expand_case(
    defaults: &Defaults,
    adapters: &BTreeMap<String, AdapterSpec>,
    spec: &CaseSpec,
) -> Result<Vec<Run>, ValidateError> {
    check_name(&spec.name)?;
    let what = format!("case '{}'", spec.name);
    let e = |msg: String| ValidateError::Suite(format!("{what}: {msg}"));
    let a = finite(&what, "a", spec.a.or(defaults.a).unwrap_or(1.0))?;
    let b = finite(&what, "b", spec.b.or(defaults.b).unwrap_or(0.5))?;
    let (m, h) = match (&spec.place, spec.h) {
        (Some(_), Some(_)) => return Err(e("give h or place, not both".into())),
        (Some(p), None) => place_h(&what, a, b, spec.m, p)?,
        (None, Some(h)) => (
            spec.m.ok_or_else(|| e("m is missing".into()))?,
            finite(&what, "h", h)?,
        ),
        (None, None) => return Err(e("give h (with m) or place".into())),
    };
    finite(&what, "m", m)?;
    let t_end = finite(
        &what,
        "t_end",
        spec.t_end.or(defaults.t_end).unwrap_or(100.0),
    )?;
    if t_end < 0.0 {
        return Err(e(format!("t_end must be non-negative, got {t_end}")));
    }
    let samples = spec.samples.or(defaults.samples).unwrap_or(201);
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(e(format!(
            "samples must be between 1 and {MAX_SAMPLES}, got {samples}"
        )));
    }
    let phase1 = finite(
        &what,
        "phase1",
        spec.phase1.or(defaults.phase1).unwrap_or(0.0),
    )?;
    let phase2 = finite(
        &what,
        "phase2",
        spec.phase2.or(defaults.phase2).unwrap_or(0.0),
    )?;
    let choice = TorusChoice {
        torus: 0,
        phase1,
        phase2,
    };
    let motion = ExplicitMotion::new(a, b, m, h, choice)
        .map_err(|err| e(format!("(a, b, m, h) = ({a}, {b}, {m}, {h}): {err}")))?;
    let camera = motion.camera;
    if let Some(expected) = &spec.camera {
        let want: Camera = expected.parse().map_err(e)?;
        if want != camera {
            return Err(e(format!(
                "(m, h) = ({m}, {h}) lies in camera {camera}, not {want}"
            )));
        }
    }
    let tori: Vec<usize> = match spec.tori.as_ref().or(defaults.tori.as_ref()) {
        None => vec![0],
        Some(Tori::Name(s)) if s == "all" => (0..motion.tori).collect(),
        Some(Tori::Name(s)) => {
            return Err(e(format!(
                "tori must be \"all\", an index or a list, got '{s}'"
            )))
        }
        Some(Tori::One(k)) => vec![*k],
        Some(Tori::List(v)) if v.is_empty() => return Err(e("tori is an empty list".into())),
        Some(Tori::List(v)) => v.clone(),
    };
    for &k in &tori {
        if k >= motion.tori {
            return Err(e(format!(
                "torus {k} does not exist: camera {camera} has {} (0..{})",
                motion.tori, motion.tori
            )));
        }
    }
    let methods = spec
        .methods
        .clone()
        .or(defaults.methods.clone())
        .unwrap_or_else(|| vec!["dop853".into()]);
    let tolerances = spec
        .tolerances
        .clone()
        .or(defaults.tolerances.clone())
        .unwrap_or_else(|| vec![1e-12]);
    let digits = spec.digits.or(defaults.digits);
    let step = spec.step.or(defaults.step);
    let closed_form = spec.closed_form.or(defaults.closed_form).unwrap_or(true);
    if methods.is_empty() {
        return Err(e(
            "methods is an empty list: name at least one (leave methods out for dop853)".into(),
        ));
    }
    if tolerances.is_empty() {
        return Err(e("tolerances is an empty list".into()));
    }
    let count = tori
        .len()
        .saturating_mul(usize::from(closed_form) + methods.len().saturating_mul(tolerances.len()));
    if count > MAX_RUNS {
        return Err(too_many_runs(count, &spec.name));
    }
    let mut thresholds = spec.thresholds.over(defaults.thresholds);
    thresholds.check(&what)?;
    if thresholds.min_order.is_some() && spec.convergence.is_none() {
        return Err(e(
            "min_order holds convergence cases only (give convergence = { steps = [...] })".into(),
        ));
    }
    if thresholds.floor.is_some() && spec.convergence.is_none() {
        return Err(e(
            "floor holds convergence cases only (give convergence = { steps = [...] })".into(),
        ));
    }
    if thresholds.closed_form_f64.is_none() {
        thresholds.closed_form_f64 = Some(DEFAULT_CLOSED_FORM_F64);
    }
    if thresholds.closed_form_residual.is_none() {
        thresholds.closed_form_residual = Some(DEFAULT_CLOSED_FORM_RESIDUAL);
    }
    let mut runs = Vec::new();
    for &torus in &tori {
        let base = Run {
            id: String::new(),
            case: spec.name.clone(),
            a,
            b,
            m,
            h,
            torus,
            phase1,
            phase2,
            t_end,
            samples,
            camera: camera.label().to_string(),
            kind: RunKind::ClosedForm,
            thresholds,
        };
        if closed_form {
            runs.push(Run {
                id: format!("{}/t{torus}/closed-form", spec.name),
                ..base.clone()
            });
        }
        if let Some(conv) = &spec.convergence {
            runs.extend(convergence_runs(&base, &methods, conv, digits).map_err(e)?);
            continue;
        }
        for method in &methods {
            if let Some(adapter) = adapters.get(method) {
                for &tol in &tolerances {
                    if !(tol.is_finite() && tol > 0.0) {
                        return Err(e(format!("tolerance must be positive, got {tol}")));
                    }
                    runs.push(Run {
                        id: format!("{}/t{torus}/{method}@{}", spec.name, tol_label(tol)),
                        kind: RunKind::External {
                            method: method.clone(),
                            command: adapter.command.clone(),
                            rtol: tol,
                            atol: tol,
                            digits,
                            timeout: adapter.timeout,
                        },
                        ..base.clone()
                    });
                }
                continue;
            }
            for &tol in &tolerances {
                // Checked here so a bad method or tolerance is a suite error, not a failed run.
                let config =
                    method_config(method, tol, tol, digits, step).map_err(|err| e(err.detail()))?;
                let name = config.method.as_str().to_string();
                let run_digits =
                    (config.method == MethodName::TaylorMp).then(|| config.mp_digits());
                let run_step = (config.method == MethodName::Rk4).then_some(step).flatten();
                let mut id = format!("{}/t{torus}/{name}@{}", spec.name, tol_label(tol));
                if let Some(d) = run_digits {
                    id.push_str(&format!("/{d}d"));
                }
                if let Some(s) = run_step {
                    id.push_str(&format!("/step{}", tol_label(s)));
                }
                runs.push(Run {
                    id,
                    kind: RunKind::Integrator {
                        method: name,
                        rtol: tol,
                        atol: tol,
                        digits: run_digits,
                        step: run_step,
                    },
                    ..base.clone()
                });
            }
        }
    }
    Ok(runs)
}
