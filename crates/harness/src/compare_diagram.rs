//! The diagram of a comparison (`rsts compare --svg`): the state error and the drifts of the
//! first integrals H, K, G (docs/equations.md) at every sample, against time on a log scale — the
//! picture of how an integrator's error grows along the motion, drawn by [`rsts_plots`].
//!
//! [`Recorder`] keeps the figures while the comparison runs (an [`Observer`] that hands every
//! record on), [`chart`] makes the diagram of them, [`write_svg`] writes it whole or not at all.

use std::io;
use std::path::Path;

use rsts_closed_form::Motion;
use rsts_plots::{Chart, Scale, Series, Style};

use crate::analysis::Observer;
use crate::metrics::{Report, SampleRecord};

/// Most points a curve of the diagram keeps: beyond, the samples are taken in consecutive runs
/// and each run gives its largest value (the envelope of the curve, so no peak is lost), which
/// bounds the memory and the SVG's size for any number of samples.
pub const MAX_POINTS: usize = 2000;

/// The four curves of the diagram, (t, value) in time order: the state error
/// max|x − x_exact| over the nine components, and |H(t) − H(0)|, |K(t) − K(0)|, |G(t) − G(0)|.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErrorSeries {
    pub state_error: Vec<(f64, f64)>,
    pub drift_h: Vec<(f64, f64)>,
    pub drift_k: Vec<(f64, f64)>,
    pub drift_g: Vec<(f64, f64)>,
}

/// An observer that keeps the [`ErrorSeries`] of a run of `samples` samples (at most
/// [`MAX_POINTS`] points a curve) and hands every record on to `inner`.
pub struct Recorder<'a> {
    inner: &'a mut dyn Observer,
    /// Samples a point stands for (1 up to [`MAX_POINTS`] samples).
    stride: usize,
    seen: usize,
    pub series: ErrorSeries,
}

impl<'a> Recorder<'a> {
    pub fn new(inner: &'a mut dyn Observer, samples: usize) -> Self {
        Self {
            inner,
            stride: samples.div_ceil(MAX_POINTS).max(1),
            seen: 0,
            series: ErrorSeries::default(),
        }
    }
}

/// Add (t, y) to a curve: a new point at the start of each run of `stride` samples, else the
/// larger of the run's point and this one.
fn keep(curve: &mut Vec<(f64, f64)>, first_of_run: bool, t: f64, y: f64) {
    match curve.last_mut() {
        Some(last) if !first_of_run => {
            // NaN (an integration that blew up) is kept: it is the worst value.
            if y > last.1 || y.is_nan() {
                *last = (t, y);
            }
        }
        _ => curve.push((t, y)),
    }
}

impl Observer for Recorder<'_> {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        let first = self.seen.is_multiple_of(self.stride);
        self.seen += 1;
        let (e, s) = (&r.errors, &mut self.series);
        keep(&mut s.state_error, first, r.t, e.state_error);
        keep(&mut s.drift_h, first, r.t, e.drift_h);
        keep(&mut s.drift_k, first, r.t, e.drift_k);
        keep(&mut s.drift_g, first, r.t, e.drift_g);
        self.inner.on_sample(r)
    }
    fn wants_states(&self) -> bool {
        self.inner.wants_states()
    }
    fn should_stop(&self) -> bool {
        self.inner.should_stop()
    }
}

/// The diagram of a comparison of `motion`: title the method and its tolerances, subtitle the
/// motion; x the time, y (log scale) the state error and the three drifts. A value 0 (at t = 0,
/// or a drift below f64's resolution) has no place on a log axis and is left out; a curve that
/// is 0 throughout says so in the legend.
pub fn chart(motion: &Motion, report: &Report, series: &ErrorSeries) -> Chart {
    let curves = [
        ("state error max|x − x_exact|", &series.state_error),
        ("drift of H: |H(t) − H(0)|", &series.drift_h),
        ("drift of K: |K(t) − K(0)|", &series.drift_k),
        ("drift of G: |G(t) − G(0)|", &series.drift_g),
    ];
    let series = curves
        .iter()
        .zip(rsts_plots::PALETTE)
        .map(|((label, points), colour)| {
            let zero = points.iter().all(|p| p.1 == 0.0);
            let label = match zero {
                true => format!("{label}: 0 throughout"),
                false => label.to_string(),
            };
            let mut s = Series::new(label, points.to_vec(), Style::Line);
            s.color = Some(colour.to_string());
            s
        })
        .collect();
    let tolerances = match (report.rtol, report.atol) {
        (Some(r), Some(a)) if r == a => format!(" at rtol = atol = {r:e}"),
        (Some(r), Some(a)) => format!(" at rtol = {r:e}, atol = {a:e}"),
        _ => String::new(),
    };
    let [a, b, m, h] = [&motion.a, &motion.b, &motion.m, &motion.h].map(short);
    Chart {
        title: format!(
            "{}{tolerances} against the exact motion\ncamera {}: a = {a}, b = {b}, m = {m}, h = {h}, torus {}",
            report.method, report.camera, motion.torus
        ),
        x_label: "time t".into(),
        y_label: "error, drift (log scale)".into(),
        x_scale: Scale::Linear,
        y_scale: Scale::Log10,
        series,
        width: 820,
        height: 500,
    }
}

