//! Small SVG charts for reports: line and marker series on linear or log₁₀ axes, with ticks,
//! labels, a title and a legend — what a work-precision diagram or an error-against-time plot
//! needs, without a font or drawing dependency.
//!
//! ```
//! use rsts_plots::{Chart, Scale, Series, Style};
//! let chart = Chart {
//!     title: "Work–precision".into(),
//!     x_label: "max error".into(),
//!     y_label: "seconds".into(),
//!     x_scale: Scale::Log10,
//!     y_scale: Scale::Log10,
//!     series: vec![Series::new("dop853", vec![(1e-6, 1e-3), (1e-9, 3e-3)], Style::LineMarkers)],
//!     ..Chart::default()
//! };
//! let svg = rsts_plots::render_svg(&chart).unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

use std::fmt::Write;

/// Axis scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scale {
    #[default]
    Linear,
    Log10,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Style {
    #[default]
    Line,
    Markers,
    LineMarkers,
}

/// One named series of (x, y) points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// CSS colour; `None` takes the next colour of the palette.
    pub color: Option<String>,
    /// Dashed line (e.g. for a peer's series).
    pub dashed: bool,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            label: label.into(),
            points,
            style,
            color: None,
            dashed: false,
        }
    }
}

/// A chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub series: Vec<Series>,
    pub width: u32,
    pub height: u32,
}

impl Default for Chart {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            width: 760,
            height: 480,
        }
    }
}

/// Why a chart cannot be drawn.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PlotError {
    #[error("nothing to plot: no finite point (positive on log axes) in any series")]
    Empty,
    #[error("chart size {0}×{1} is too small")]
    TooSmall(u32, u32),
}

/// Colour-blind-friendly palette (Okabe–Ito, then greys).
pub const PALETTE: [&str; 8] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#999999",
];

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn forward(scale: Scale, v: f64) -> Option<f64> {
    match scale {
        Scale::Linear if v.is_finite() => Some(v),
        Scale::Log10 if v.is_finite() && v > 0.0 => Some(v.log10()),
        _ => None,
    }
}

/// Tick positions (in transformed units) and their labels.
fn ticks(scale: Scale, lo: f64, hi: f64) -> Vec<(f64, String)> {
    match scale {
        Scale::Log10 => {
            let (a, b) = (lo.floor() as i32, hi.ceil() as i32);
            let step = ((b - a) as f64 / 8.0).ceil().max(1.0) as i32;
            (a..=b)
                .filter(|k| k.rem_euclid(step) == 0)
                .filter(|&k| (k as f64) >= lo - 1e-9 && (k as f64) <= hi + 1e-9)
                .map(|k| (k as f64, format!("1e{k}")))
                .collect()
        }
        Scale::Linear => {
            let span = (hi - lo).max(f64::MIN_POSITIVE);
            let raw = span / 6.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * mag)
                .find(|s| *s >= raw)
                .unwrap_or(10.0 * mag);
            let first = (lo / step).ceil() as i64;
            let last = (hi / step).floor() as i64;
            (first..=last)
                .map(|k| {
                    let v = k as f64 * step;
                    let label = if (1e-3..1e5).contains(&step.abs()) {
                        let decimals = (-step.log10().floor()).max(0.0) as usize;
                        format!("{v:.decimals$}")
                    } else {
                        format!("{v:.0e}")
                    };
                    (v, label)
                })
                .collect()
        }
    }
}

/// Range of the transformed values, padded; a single value gets a unit-wide range.
fn range(values: impl Iterator<Item = f64>, scale: Scale) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return None;
    }
    if hi - lo < 1e-12 * lo.abs().max(1.0) {
        let half = if scale == Scale::Log10 {
            0.5
        } else {
            0.5 * lo.abs().max(1.0)
        };
        return Some((lo - half, hi + half));
    }
    let pad = 0.04 * (hi - lo);
    Some((lo - pad, hi + pad))
}

