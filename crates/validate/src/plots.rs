//! SVG plots of a report: error against time per (case, torus), work–precision per case with
//! several tolerances, and the (m, h) diagram of each field pair with the case points coloured
//! pass/fail.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use rsts_closed_form::diagram::{diagram_svg, DiagramOptions};
use rsts_plots::{render_svg, Chart, Scale, Series, Style};

use crate::report::Report;
use crate::run::{RunResult, Status};
use crate::ValidateError;

/// Colours of the case points.
pub const PASS_COLOUR: &str = "#1a9850";
pub const FAIL_COLOUR: &str = "#d73027";

/// A file name from a case name and torus.
/// A file-name-safe form of a case name, at most 80 characters: a longer name keeps its first
/// 63 characters and a 16-hex-digit hash of the whole name (so any case name gives a file that
/// the file system accepts, and distinct names stay distinct).
fn slug(s: &str) -> String {
    let safe: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if safe.len() <= 80 {
        return safe;
    }
    // FNV-1a 64: stable across runs and platforms.
    let hash = s.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{}-{hash:016x}", &safe[..63])
}

fn method_label(r: &RunResult) -> String {
    match (r.rtol, r.digits) {
        (Some(t), Some(d)) => format!("{}@{t:e}/{d}d", r.method),
        (Some(t), None) => format!("{}@{t:e}", r.method),
        _ => r.method.clone(),
    }
}

/// The error-against-time chart of the integrator runs of one (case, torus).
pub fn error_chart(case: &str, torus: usize, runs: &[&RunResult]) -> Chart {
    let mut series = Vec::new();
    for r in runs.iter().filter(|r| r.figures.is_some()) {
        let pts = |v: &[f64]| r.series.t.iter().copied().zip(v.iter().copied()).collect();
        series.push(Series::new(
            method_label(r),
            pts(&r.series.state_error),
            Style::Line,
        ));
        // The distance from N, as the axis label says (off_N, the drift of the on-N integral
        // relations, stays near round-off while the state leaves N: camera V).
        let finite = |v: &[f64]| -> Vec<(f64, f64)> {
            r.series
                .t
                .iter()
                .copied()
                .zip(v.iter().copied())
                .filter(|(_, y)| y.is_finite())
                .collect()
        };
        if !r.series.distance_from_n.is_empty() {
            let mut dist = Series::new(
                format!("{} distance from N", method_label(r)),
                finite(&r.series.distance_from_n),
                Style::Line,
            );
            dist.dashed = true;
            series.push(dist);
        }
    }
    let camera = runs.first().map(|r| r.camera.as_str()).unwrap_or("");
    Chart {
        title: format!("{case} (camera {camera}, torus {torus}): error against time"),
        x_label: "t".into(),
        y_label: "max |x_int − x_exact| (solid), distance from N (dashed)".into(),
        x_scale: Scale::Linear,
        y_scale: Scale::Log10,
        series,
        ..Chart::default()
    }
}

/// Work–precision of one case: per method, integration time against max error over tolerances
/// (the lowest torus of the case).
pub fn work_precision_chart(case: &str, runs: &[&RunResult]) -> Option<Chart> {
    let torus = runs.iter().map(|r| r.torus).min()?;
    // (max error, seconds, rtol) per method.
    let mut by_method: BTreeMap<String, Vec<(f64, f64, Option<f64>)>> = BTreeMap::new();
    for r in runs.iter().filter(|r| r.torus == torus) {
        if let Some(f) = &r.figures {
            let key = match r.digits {
                Some(d) => format!("{} ({d} digits)", r.method),
                None => r.method.clone(),
            };
            by_method.entry(key).or_default().push((
                f.max_state_error,
                r.timing.integration_seconds,
                r.rtol,
            ));
        }
    }
    if !by_method.values().any(|v| v.len() >= 2) {
        return None;
    }
    let series = by_method
        .into_iter()
        .map(|(m, mut pts)| {
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            // Each point labelled with the tolerance it ran at.
            let labels = pts
                .iter()
                .map(|p| p.2.map_or(String::new(), |t| format!("{t:e}")))
                .collect();
            Series::new(
                m,
                pts.iter().map(|p| (p.0, p.1)).collect(),
                Style::LineMarkers,
            )
            .with_point_labels(labels)
        })
        .collect();
    Some(Chart {
        title: format!("{case} (torus {torus}): work against precision"),
        x_label: "max state error".into(),
        y_label: "integration time (s)".into(),
        x_scale: Scale::Log10,
        y_scale: Scale::Log10,
        series,
        ..Chart::default()
    })
}