/// A decimal as the user wrote it, or the shortest f64 text when that is long (the exact value
/// of a binary64 number), with a true minus sign.
fn short(d: &rsts_closed_form::Decimal) -> String {
    let text = d.to_string();
    let text = match text.len() > 14 {
        true => d.to_f64().to_string(),
        false => text,
    };
    text.replace('-', "−")
}

/// Check, before the comparison runs, that `svg` can be written: at least two samples (a curve
/// needs two times), a writable place, not the same file as the MCAP log or an input (the files
/// of an `--exec` command).
pub fn check_output(
    svg: &Path,
    samples: usize,
    mcap: Option<&Path>,
    inputs: &[std::path::PathBuf],
) -> io::Result<()> {
    let refused = |m: String| io::Error::new(io::ErrorKind::InvalidInput, m);
    if samples < 2 {
        return Err(refused(format!(
            "--svg: the diagram draws errors against time and needs at least 2 samples, got {samples}"
        )));
    }
    let mut outputs = vec![rsts_io::Output::File("--svg", svg)];
    outputs.extend(mcap.map(|p| rsts_io::Output::File("--mcap", p)));
    let inputs: Vec<rsts_io::Input> = inputs.iter().map(|p| ("--exec", p.as_path())).collect();
    rsts_io::check_outputs(&inputs, &outputs)?;
    rsts_io::check_writable(svg)
        .map_err(|e| io::Error::new(e.kind(), format!("--svg {}: {e}", svg.display())))
}

/// Write the diagram of a comparison to `svg`, whole or not at all.
pub fn write_svg(
    svg: &Path,
    motion: &Motion,
    report: &Report,
    series: &ErrorSeries,
) -> io::Result<()> {
    let text = rsts_plots::render_svg(&chart(motion, report, series)).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("--svg {}: {e}", svg.display()),
        )
    })?;
    rsts_io::write_atomic(svg, text.as_bytes())
        .map_err(|e| io::Error::new(e.kind(), format!("--svg {}: {e}", svg.display())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::NoObserver;
    use crate::metrics::{SampleErrors, StateSnapshot};

    fn record(index: usize, t: f64, y: f64) -> SampleRecord {
        SampleRecord {
            index,
            t,
            exact: StateSnapshot::NAN,
            integrated: StateSnapshot::NAN,
            errors: SampleErrors {
                state_error: y,
                drift_h: 2.0 * y,
                drift_k: 0.0,
                drift_g: y / 2.0,
                ..Default::default()
            },
        }
    }

    /// A value of sample i that is not monotone, so the largest of a run is not its first or last.
    fn value(i: usize) -> f64 {
        1.0 + ((i * 7919) % 101) as f64
    }

    #[test]
    fn every_sample_is_kept_up_to_max_points() {
        let mut inner = NoObserver;
        let mut r = Recorder::new(&mut inner, 1500);
        for i in 0..1500 {
            r.on_sample(&record(i, i as f64, value(i))).unwrap();
        }
        let want: Vec<(f64, f64)> = (0..1500).map(|i| (i as f64, value(i))).collect();
        assert_eq!(r.series.state_error, want);
        assert_eq!(r.series.drift_h.len(), 1500);
    }

    #[test]
    fn beyond_max_points_each_point_is_the_largest_of_its_run() {
        let n = 3 * MAX_POINTS + 5; // runs of 4 samples
        let mut inner = NoObserver;
        let mut r = Recorder::new(&mut inner, n);
        for i in 0..n {
            r.on_sample(&record(i, i as f64, value(i))).unwrap();
        }
        let runs: Vec<Vec<usize>> = (0..n)
            .collect::<Vec<_>>()
            .chunks(4)
            .map(|c| c.to_vec())
            .collect();
        assert!(r.series.state_error.len() <= MAX_POINTS);
        assert_eq!(r.series.state_error.len(), runs.len());
        for (point, run) in r.series.state_error.iter().zip(&runs) {
            let top = run.iter().map(|&i| value(i)).fold(f64::MIN, f64::max);
            assert_eq!(point.1, top, "run {run:?}");
            assert_eq!(value(point.0 as usize), top, "the time of the largest");
            assert!(run.contains(&(point.0 as usize)));
        }
        let g_top = r.series.drift_g.iter().map(|p| p.1).fold(0.0, f64::max);
        assert_eq!(g_top, 101.0 / 2.0, "the overall peak survives");
    }

    #[test]
    fn a_nan_is_the_worst_value_of_its_run() {
        let mut inner = NoObserver;
        let mut r = Recorder::new(&mut inner, 4 * MAX_POINTS);
        for i in 0..8 {
            let y = if i == 5 { f64::NAN } else { 1.0 };
            r.on_sample(&record(i, i as f64, y)).unwrap();
        }
        assert_eq!(r.series.state_error.len(), 2);
        assert!(r.series.state_error[1].1.is_nan());
    }
}
