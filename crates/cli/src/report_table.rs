//! The report of `rsts compare` and `rsts check` as a table of `key: value` lines (the JSON's
//! figures, rounded for reading), shared by both commands.

use std::io::Write;

use rsts_harness::Report;

use crate::output;

/// The report as `key: value` lines; `span` is the time interval.
pub fn write_table(
    out: &mut dyn Write,
    r: &Report,
    span: &str,
    motion: &rsts_closed_form::Motion,
) -> anyhow::Result<()> {
    // The numbers as the report's JSON shows them (f64).
    let [a, b, m, h] = motion.parameters_f64();
    let torus = motion.torus;
    let e = |x: f64| format!("{x:.3e}");
    let mut items = vec![
        (
            "camera",
            format!(
                "{} (a = {a}, b = {b}, m = {m}, h = {h}, torus {torus})",
                r.camera
            ),
        ),
        (
            "method",
            format!(
                "{} ({}{} digits; reference {} digits)",
                r.method,
                match (r.rtol, r.atol) {
                    (Some(rtol), Some(atol)) => format!("rtol {rtol:e}, atol {atol:e}, "),
                    _ => String::new(),
                },
                r.digits,
                r.reference_digits
            ),
        ),
        (
            "samples",
            format!(
                "{} over [{span}]{}",
                r.samples_compared,
                if r.complete { "" } else { " (interrupted)" }
            ),
        ),
        ("max state error", e(r.max_state_error)),
        ("final state error", e(r.final_state_error)),
        (
            "max orientation error",
            format!("{} rad", e(r.max_orientation_error)),
        ),
        ("correct digits", digits_line(&r.correct_digits)),
        (
            "drift of H, K, G",
            format!("{}, {}, {}", e(r.drift.h), e(r.drift.k), e(r.drift.g)),
        ),
        ("constraint drift", e(r.drift.constraints)),
        (
            "drift growth",
            r.drift
                .growth
                .map_or_else(|| "-".to_string(), |g| g.describe()),
        ),
        ("drift of on-N relations", e(r.drift.off_n)),
        (
            "steps (rejected)",
            format!(
                "{} ({})",
                output::or_na(r.steps),
                output::or_na(r.rejected_steps)
            ),
        ),
        ("rhs evaluations", output::or_na(r.rhs_evals)),
        (
            "integration time",
            match (r.integration_seconds, r.wall_seconds) {
                (Some(s), Some(w)) => format!("{s:.6} s (process wall time {w:.6} s)"),
                (Some(s), None) => format!("{s:.6} s"),
                (None, Some(w)) => format!("n/a (process wall time {w:.6} s)"),
                (None, None) => output::NA.to_string(),
            },
        ),
    ];
    items.extend(geometry_lines(r));
    output::write_key_values(out, &items)?;
    Ok(())
}

/// `scd 9.81 (min 9.52), mescd 10.13 (min 9.84)`: at the last sample and the worst.
fn digits_line(d: &rsts_harness::CorrectDigits) -> String {
    let f = |x: f64| {
        if x.is_finite() {
            format!("{x:.2}")
        } else {
            "exact".to_string()
        }
    };
    format!(
        "scd {} (min {}), mescd {} (min {})",
        f(d.scd),
        f(d.scd_min),
        f(d.mescd),
        f(d.mescd_min)
    )
}

/// The geometry of the error (docs/stability.md): distance from N, phase error, what dominates.
fn geometry_lines(r: &Report) -> Vec<(&'static str, String)> {
    let e = |x: f64| format!("{x:.3e}");
    let grows = |g: &Option<rsts_harness::geometry::GrowthSummary>| match g {
        Some(g) => format!("grows like {}", g.describe()),
        None => "too few samples for a growth fit".to_string(),
    };
    let mut lines = Vec::new();
    if let Some(n) = &r.normal {
        lines.push((
            "distance from N",
            format!(
                "max {}, final {} ({}; N normally {} here)",
                e(n.distance_from_n.max),
                e(n.distance_from_n.last),
                grows(&n.growth),
                n.kind
            ),
        ));
    }
    if let Some(p) = &r.phase_error {
        lines.push((
            "phase error",
            format!(
                "psi1 max {}, psi2 max {} rad ({})",
                e(p.psi1.max),
                e(p.psi2.max),
                grows(&p.growth)
            ),
        ));
    }
    if let Some(s) = &r.error_split {
        lines.push((
            "the error is",
            format!(
                "{} (at t = {}: along N {}, off N {})",
                s.summary,
                (s.t * 1e6).round() / 1e6,
                e(s.along_n),
                e(s.departure_from_n)
            ),
        ));
    }
    lines
}
