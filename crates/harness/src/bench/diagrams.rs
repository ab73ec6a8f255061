//! The diagrams of a benchmark: work–precision (error against cost) and tolerance
//! proportionality (error against tolerance, with the fitted C·tol^p), as charts for
//! [`rsts_plots::render_svg`]: which rows make a series, their order, labels and colours.

use rsts_plots::{Chart, Series, Style};

use super::{BenchReport, BenchRow};

/// The cost a work–precision diagram draws against the error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cost {
    Seconds,
    RhsEvals,
    Steps,
}

impl Cost {
    /// The cost of a row; `None` when not known (an integrator that does not state its steps
    /// or evaluations) or not positive (no point on a log axis).
    pub fn of(&self, row: &BenchRow) -> Option<f64> {
        let c = match self {
            Cost::Seconds => Some(row.integration_seconds),
            Cost::RhsEvals => row.rhs_evals.map(|n| n as f64),
            Cost::Steps => row.steps.map(|n| n as f64),
        };
        c.filter(|&c| c > 0.0)
    }

    /// The labels of the rows the diagram of `report` leaves out for want of this cost, each
    /// once (the caller notes them: a point left out is said, not silently lost).
    pub fn left_out(&self, report: &BenchReport) -> Vec<String> {
        let mut labels: Vec<String> = Vec::new();
        for (row, l) in report.rows.iter().zip(&report.labels) {
            if self.of(row).is_none() && !labels.contains(&l.label) {
                labels.push(l.label.clone());
            }
        }
        labels
    }

    /// What this cost is called in a note (`steps`, `right-hand-side evaluations`, `seconds`).
    pub fn name(&self) -> &'static str {
        match self {
            Cost::Seconds => "integration seconds",
            Cost::RhsEvals => "right-hand-side evaluations",
            Cost::Steps => "steps",
        }
    }

    pub(super) fn label(&self, repeats: usize) -> String {
        match self {
            Cost::Seconds => format!("integration seconds (median of {repeats})"),
            Cost::RhsEvals => "right-hand-side evaluations".into(),
            Cost::Steps => "accepted steps".into(),
        }
    }
}

/// Colour of a series: a peer's method takes the colour of our method of the same precision.
fn counterpart(label: &str) -> Option<&'static str> {
    let rest = label.strip_prefix("heyoka-")?;
    if rest.starts_with("f64") {
        Some("taylor-f64")
    } else if rest.starts_with("real128") {
        Some("taylor-dd")
    } else if rest.starts_with("mpfr") {
        Some("taylor-mp")
    } else {
        None
    }
}

/// Our series take the palette in order; a peer's series takes the colour of our method of the
/// same precision ([`counterpart`]) unless another peer series has it, else the next free one.
pub(super) fn assign_colours(series: &mut [Series]) {
    let palette = rsts_plots::PALETTE;
    let mut used: Vec<usize> = Vec::new();
    let mut colour_of: Vec<Option<usize>> = vec![None; series.len()];
    for k in (0..series.len()).filter(|&k| !series[k].dashed) {
        let c = (0..palette.len())
            .map(|i| (k + i) % palette.len())
            .find(|c| !used.contains(c));
        colour_of[k] = c.or(Some(k % palette.len()));
        used.extend(colour_of[k]);
    }
    let mut taken_by_peer: Vec<usize> = Vec::new();
    for k in 0..series.len() {
        if !series[k].dashed {
            continue;
        }
        let twin = counterpart(&series[k].label).and_then(|ours| {
            series.iter().position(|s| {
                !s.dashed && (s.label == ours || s.label.starts_with(&format!("{ours}-")))
            })
        });
        let c = match twin.and_then(|j| colour_of[j]) {
            Some(c) if !taken_by_peer.contains(&c) => c,
            _ => (0..palette.len())
                .find(|c| !used.contains(c))
                .unwrap_or(k % palette.len()),
        };
        taken_by_peer.push(c);
        used.push(c);
        colour_of[k] = Some(c);
    }
    for (s, c) in series.iter_mut().zip(colour_of) {
        s.color = c.map(|c| palette[c].to_string());
    }
}

