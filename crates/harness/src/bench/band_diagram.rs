//! The work–precision diagram of an ensemble: per method, the median error over the motions
//! against the median cost (a line through the tolerances) and the 5–95 % band of the error
//! shaded around it.

use rsts_plots::{Chart, Series, Style};

use super::diagrams::{assign_colours, Cost};
use super::BenchReport;
use crate::ensemble::percentile;

/// (tolerance, error p05, median, p95, cost) of one band.
type BandPoint = (f64, f64, f64, f64, f64);

/// The diagram of `report`'s bands (an ensemble's report; empty otherwise).
pub fn ensemble_work_precision(report: &BenchReport, cost: Cost) -> Chart {
    let case = &report.case;
    let n = report.ensemble.as_ref().map_or(0, |e| e.n);
    let mut series: Vec<Series> = Vec::new();
    // Per series: (tolerance, p05, median, p95, cost) drawn from loose to tight tolerance.
    let mut points: Vec<Vec<BandPoint>> = Vec::new();
    for band in &report.bands {
        let of = || {
            report
                .rows
                .iter()
                .zip(&report.labels)
                .filter(|(r, _)| r.method == band.method && r.tolerance == band.tolerance)
        };
        // The median over the motions that state the cost (none: the band is not drawn).
        let costs: Vec<f64> = of().filter_map(|(r, _)| cost.of(r)).collect();
        let c = match cost {
            Cost::Seconds => band.time_median,
            _ => percentile(&costs, 0.5),
        };
        let Some((_, label)) = of().next() else {
            continue;
        };
        if c.is_nan() || c <= 0.0 {
            continue;
        }
        let k = match series.iter().position(|s| s.label == label.label) {
            Some(k) => k,
            None => {
                let mut s = Series::new(label.label.clone(), Vec::new(), Style::LineMarkers);
                s.dashed = label.external;
                series.push(s);
                points.push(Vec::new());
                series.len() - 1
            }
        };
        points[k].push((
            band.tolerance,
            band.error_p05,
            band.error_median,
            band.error_p95,
            c,
        ));
    }
    for (s, mut p) in series.iter_mut().zip(points) {
        p.sort_by(|a, b| b.0.total_cmp(&a.0));
        s.point_labels = p.iter().map(|q| format!("{:e}", q.0)).collect();
        s.points = p.iter().map(|q| (q.2, q.4)).collect();
        s.band = p.iter().map(|q| ((q.1, q.4), (q.3, q.4))).collect();
    }
    assign_colours(&mut series);
    Chart::log_log(
        format!(
            "Work–precision over {n} motions: a = {}, b = {}, T = {}",
            case.motion.a.to_f64(),
            case.motion.b.to_f64(),
            case.t_end_f64()
        ),
        format!(
            "max state error over {} samples: median (line) and 5–95 % of the motions (band)",
            case.samples
        ),
        format!(
            "{}, median over the motions; points: tolerance",
            cost.label(report.repeats)
        ),
        series,
    )
}
