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

mod axis;

use std::fmt::Write;

use axis::Label;

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
    /// A short text beside each point (e.g. the tolerance it was run at); empty: none.
    pub point_labels: Vec<String>,
    /// A shaded band in the series' colour, drawn under it: pairs (one edge, other edge) of
    /// points, the area between the two edges (e.g. the 5 % and 95 % percentiles); empty: none.
    pub band: Vec<((f64, f64), (f64, f64))>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            label: label.into(),
            points,
            style,
            color: None,
            dashed: false,
            point_labels: Vec::new(),
            band: Vec::new(),
        }
    }

    /// The same series with `labels[k]` written beside point k.
    pub fn with_point_labels(mut self, labels: Vec<String>) -> Self {
        self.point_labels = labels;
        self
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

impl Chart {
    /// A log–log chart of the reports' size (820×540): work–precision, tolerance
    /// proportionality, observed order.
    pub fn log_log(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Log10,
            y_scale: Scale::Log10,
            series,
            width: 820,
            height: 540,
        }
    }
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

/// SVG text of a tick label: `10` with the exponent raised, `2×10⁻⁶`, or plain.
fn label_svg(label: &Label) -> String {
    match label {
        Label::Plain(s) => escape(s),
        Label::Power { mantissa, exponent } => {
            let m = mantissa.as_ref().map_or(String::new(), |m| format!("{m}×"));
            match exponent {
                0 if m.is_empty() => "1".into(),
                1 if m.is_empty() => "10".into(),
                e => format!(
                    r#"{m}10<tspan dy="-5" font-size="9">{}</tspan>"#,
                    e.to_string().replace('-', "−")
                ),
            }
        }
    }
}

/// An axis-aligned box (x0, y0, x1, y1) in px.
type Rect = (f64, f64, f64, f64);

fn overlap(a: Rect, b: Rect) -> f64 {
    let w = (a.2.min(b.2) - a.0.max(b.0)).max(0.0);
    let h = (a.3.min(b.3) - a.1.max(b.1)).max(0.0);
    w * h
}

/// Positions of the point labels: beside each marker, where the label covers no other label, no
/// marker and stays inside the plot (the least covered place when none is free).
/// `points`: (x, y, text width) per label; returns (x, y, text-anchor) per label.
fn place_labels(points: &[(f64, f64, f64)], plot: Rect) -> Vec<(f64, f64, &'static str)> {
    const H: f64 = 10.0;
    let markers: Vec<Rect> = points
        .iter()
        .map(|&(x, y, _)| (x - 4.0, y - 4.0, x + 4.0, y + 4.0))
        .collect();
    let mut placed: Vec<Rect> = Vec::new();
    let mut out = Vec::new();
    for &(x, y, w) in points {
        // (dx, dy of the baseline, anchor): right, left, above, below, the diagonals.
        let candidates = [
            (7.0, 4.0, "start"),
            (-7.0, 4.0, "end"),
            (0.0, -8.0, "middle"),
            (0.0, 16.0, "middle"),
            (6.0, -6.0, "start"),
            (6.0, 15.0, "start"),
            (-6.0, -6.0, "end"),
            (-6.0, 15.0, "end"),
        ];
        let rect = |(dx, dy, anchor): (f64, f64, &str)| {
            let x0 = match anchor {
                "start" => x + dx,
                "end" => x + dx - w,
                _ => x + dx - w / 2.0,
            };
            (x0, y + dy - H + 1.0, x0 + w, y + dy + 2.0)
        };
        let cost = |c: (f64, f64, &str)| {
            let r = rect(c);
            let outside = if r.0 < plot.0 || r.2 > plot.2 || r.1 < plot.1 || r.3 > plot.3 {
                1e6
            } else {
                0.0
            };
            let covered: f64 = placed.iter().chain(&markers).map(|p| overlap(r, *p)).sum();
            outside + covered
        };
        let best = candidates
            .iter()
            .copied()
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap();
        placed.push(rect(best));
        out.push((x + best.0, y + best.1, best.2));
    }
    out
}

/// Render the chart as a standalone SVG document: the plot frame with its grid, ticks labelled on
/// both axes, the series (and their point labels), and the legend to the right of the frame,
/// clear of the data.
pub fn render_svg(chart: &Chart) -> Result<String, PlotError> {
    if chart.width < 200 || chart.height < 150 {
        return Err(PlotError::TooSmall(chart.width, chart.height));
    }
    let pts: Vec<Vec<(f64, f64, Option<&str>)>> = chart
        .series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .enumerate()
                .filter_map(|(k, &(x, y))| {
                    Some((
                        forward(chart.x_scale, x)?,
                        forward(chart.y_scale, y)?,
                        s.point_labels.get(k).map(String::as_str),
                    ))
                })
                .collect()
        })
        .collect();
    let extent = |values: Vec<f64>| -> Option<(f64, f64)> {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        lo.is_finite().then_some((lo, hi))
    };
    // Each band as its polygon: one edge forward, the other back (points off the axes dropped).
    let bands: Vec<Vec<(f64, f64)>> = chart
        .series
        .iter()
        .map(|s| {
            let on_axes =
                |(x, y): (f64, f64)| Some((forward(chart.x_scale, x)?, forward(chart.y_scale, y)?));
            let mut polygon: Vec<(f64, f64)> = s.band.iter().filter_map(|b| on_axes(b.0)).collect();
            polygon.extend(s.band.iter().rev().filter_map(|b| on_axes(b.1)));
            polygon
        })
        .collect();
    let all = || {
        pts.iter()
            .flatten()
            .map(|p| (p.0, p.1))
            .chain(bands.iter().flatten().copied())
    };
    let (x0, x1) = extent(all().map(|p| p.0).collect()).ok_or(PlotError::Empty)?;
    let (y0, y1) = extent(all().map(|p| p.1).collect()).ok_or(PlotError::Empty)?;
    let (x0, x1) = axis::range(x0, x1, chart.x_scale);
    let (y0, y1) = axis::range(y0, y1, chart.y_scale);
    let (w, h) = (chart.width as f64, chart.height as f64);
    // The legend: a column right of the frame.
    let legend: Vec<(&str, String, bool)> = chart
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
        .map(|(k, s)| {
            let color = s
                .color
                .clone()
                .unwrap_or_else(|| PALETTE[k % PALETTE.len()].to_string());
            (s.label.as_str(), color, s.dashed)
        })
        .collect();
    let legend_w = if legend.is_empty() {
        0.0
    } else {
        40.0 + 6.7
            * legend
                .iter()
                .map(|l| l.0.chars().count())
                .max()
                .unwrap_or(0) as f64
    };
    let (left, top, bottom) = (84.0, 44.0, 58.0);
    let right = 20.0
        + if legend.is_empty() {
            0.0
        } else {
            legend_w + 14.0
        };
    let (pw, ph) = (w - left - right, h - top - bottom);
    if pw < 80.0 || ph < 60.0 {
        return Err(PlotError::TooSmall(chart.width, chart.height));
    }
    let sx = |x: f64| left + (x - x0) / (x1 - x0) * pw;
    let sy = |y: f64| top + ph - (y - y0) / (y1 - y0) * ph;
    let xt = axis::ticks(chart.x_scale, x0, x1, pw, 58.0);
    let yt = axis::ticks(chart.y_scale, y0, y1, ph, 22.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="Helvetica, Arial, sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="26" text-anchor="middle" font-size="15" font-weight="bold">{}</text>"#,
        left + pw / 2.0,
        escape(&chart.title)
    );
    // Grid at the major ticks; short marks at all ticks.
    let _ = writeln!(s, r##"<g stroke="#e3e3e3" stroke-width="1">"##);
    for t in xt.iter().filter(|t| t.major) {
        let _ = writeln!(
            s,
            r#"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}"/>"#,
            sx(t.at),
            top,
            top + ph
        );
    }
    for t in yt.iter().filter(|t| t.major) {
        let _ = writeln!(
            s,
            r#"<line x1="{1:.1}" y1="{0:.1}" x2="{2:.1}" y2="{0:.1}"/>"#,
            sy(t.at),
            left,
            left + pw
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(s, r##"<g stroke="#444" stroke-width="1">"##);
    for t in &xt {
        let len = if t.major { 6.0 } else { 3.5 };
        let _ = writeln!(
            s,
            r#"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}"/>"#,
            sx(t.at),
            top + ph,
            top + ph - len
        );
    }
    for t in &yt {
        let len = if t.major { 6.0 } else { 3.5 };
        let _ = writeln!(
            s,
            r#"<line x1="{1:.1}" y1="{0:.1}" x2="{2:.1}" y2="{0:.1}"/>"#,
            sy(t.at),
            left,
            left + len
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##
    );
    for t in &xt {
        if let Some(label) = &t.label {
            let _ = writeln!(
                s,
                r#"<text class="tick x" data-v="{}" x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
                t.value,
                sx(t.at),
                top + ph + 19.0,
                label_svg(label)
            );
        }
    }
    for t in &yt {
        if let Some(label) = &t.label {
            let _ = writeln!(
                s,
                r#"<text class="tick y" data-v="{}" x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"#,
                t.value,
                left - 7.0,
                sy(t.at) + 4.0,
                label_svg(label)
            );
        }
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        h - 14.0,
        escape(&chart.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        top + ph / 2.0,
        escape(&chart.y_label)
    );
    // Bands under the series.
    for (k, (series, polygon)) in chart.series.iter().zip(&bands).enumerate() {
        if polygon.len() < 3 {
            continue;
        }
        let color = series
            .color
            .clone()
            .unwrap_or_else(|| PALETTE[k % PALETTE.len()].to_string());
        let path: Vec<String> = polygon
            .iter()
            .map(|&(x, y)| format!("{:.2},{:.2}", sx(x), sy(y)))
            .collect();
        let _ = writeln!(
            s,
            r#"<polygon class="band" data-label="{}" fill="{color}" fill-opacity="0.18" stroke="none" points="{}"/>"#,
            escape(&series.label),
            path.join(" ")
        );
    }
    // Series.
    let mut labels: Vec<(f64, f64, f64, String, String)> = Vec::new();
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
                .map(|&(x, y, _)| format!("{:.2},{:.2}", sx(x), sy(y)))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{color}" stroke-width="1.8"{dash} points="{}"/>"#,
                path.join(" ")
            );
        }
        if matches!(series.style, Style::Markers | Style::LineMarkers) || p.len() == 1 {
            for &(x, y, _) in p {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{:.2}" cy="{:.2}" r="3.2" fill="{color}"/>"#,
                    sx(x),
                    sy(y)
                );
            }
        }
        let _ = writeln!(s, "</g>");
        for &(x, y, text) in p {
            if let Some(text) = text.filter(|t| !t.is_empty()) {
                let width = 5.6 * text.chars().count() as f64;
                labels.push((sx(x), sy(y), width, text.to_string(), color.clone()));
            }
        }
    }
    if !labels.is_empty() {
        let at: Vec<(f64, f64, f64)> = labels.iter().map(|l| (l.0, l.1, l.2)).collect();
        let places = place_labels(&at, (left, top, left + pw, top + ph));
        let _ = writeln!(
            s,
            r#"<g class="point-labels" font-size="10" stroke="white" stroke-width="3" paint-order="stroke">"#
        );
        for ((_, _, _, text, color), (x, y, anchor)) in labels.iter().zip(places) {
            let _ = writeln!(
                s,
                r#"<text x="{x:.1}" y="{y:.1}" text-anchor="{anchor}" fill="{color}">{}</text>"#,
                escape(text)
            );
        }
        let _ = writeln!(s, "</g>");
    }
    if !legend.is_empty() {
        let lx = left + pw + 14.0;
        let _ = writeln!(
            s,
            r##"<g class="legend"><rect x="{lx:.1}" y="{top:.1}" width="{legend_w:.1}" height="{:.1}" fill="white" stroke="#bbb"/>"##,
            10.0 + 18.0 * legend.len() as f64
        );
        for (i, (label, color, dashed)) in legend.iter().enumerate() {
            let y = top + 15.0 + 18.0 * i as f64;
            let dash = if *dashed {
                r#" stroke-dasharray="6 4""#
            } else {
                ""
            };
            let _ = writeln!(
                s,
                r#"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{color}" stroke-width="2.5"{dash}/>"#,
                lx + 7.0,
                lx + 29.0
            );
            let _ = writeln!(
                s,
                r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
                lx + 34.0,
                y + 4.0,
                escape(label)
            );
        }
        let _ = writeln!(s, "</g>");
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

    /// The values of an attribute over the elements that carry `marker`.
    fn attrs(svg: &str, marker: &str, key: &str) -> Vec<String> {
        svg.lines()
            .filter(|l| l.contains(marker))
            .filter_map(|l| {
                let rest = l.split(&format!(r#" {key}=""#)).nth(1)?;
                Some(rest.split('"').next()?.to_string())
            })
            .collect()
    }

    fn num(svg: &str, marker: &str, key: &str) -> Vec<f64> {
        attrs(svg, marker, key)
            .iter()
            .map(|v| v.parse().unwrap())
            .collect()
    }

    #[test]
    fn log_axes_are_labelled_every_decade_and_points_land_inside_the_frame() {
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
        let x: Vec<String> = attrs(&svg, r#"class="tick x""#, "data-v");
        let want: Vec<String> = (-12..=-3).map(|k| format!("1e{k}")).collect();
        assert_eq!(x, want, "a label at every decade of the x axis");
        let y = attrs(&svg, r#"class="tick y""#, "data-v");
        assert_eq!(y, ["1e-4", "1e-3", "1e-2", "1e-1", "1e0"]);
        assert!(svg.contains(r#"10<tspan dy="-5" font-size="9">−6</tspan>"#));
        assert!(
            svg.contains("a&amp;b") && svg.contains("t &lt;1&gt;"),
            "text is escaped"
        );
        let (fx, fw) = (
            num(&svg, r##"fill="none" stroke="#444""##, "x")[0],
            num(&svg, r##"fill="none" stroke="#444""##, "width")[0],
        );
        let cx = num(&svg, "<circle", "cx");
        assert_eq!(cx.len(), 3);
        assert!(cx.iter().all(|x| *x > fx && *x < fx + fw), "{cx:?}");
    }

    #[test]
    fn the_legend_is_right_of_the_frame_and_point_labels_do_not_collide() {
        // Two series with points close together, each point labelled with its tolerance.
        let tolerances = ["1e-6", "1e-8", "1e-10", "1e-12"];
        let mk = |name: &str, shift: f64| {
            Series::new(
                name,
                (0..4)
                    .map(|k| {
                        (
                            10f64.powi(-6 - 2 * k) * shift,
                            1e-3 * (k + 1) as f64 * shift,
                        )
                    })
                    .collect(),
                Style::LineMarkers,
            )
            .with_point_labels(tolerances.iter().map(|t| t.to_string()).collect())
        };
        let c = chart(
            vec![mk("dop853", 1.0), mk("a much longer name", 1.15)],
            Scale::Log10,
            Scale::Log10,
        );
        let svg = render_svg(&c).unwrap();
        let frame_right = num(&svg, r##"fill="none" stroke="#444""##, "x")[0]
            + num(&svg, r##"fill="none" stroke="#444""##, "width")[0];
        let legend_x = num(&svg, r#"<g class="legend"><rect"#, "x")[0];
        assert!(legend_x > frame_right, "{legend_x} {frame_right}");
        let legend_right = legend_x + num(&svg, r#"<g class="legend"><rect"#, "width")[0];
        assert!(legend_right <= c.width as f64, "{legend_right}");
        // Every point has its label, and no two label boxes overlap.
        let block = svg.split(r#"<g class="point-labels""#).nth(1).unwrap();
        let block = block.split("</g>").next().unwrap();
        let boxes: Vec<Rect> = block
            .lines()
            .filter(|l| l.starts_with("<text"))
            .map(|l| {
                let get = |k: &str| num(l, "<text", k)[0];
                let text = l.split('>').nth(1).unwrap().split('<').next().unwrap();
                let w = 5.6 * text.chars().count() as f64;
                let x0 = match attrs(l, "<text", "text-anchor")[0].as_str() {
                    "start" => get("x"),
                    "end" => get("x") - w,
                    _ => get("x") - w / 2.0,
                };
                (x0, get("y") - 9.0, x0 + w, get("y") + 2.0)
            })
            .collect();
        assert_eq!(boxes.len(), 8);
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[i + 1..] {
                assert_eq!(overlap(*a, *b), 0.0, "{a:?} {b:?}");
            }
        }
        for t in tolerances {
            assert_eq!(block.matches(&format!(">{t}<")).count(), 2, "{t}");
        }
    }

    /// A band is one polygon in its series' colour, its edges at the points given (the low
    /// edge forward, the high edge back), inside the frame, which widens to hold it.
    #[test]
    fn a_band_is_shaded_between_its_edges() {
        let mut s = Series::new(
            "dop853",
            vec![(1e-8, 1e-3), (1e-10, 2e-3), (1e-12, 4e-3)],
            Style::LineMarkers,
        );
        s.band = vec![
            ((1e-9, 1e-3), (1e-7, 1e-3)),
            ((1e-11, 2e-3), (1e-9, 2e-3)),
            ((1e-13, 4e-3), (1e-11, 4e-3)),
        ];
        s.color = Some("#D55E00".into());
        let svg = render_svg(&chart(vec![s], Scale::Log10, Scale::Log10)).unwrap();
        let band: Vec<&str> = svg
            .lines()
            .filter(|l| l.contains(r#"class="band""#))
            .collect();
        assert_eq!(band.len(), 1, "{svg}");
        assert!(band[0].contains(r##"fill="#D55E00""##));
        let pts: Vec<(f64, f64)> = attrs(band[0], "<polygon", "points")[0]
            .split(' ')
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        assert_eq!(pts.len(), 6);
        // Low edge forward, high edge back: x of points 0 and 5 (same y) differ by 2 decades.
        assert_eq!(pts[0].1, pts[5].1);
        assert!(pts[5].0 > pts[0].0);
        let x: Vec<String> = attrs(&svg, r#"class="tick x""#, "data-v");
        assert_eq!(
            x.first().map(String::as_str),
            Some("1e-13"),
            "the axis holds the band"
        );
        assert_eq!(x.last().map(String::as_str), Some("1e-7"));
        assert!(
            svg.find(r#"class="band""#) < svg.find(r#"class="series""#),
            "drawn under the line"
        );
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
}