/// The number after `key="` in `tag`.
fn attr(tag: &str, key: &str) -> Option<String> {
    let start = tag.find(&format!(" {key}=\""))? + key.len() + 3;
    let len = tag[start..].find('"')?;
    Some(tag[start..start + len].to_string())
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Draw points (m, h, pass, label) on a diagram SVG: the map from (m, h) to px is read from the
/// main frame's `data-window` and its x, y, width, height. Points outside the window are left
/// out; returns the new SVG and the number drawn.
pub fn overlay_points(svg: &str, points: &[(f64, f64, bool, String)]) -> Option<(String, usize)> {
    let start = svg.find(r#"<rect class="frame""#)?;
    let tag = &svg[start..start + svg[start..].find('>')?];
    let win: Vec<f64> = attr(tag, "data-window")?
        .split_whitespace()
        .map(|x| x.parse().ok())
        .collect::<Option<_>>()?;
    let num = |k: &str| attr(tag, k).and_then(|v| v.parse::<f64>().ok());
    let (x0, y0, w, h) = (num("x")?, num("y")?, num("width")?, num("height")?);
    let [m_lo, m_hi, h_lo, h_hi] = win[..] else {
        return None;
    };
    let mut g =
        String::from("<g class=\"validation-points\" stroke=\"#000000\" stroke-width=\"0.8\">\n");
    let mut drawn = 0;
    // Failures last, so they are on top.
    let mut order: Vec<&(f64, f64, bool, String)> = points.iter().collect();
    order.sort_by_key(|p| !p.2);
    for (m, hh, pass, label) in order {
        if !(m_lo..=m_hi).contains(m) || !(h_lo..=h_hi).contains(hh) {
            continue;
        }
        let px = x0 + (m - m_lo) / (m_hi - m_lo) * w;
        let py = y0 + (h_hi - hh) / (h_hi - h_lo) * h;
        let _ = writeln!(
            g,
            r#"<circle class="case-point" data-pass="{pass}" data-m="{m}" data-h="{hh}" cx="{px:.2}" cy="{py:.2}" r="4.5" fill="{}"><title>{} ({})</title></circle>"#,
            if *pass { PASS_COLOUR } else { FAIL_COLOUR },
            xml_escape(label),
            if *pass { "pass" } else { "FAIL" }
        );
        drawn += 1;
    }
    let _ = writeln!(
        g,
        r#"<text x="{:.1}" y="{:.1}" font-size="12" stroke="none"><tspan fill="{PASS_COLOUR}">● pass</tspan> <tspan fill="{FAIL_COLOUR}">● fail</tspan> ({drawn} case points)</text>"#,
        x0 + 8.0,
        y0 + h - 8.0
    );
    g.push_str("</g>\n");
    let end = svg.rfind("</svg>")?;
    Some((format!("{}{}{}", &svg[..end], g, &svg[end..]), drawn))
}

/// Case → (m, h, all runs passed).
type CasePoints<'a> = BTreeMap<&'a str, (f64, f64, bool)>;

/// Write every plot of the report into `dir/plots`; returns (relative file, title) for report.md.
pub fn write_plots(report: &Report, dir: &Path) -> Result<Vec<(String, String)>, ValidateError> {
    let pdir = dir.join("plots");
    std::fs::create_dir_all(&pdir)
        .map_err(|e| ValidateError::Io(format!("cannot create {}: {e}", pdir.display())))?;
    let mut out = Vec::new();
    let mut put = |name: String, title: String, svg: &str| -> Result<(), ValidateError> {
        let p = pdir.join(&name);
        std::fs::write(&p, svg)
            .map_err(|e| ValidateError::Io(format!("cannot write {}: {e}", p.display())))?;
        out.push((format!("plots/{name}"), title));
        Ok(())
    };
    // (case, torus) → runs; case → runs.
    let mut by_motion: BTreeMap<(&str, usize), Vec<&RunResult>> = BTreeMap::new();
    let mut by_case: BTreeMap<&str, Vec<&RunResult>> = BTreeMap::new();
    for r in &report.runs {
        by_motion.entry((&r.case, r.torus)).or_default().push(r);
        by_case.entry(&r.case).or_default().push(r);
    }
    for ((case, torus), runs) in &by_motion {
        let chart = error_chart(case, *torus, runs);
        if let Ok(svg) = render_svg(&chart) {
            put(
                format!("error-{}-t{torus}.svg", slug(case)),
                chart.title.clone(),
                &svg,
            )?;
        }
    }
    for (case, runs) in &by_case {
        if let Some(chart) = work_precision_chart(case, runs) {
            if let Ok(svg) = render_svg(&chart) {
                put(
                    format!("work-precision-{}.svg", slug(case)),
                    chart.title.clone(),
                    &svg,
                )?;
            }
        }
    }
    // One diagram per field pair; a case point passes when all its runs pass.
    let mut fields: BTreeMap<(u64, u64), CasePoints> = BTreeMap::new();
    for r in &report.runs {
        let e = fields
            .entry((r.a.to_bits(), r.b.to_bits()))
            .or_default()
            .entry(&r.case)
            .or_insert((r.m, r.h, true));
        e.2 &= r.status == Status::Pass;
    }
    for ((a, b), cases) in &fields {
        let (a, b) = (f64::from_bits(*a), f64::from_bits(*b));
        let opts = DiagramOptions {
            title: Some(format!("Validation cases, a = {a}, b = {b}")),
            ..DiagramOptions::default()
        };
        let Ok(svg) = diagram_svg(a, b, &opts) else {
            continue;
        };
        let points: Vec<(f64, f64, bool, String)> = cases
            .iter()
            .map(|(c, (m, h, ok))| (*m, *h, *ok, format!("{c}: m = {m}, h = {h}")))
            .collect();
        if let Some((svg, drawn)) = overlay_points(&svg, &points) {
            put(
                format!("diagram-a{a}-b{b}.svg"),
                format!(
                    "(m, h) diagram, a = {a}, b = {b}: {drawn} of {} case points in the window, coloured pass/fail",
                    points.len()
                ),
                &svg,
            )?;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_are_drawn_where_the_frame_maps_them() {
        let svg = diagram_svg(1.0, 0.5, &DiagramOptions::default()).unwrap();
        let pts = vec![
            (0.3, -0.375, true, "I+".to_string()),
            (-0.7092, 1.5643, false, "V <bad>".to_string()),
            (100.0, 0.0, true, "outside".to_string()),
        ];
        let (out, drawn) = overlay_points(&svg, &pts).unwrap();
        assert_eq!(drawn, 2);
        assert_eq!(out.matches("class=\"case-point\"").count(), 2);
        assert!(out.contains(&format!("fill=\"{FAIL_COLOUR}\"><title>V &lt;bad&gt;")));
        assert!(out.trim_end().ends_with("</svg>"));
        // I+ (m = 0.3) lies right of V (m = −0.7092).
        let cx = |tag: &str| -> f64 {
            let i = out.find(tag).unwrap();
            let end = i + out[i..].find('>').unwrap();
            attr(&out[i - 1..end], "cx").unwrap().parse().unwrap()
        };
        assert!(cx("data-m=\"0.3\" data-h=\"-0.375\"") > cx("data-m=\"-0.7092\" data-h"));
    }
}
