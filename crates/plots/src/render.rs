//! The SVG of a chart: frame, grid, ticks, series, point labels and legend.

use std::fmt::Write;

use crate::axis;
use crate::axis::Label;
use crate::labels::place_labels;
use crate::{Chart, PlotError, Scale, Style, PALETTE};

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
    // A title of two lines (`"title\nsubtitle"`): the second in smaller type under the first.
    let (title, subtitle) = match chart.title.split_once('\n') {
        Some((t, sub)) => (t, Some(sub)),
        None => (chart.title.as_str(), None),
    };
    let (left, bottom) = (84.0, 58.0);
    let top = if subtitle.is_some() { 62.0 } else { 44.0 };
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
        escape(title)
    );
    if let Some(sub) = subtitle {
        let _ = writeln!(
            s,
            r##"<text class="subtitle" x="{:.1}" y="45" text-anchor="middle" font-size="12.5" fill="#333">{}</text>"##,
            left + pw / 2.0,
            escape(sub)
        );
    }
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
