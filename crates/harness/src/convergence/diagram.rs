//! The convergence diagram: log–log error against the fixed step, as a chart for
//! [`rsts_plots::render_svg`] — per method the points of its fitted window (line and markers)
//! and the fitted line C·hᵖ (dashed), the excluded points of every method in grey.

use rsts_plots::{Chart, Series, Style};

use super::ConvergenceReport;

/// Colour of the excluded points (of every method).
const EXCLUDED_GREY: &str = "#9a9a9a";

/// The chart of a convergence study (`rsts convergence --svg`).
pub fn chart(report: &ConvergenceReport) -> Chart {
    let palette = rsts_plots::PALETTE;
    let mut series = Vec::new();
    let mut excluded = Vec::new();
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
        // The fitted line over its window, a factor 2 beyond each end.
        let (lo, hi) = (fit.window[0] / 2.0, fit.window[1] * 2.0);
        let line = |h: f64| 10f64.powf(fit.log10_constant + fit.order * h.log10());
        let mut s = Series::new(
            format!(
                "{} fit: order {:.2} ± {:.2}",
                fit.method, fit.order, fit.order_stderr
            ),
            vec![(lo, line(lo)), (hi, line(hi))],
            Style::Line,
        );
        s.color = Some(colour);
        s.dashed = true;
        series.push(s);
    }
    if !excluded.is_empty() {
        let mut s = Series::new(
            "excluded: round-off floor, pre-asymptotic",
            excluded,
            Style::Markers,
        );
        s.color = Some(EXCLUDED_GREY.into());
        series.push(s);
    }
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
