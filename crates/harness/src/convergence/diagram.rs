//! The convergence diagram: log–log error against the fixed step, as a chart for
//! [`rsts_plots::render_svg`] — per method the points of its regimes (line and markers), each
//! regime's fitted line C·hᵖ (dashed, its order ± the uncertainty to two significant digits in
//! the legend), its floor's lowest point with the floor's kind in words ("round-off" or
//! "above round-off"), and the excluded points of every method in grey, their kinds listed.

use rsts_plots::{Chart, Series, Style};

use super::ConvergenceReport;

/// Colour of the excluded points (of every method).
const EXCLUDED_GREY: &str = "#9a9a9a";

/// The chart of a convergence study (`rsts convergence --svg`).
pub fn chart(report: &ConvergenceReport) -> Chart {
    let palette = rsts_plots::PALETTE;
    let mut series = Vec::new();
    let mut excluded = Vec::new();
    let mut floors: Vec<Series> = Vec::new();
    let mut kinds = Vec::new();
    for (k, fit) in report.fits.iter().enumerate() {
        let colour = palette[k % palette.len()].to_string();
        let rows: Vec<_> = report
            .rows
            .iter()
            .filter(|r| r.method == fit.method)
            .collect();
        let out_of = |h: f64| fit.excluded.iter().any(|e| e.step == h);
        let inside: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| !out_of(r.step))
            .map(|r| (r.step, r.max_error))
            .collect();
        let outside: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| out_of(r.step) && r.max_error > 0.0 && r.max_error.is_finite())
            .map(|r| (r.step, r.max_error))
            .collect();
        let mut s = Series::new(fit.method.clone(), inside, Style::LineMarkers);
        s.color = Some(colour.clone());
        series.push(s);
        excluded.extend(outside);
        // Each regime's fitted line over its window, a factor 2 beyond each end; the legend
        // says the order (its uncertainty to two significant digits) and, with more than one
        // regime, down to which step.
        let several = fit.regimes.len() > 1;
        for (r, regime) in fit.regimes.iter().enumerate() {
            let (lo, hi) = (regime.window[0] / 2.0, regime.window[1] * 2.0);
            let line = |h: f64| 10f64.powf(regime.log10_constant + regime.order * h.log10());
            let order = super::order_with_error(regime.order, regime.order_stderr);
            let label = if !several {
                format!("{} fit: order {order}", fit.method)
            } else if fit.competing {
                format!(
                    "{} fit: order {order} (competing window, h {:.1e} to {:.1e})",
                    fit.method, regime.window[0], regime.window[1]
                )
            } else if r + 1 < fit.regimes.len() {
                format!(
                    "{} fit: order {order} down to h = {:.1e}",
                    fit.method, regime.window[0]
                )
            } else {
                format!("{} fit: then order {order} (asymptotic)", fit.method)
            };
            let mut s = Series::new(label, vec![(lo, line(lo)), (hi, line(hi))], Style::Line);
            s.color = Some(colour.clone());
            s.dashed = true;
            series.push(s);
        }
        // The floor: its lowest point, in the method's colour, its kind in words.
        if let Some(f) = &fit.floor {
            if let Some(r) = rows.iter().find(|r| r.max_error == f.error) {
                let mut s = Series::new(
                    format!("{} floor {:.1e}: {}", fit.method, f.error, f.kind.as_str()),
                    vec![(r.step, r.max_error)],
                    Style::Markers,
                );
                s.color = Some(colour.clone());
                floors.push(s);
            }
        }
        for e in &fit.excluded {
            if !kinds.contains(&e.kind) {
                kinds.push(e.kind);
            }
        }
    }
    if !excluded.is_empty() {
        let names: Vec<&str> = kinds
            .iter()
            .map(|k: &super::ExcludedKind| k.as_str())
            .collect();
        let label = format!("excluded: {}", names.join(", "));
        let mut s = Series::new(label, excluded, Style::Markers);
        s.color = Some(EXCLUDED_GREY.into());
        series.push(s);
    }
    series.extend(floors);
    let c = &report.case;
    Chart::log_log(
        format!(
            "Observed order: a = {}, b = {}, m = {}, h = {}, T = {}",
            c.motion.a.to_f64(),
            c.motion.b.to_f64(),
            c.motion.m.to_f64(),
            c.motion.h.to_f64(),
            c.t_end_f64()
        ),
        "fixed step h",
        format!(
            "max state error over {} samples (closed-form reference)",
            c.samples
        ),
        series,
    )
}