/// Render the chart as a standalone SVG document.
pub fn render_svg(chart: &Chart) -> Result<String, PlotError> {
    if chart.width < 200 || chart.height < 150 {
        return Err(PlotError::TooSmall(chart.width, chart.height));
    }
    let pts: Vec<Vec<(f64, f64)>> = chart
        .series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .filter_map(|&(x, y)| {
                    Some((forward(chart.x_scale, x)?, forward(chart.y_scale, y)?))
                })
                .collect()
        })
        .collect();
    let (x0, x1) =
        range(pts.iter().flatten().map(|p| p.0), chart.x_scale).ok_or(PlotError::Empty)?;
    let (y0, y1) =
        range(pts.iter().flatten().map(|p| p.1), chart.y_scale).ok_or(PlotError::Empty)?;
    let (w, h) = (chart.width as f64, chart.height as f64);
    let (left, right, top, bottom) = (78.0, 20.0, 44.0, 58.0);
    let (pw, ph) = (w - left - right, h - top - bottom);
    let sx = |x: f64| left + (x - x0) / (x1 - x0) * pw;
    let sy = |y: f64| top + ph - (y - y0) / (y1 - y0) * ph;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="Helvetica, Arial, sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="26" text-anchor="middle" font-size="15" font-weight="bold">{}</text>"#,
        w / 2.0,
        escape(&chart.title)
    );
    // Grid and ticks.
    let _ = writeln!(s, r##"<g stroke="#e3e3e3" stroke-width="1">"##);
    let xt = ticks(chart.x_scale, x0, x1);
    let yt = ticks(chart.y_scale, y0, y1);
    for (v, _) in &xt {
        let _ = writeln!(
            s,
            r#"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}"/>"#,
            sx(*v),
            top,
            top + ph
        );
    }
    for (v, _) in &yt {
        let _ = writeln!(
            s,
            r#"<line x1="{1:.1}" y1="{0:.1}" x2="{2:.1}" y2="{0:.1}"/>"#,
            sy(*v),
            left,
            left + pw
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##
    );
    for (v, label) in &xt {
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            sx(*v),
            top + ph + 18.0,
            escape(label)
        );
    }
    for (v, label) in &yt {
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"#,
            left - 6.0,
            sy(*v) + 4.0,
            escape(label)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        h - 16.0,
        escape(&chart.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        top + ph / 2.0,
        escape(&chart.y_label)
    );
    // Series.
    let mut legend = Vec::new();
    for (k, (series, p)) in chart.series.iter().zip(&pts).enumerate() {
        let color = series
            .color
            .clone()
            .unwrap_or_else(|| PALETTE[k % PALETTE.len()].to_string());
        let dash = if series.dashed {
            r#" stroke-dasharray="6 4""#
        } else {
            ""
        };
        let _ = writeln!(
            s,
            r#"<g class="series" data-label="{}">"#,
            escape(&series.label)
        );
        if matches!(series.style, Style::Line | Style::LineMarkers) && p.len() > 1 {
            let path: Vec<String> = p
                .iter()
                .map(|&(x, y)| format!("{:.2},{:.2}", sx(x), sy(y)))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{color}" stroke-width="1.8"{dash} points="{}"/>"#,
                path.join(" ")
            );
        }
        if matches!(series.style, Style::Markers | Style::LineMarkers) || p.len() == 1 {
            for &(x, y) in p {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{:.2}" cy="{:.2}" r="3.2" fill="{color}"/>"#,
                    sx(x),
                    sy(y)
                );
            }
        }
        let _ = writeln!(s, "</g>");
        if !series.label.is_empty() {
            legend.push((series.label.clone(), color, series.dashed));
        }
    }
    if !legend.is_empty() {
        let lw = 26.0
            + 7.0
                * legend
                    .iter()
                    .map(|l| l.0.chars().count())
                    .max()
                    .unwrap_or(0) as f64;
        let lx = left + pw - lw - 8.0;
        let _ = writeln!(
            s,
            r##"<rect x="{lx:.1}" y="{:.1}" width="{lw:.1}" height="{:.1}" fill="white" fill-opacity="0.85" stroke="#bbb"/>"##,
            top + 8.0,
            8.0 + 16.0 * legend.len() as f64
        );
        for (i, (label, color, dashed)) in legend.iter().enumerate() {
            let y = top + 20.0 + 16.0 * i as f64;
            let dash = if *dashed {
                r#" stroke-dasharray="6 4""#
            } else {
                ""
            };
            let _ = writeln!(
                s,
                r#"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{color}" stroke-width="2.5"{dash}/>"#,
                lx + 5.0,
                lx + 21.0
            );
            let _ = writeln!(
                s,
                r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
                lx + 25.0,
                y + 4.0,
                escape(label)
            );
        }
    }
    s.push_str("</svg>\n");
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chart(series: Vec<Series>, x: Scale, y: Scale) -> Chart {
        Chart {
            title: "t <1>".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            x_scale: x,
            y_scale: y,
            series,
            ..Chart::default()
        }
    }

    #[test]
    fn log_axes_get_decade_ticks_and_points_land_inside_the_frame() {
        let c = chart(
            vec![Series::new(
                "a&b",
                vec![(1e-12, 1e-4), (1e-6, 1e-2), (1e-3, 1.0)],
                Style::LineMarkers,
            )],
            Scale::Log10,
            Scale::Log10,
        );
        let svg = render_svg(&c).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(
            svg.contains(">1e-6<") && svg.contains(">1e-2<"),
            "decade labels"
        );
        assert!(
            svg.contains("a&amp;b") && svg.contains("t &lt;1&gt;"),
            "text is escaped"
        );
        assert_eq!(svg.matches("<circle").count(), 3);
        for cap in svg.split("<circle cx=\"").skip(1) {
            let x: f64 = cap.split('"').next().unwrap().parse().unwrap();
            assert!((78.0..=740.0).contains(&x), "{x}");
        }
    }

    #[test]
    fn non_positive_values_are_dropped_on_log_axes_and_empty_charts_are_errors() {
        let c = chart(
            vec![Series::new(
                "s",
                vec![(0.0, 1.0), (-1.0, 2.0), (f64::NAN, 3.0)],
                Style::Markers,
            )],
            Scale::Log10,
            Scale::Linear,
        );
        assert_eq!(render_svg(&c), Err(PlotError::Empty));
        let c = chart(
            vec![Series::new(
                "s",
                vec![(0.0, 1.0), (2.0, 2.0)],
                Style::Markers,
            )],
            Scale::Log10,
            Scale::Linear,
        );
        assert_eq!(render_svg(&c).unwrap().matches("<circle").count(), 1);
        let mut small = chart(vec![], Scale::Linear, Scale::Linear);
        small.width = 10;
        assert!(render_svg(&small).is_err());
    }

    #[test]
    fn linear_ticks_are_round_numbers() {
        let t = ticks(Scale::Linear, 0.0, 10.0);
        let labels: Vec<&str> = t.iter().map(|x| x.1.as_str()).collect();
        assert_eq!(labels, ["0", "2", "4", "6", "8", "10"]);
    }
}