/// The work–precision diagram: one line per method, max error against `cost` (log–log); for
/// an ensemble, the median and the 5–95 % band over the motions
/// ([`super::band_diagram::ensemble_work_precision`]).
pub fn work_precision(report: &BenchReport, cost: Cost) -> Chart {
    if report.ensemble.is_some() {
        return super::band_diagram::ensemble_work_precision(report, cost);
    }
    let (case, repeats) = (&report.case, report.repeats);
    let mut series: Vec<Series> = Vec::new();
    // (tolerance, error, cost) per series, drawn from loose to tight tolerance; a row without
    // the cost (an external integrator that states no evaluations) is not drawn
    // ([`Cost::left_out`]).
    let mut points: Vec<Vec<(f64, f64, f64)>> = Vec::new();
    for (row, l) in report.rows.iter().zip(&report.labels) {
        let k = match series.iter().position(|s| s.label == l.label) {
            Some(k) => k,
            None => {
                let mut s = Series::new(l.label.clone(), Vec::new(), Style::LineMarkers);
                s.dashed = l.external;
                series.push(s);
                points.push(Vec::new());
                series.len() - 1
            }
        };
        if let Some(c) = cost.of(row) {
            points[k].push((row.tolerance, row.max_error, c));
        }
    }
    for (s, mut p) in series.iter_mut().zip(points) {
        p.sort_by(|a, b| b.0.total_cmp(&a.0));
        // Each point labelled with its tolerance.
        s.point_labels = p.iter().map(|(tol, _, _)| format!("{tol:e}")).collect();
        s.points = p.into_iter().map(|(_, e, t)| (e, t)).collect();
    }
    series.retain(|s| !s.points.is_empty());
    assign_colours(&mut series);
    Chart::log_log(
        format!(
            "Work–precision: a = {}, b = {}, m = {}, h = {}, T = {}",
            case.motion.a.to_f64(),
            case.motion.b.to_f64(),
            case.motion.m.to_f64(),
            case.motion.h.to_f64(),
            case.t_end_f64()
        ),
        format!(
            "max state error over {} samples (closed-form reference)",
            case.samples
        ),
        format!("{}; points: tolerance", cost.label(repeats)),
        series,
    )
}

/// The tolerance-proportionality diagram: each method's max error against its tolerance
/// (markers, log–log), its fitted C·tol^p (a line of the same colour) and error = tol (grey).
pub fn tolerance_proportionality(report: &BenchReport) -> Chart {
    let (case, fits) = (&report.case, &report.fits);
    let mut series: Vec<Series> = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for (row, l) in report.rows.iter().zip(&report.labels) {
        let (tol, err) = (row.tolerance, row.max_error);
        if !(tol > 0.0 && err > 0.0 && tol.is_finite() && err.is_finite()) {
            continue;
        }
        (lo, hi) = (lo.min(tol), hi.max(tol));
        match series.iter_mut().find(|s| s.label == l.label) {
            Some(s) => s.points.push((tol, err)),
            None => {
                let mut s = Series::new(l.label.clone(), vec![(tol, err)], Style::Markers);
                s.dashed = l.external;
                series.push(s);
            }
        }
    }
    assign_colours(&mut series);
    let mut lines = Vec::new();
    for s in &series {
        let method = report
            .rows
            .iter()
            .zip(&report.labels)
            .find(|(_, l)| l.label == s.label)
            .map(|(r, _)| r.method.as_str());
        if let Some(f) = fits.iter().find(|f| Some(f.method.as_str()) == method) {
            let (a, b) = s.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
            let mut line = Series::new(
                format!(
                    "{} fit: {:.2e}·tol^{:.2}",
                    s.label, f.tolerance_constant, f.tolerance_exponent
                ),
                vec![(a, f.at(a)), (b, f.at(b))],
                Style::Line,
            );
            line.color = s.color.clone();
            line.dashed = s.dashed;
            lines.push(line);
        }
    }
    series.extend(lines);
    if hi > 0.0 {
        let mut diagonal = Series::new("error = tolerance", vec![(lo, lo), (hi, hi)], Style::Line);
        diagonal.color = Some("#999999".into());
        series.push(diagonal);
    }
    Chart::log_log(
        format!(
            "Tolerance proportionality: a = {}, b = {}, m = {}, h = {}, T = {}",
            case.motion.a.to_f64(),
            case.motion.b.to_f64(),
            case.motion.m.to_f64(),
            case.motion.h.to_f64(),
            case.t_end_f64()
        ),
        "tolerance (rtol = atol)",
        format!(
            "max state error over {} samples; lines: fitted C·tol^p",
            case.samples
        ),
        series,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_series_has_its_own_colour_and_a_peer_shares_its_twins() {
        let mk = |label: &str, dashed: bool| {
            let mut s = Series::new(label, vec![(1.0, 1.0)], Style::LineMarkers);
            s.dashed = dashed;
            s
        };
        let mut series = vec![
            mk("dop853", false),
            mk("taylor-f64", false),
            mk("heyoka-f64", true),
            mk("heyoka-f64-ha", true),
            mk("other", true),
        ];
        assign_colours(&mut series);
        let c: Vec<String> = series.iter().map(|s| s.color.clone().unwrap()).collect();
        assert_eq!(c[2], c[1], "heyoka-f64 drawn like taylor-f64");
        for i in 0..c.len() {
            for j in 0..i {
                assert!(
                    i == 2 && j == 1 || c[i] != c[j],
                    "{i} and {j} share {}",
                    c[i]
                );
            }
        }
    }

    #[test]
    fn peers_take_the_colour_of_our_method_of_the_same_precision() {
        assert_eq!(counterpart("heyoka-f64"), Some("taylor-f64"));
        assert_eq!(counterpart("heyoka-real128"), Some("taylor-dd"));
        assert_eq!(counterpart("heyoka-mpfr-80d"), Some("taylor-mp"));
        assert_eq!(counterpart("taylor-f64"), None);
    }
}
