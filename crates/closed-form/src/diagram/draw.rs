//! SVG drawing of one plot (cameras, m = 0, Σ), its axes and its labels, with the colours and
//! number formatting they use.

use std::fmt::Write as _;

use crate::camera::Camera;
use crate::constants::SigmaCurve;

use super::labels::LabelPlacement;
use super::regions::{camera_chains, simplify_ring, Chain, Frame, Geometry};
use super::tori_text;

pub(super) fn fmt_px(x: f64) -> String {
    let s = format!("{x:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn fmt_tick(x: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10()).ceil().max(0.0) as usize
    };
    let s = format!("{x:.decimals$}");
    let s = if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    };
    s.replace('-', "−")
}

fn nice_step(span: f64, target: f64) -> f64 {
    let raw = span / target;
    let mag = 10f64.powf(raw.log10().floor());
    let r = raw / mag;
    let nice = if r < 1.5 {
        1.0
    } else if r < 3.5 {
        2.0
    } else if r < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

pub(super) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Fill colour of each camera: one hue per Roman numeral, lighter for the part with m > 0.
pub(super) fn camera_colour(c: Camera) -> &'static str {
    match c {
        Camera::IPlus => "#fde3c4",
        Camera::IMinus => "#f9c58d",
        Camera::IIPlus => "#d3e6f8",
        Camera::IIMinus => "#a9cdef",
        Camera::III => "#dcd0ef",
        Camera::IVPlus => "#d5eed2",
        Camera::IVMinus => "#aedba8",
        Camera::V => "#f6eba0",
        Camera::VI => "#f6c4d2",
    }
}

/// Size (px) of a camera label (the name over the number of tori), to end leader lines at.
const LABEL_W: f64 = 36.0;
const LABEL_H: f64 = 27.0;

/// Write the clip path, background, camera fills, the line m = 0 and Σ of one plot; return the
/// camera polygons. `prefix` makes the ids unique ("" for the main plot).
pub(super) fn draw_plot(
    s: &mut String,
    g: &Geometry,
    f: &Frame,
    prefix: &str,
    stroke_scale: f64,
) -> Vec<Chain> {
    let clip = format!("{prefix}plot-area");
    let _ = writeln!(
        s,
        r#"<defs><clipPath id="{clip}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath></defs>"#,
        fmt_px(f.x0),
        fmt_px(f.y0),
        fmt_px(f.w),
        fmt_px(f.h)
    );
    // Inadmissible background.
    let _ = writeln!(
        s,
        r##"<rect class="inadmissible" x="{}" y="{}" width="{}" height="{}" fill="#f2f2f2"/>"##,
        fmt_px(f.x0),
        fmt_px(f.y0),
        fmt_px(f.w),
        fmt_px(f.h)
    );
    // Cameras.
    let chains = camera_chains(g, f);
    let _ = writeln!(s, r#"<g class="cameras" clip-path="url(#{clip})">"#);
    for camera in Camera::ALL {
        let mut d = String::new();
        for ch in chains.iter().filter(|c| c.camera == camera) {
            let ring: Vec<(f64, f64)> = ch
                .upper
                .iter()
                .chain(ch.lower.iter().rev())
                .map(|&(m, h)| (f.px(m), f.py(h)))
                .collect();
            let ring = simplify_ring(&ring, 0.05);
            if ring.len() < 3 {
                continue;
            }
            for (k, (x, y)) in ring.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{},{}",
                    if k == 0 { "M" } else { "L" },
                    fmt_px(*x),
                    fmt_px(*y)
                );
            }
            d.push('Z');
        }
        if d.is_empty() {
            continue;
        }
        let col = camera_colour(camera);
        let _ = writeln!(
            s,
            r#"<path class="camera" data-camera="{}" d="{d}" fill="{col}" stroke="{col}" stroke-width="0.8" stroke-linejoin="round"/>"#,
            camera.label()
        );
    }
    let _ = writeln!(s, "</g>");

    // m = 0 (not part of Σ: it splits I, II, IV into their ± parts).
    if f.m_lo < 0.0 && f.m_hi > 0.0 {
        let x = fmt_px(f.px(0.0));
        let _ = writeln!(
            s,
            r##"<line class="m-zero" x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#555555" stroke-width="1" stroke-dasharray="5,4"/>"##,
            fmt_px(f.y0),
            fmt_px(f.y0 + f.h)
        );
    }

    // Σ.
    let (m_lo, m_hi, h_lo, h_hi) = (f.m_lo, f.m_hi, f.h_lo, f.h_hi);
    let _ = writeln!(
        s,
        r#"<g class="sigma-curves" clip-path="url(#{clip})" fill="none" stroke-linecap="round" stroke-linejoin="round">"#
    );
    for c in SigmaCurve::ALL {
        let (d0, d1) = g.domain(c);
        let lo = d0.max(m_lo);
        let hi = d1.min(m_hi);
        if lo >= hi {
            continue;
        }
        let mut d = String::new();
        if c == SigmaCurve::Hyperbola {
            // Sample densely in m and in h; keep the part in (a little beyond) the window.
            let mut ms: Vec<f64> = (0..=2000)
                .map(|i| lo + (hi - lo) * i as f64 / 2000.0)
                .collect();
            for i in 0..=400 {
                let level = h_lo + (h_hi - h_lo) * i as f64 / 400.0;
                ms.extend(g.crossings(c, level));
            }
            ms.retain(|m| *m >= lo && *m < hi && *m < 0.0);
            ms.sort_by(|p, q| p.total_cmp(q));
            let margin = 0.02 * (h_hi - h_lo);
            let mut pen_down = false;
            for m in ms {
                let h = g.curve_h(c, m);
                if h <= h_hi + margin && h >= h_lo - margin {
                    let _ = write!(
                        d,
                        "{}{},{}",
                        if pen_down { "L" } else { "M" },
                        fmt_px(f.px(m)),
                        fmt_px(f.py(h))
                    );
                    pen_down = true;
                } else {
                    pen_down = false;
                }
            }
        } else {
            let _ = write!(
                d,
                "M{},{}L{},{}",
                fmt_px(f.px(lo)),
                fmt_px(f.py(g.curve_h(c, lo))),
                fmt_px(f.px(hi)),
                fmt_px(f.py(g.curve_h(c, hi)))
            );
        }
        if d.is_empty() {
            continue;
        }
        let (class, width_px, colour) = if Geometry::is_outer(c) {
            ("sigma outer", 2.6 * stroke_scale, "#1a1a1a")
        } else {
            ("sigma inner", 1.3 * stroke_scale, "#333333")
        };
        let _ = writeln!(
            s,
            r#"<path id="{prefix}sigma-{c:?}" class="{class}" d="{d}" stroke="{colour}" stroke-width="{width_px}"><title>Σ: {}</title></path>"#,
            xml_escape(c.equation())
        );
    }
    let _ = writeln!(s, "</g>");
    chains
}

/// Frame, ticks and tick labels of one plot. The frame's `data-window="m_lo m_hi h_lo h_hi"`
/// with its x, y, width, height give the map from (m, h) to px.
pub(super) fn draw_axes(s: &mut String, f: &Frame, ticks: f64, font: f64, grid: bool) {
    let m_step = nice_step(f.m_hi - f.m_lo, ticks);
    let h_step = nice_step(f.h_hi - f.h_lo, ticks);
    let range = |lo: f64, hi: f64, step: f64| -> Vec<f64> {
        let k0 = (lo / step - 1e-9).ceil() as i64;
        let k1 = (hi / step + 1e-9).floor() as i64;
        (k0..=k1).map(|k| k as f64 * step).collect()
    };
    let m_ticks = range(f.m_lo, f.m_hi, m_step);
    let h_ticks = range(f.h_lo, f.h_hi, h_step);
    if grid {
        let _ = writeln!(
            s,
            r##"<g class="grid" stroke="#000000" stroke-opacity="0.08" stroke-width="1">"##
        );
        for &m in &m_ticks {
            let x = fmt_px(f.px(m));
            let _ = writeln!(
                s,
                r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
                fmt_px(f.y0),
                fmt_px(f.y0 + f.h)
            );
        }
        for &h in &h_ticks {
            let y = fmt_px(f.py(h));
            let _ = writeln!(
                s,
                r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}"/>"#,
                fmt_px(f.x0),
                fmt_px(f.x0 + f.w)
            );
        }
        let _ = writeln!(s, "</g>");
    }
    let _ = writeln!(
        s,
        r##"<rect class="frame" data-window="{} {} {} {}" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#000000" stroke-width="1.2"/>"##,
        f.m_lo,
        f.m_hi,
        f.h_lo,
        f.h_hi,
        fmt_px(f.x0),
        fmt_px(f.y0),
        fmt_px(f.w),
        fmt_px(f.h)
    );
    let _ = writeln!(
        s,
        r##"<g class="axes" font-size="{font}" fill="#000000" stroke="#000000" stroke-width="1.2">"##
    );
    let tick = 0.45 * font;
    let ybot = f.y0 + f.h;
    for &m in &m_ticks {
        let x = fmt_px(f.px(m));
        let _ = writeln!(
            s,
            r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/><text x="{x}" y="{}" text-anchor="middle" stroke="none">{}</text>"#,
            fmt_px(ybot),
            fmt_px(ybot + tick),
            fmt_px(ybot + tick + 1.15 * font),
            fmt_tick(m, m_step)
        );
    }
    for &h in &h_ticks {
        let y = fmt_px(f.py(h));
        let _ = writeln!(
            s,
            r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}"/><text x="{}" y="{}" text-anchor="end" stroke="none">{}</text>"#,
            fmt_px(f.x0 - tick),
            fmt_px(f.x0),
            fmt_px(f.x0 - tick - 3.0),
            fmt_px(f.py(h) + 0.35 * font),
            fmt_tick(h, h_step)
        );
    }
    let _ = writeln!(s, "</g>");
}

pub(super) fn draw_labels(s: &mut String, f: &Frame, labels: &[LabelPlacement]) {
    let _ = writeln!(
        s,
        r##"<g class="camera-labels" text-anchor="middle" fill="#111111">"##
    );
    for p in labels {
        let (x, y) = p.text;
        if p.text != p.anchor {
            // Leader line from the anchor to the edge of the label box.
            let (ax, ay) = p.anchor;
            let (dx, dy) = (x - ax, y - ay);
            let t = 1.0
                - (0.5 * (LABEL_W + 6.0) / dx.abs().max(1e-9))
                    .min(0.5 * (LABEL_H + 6.0) / dy.abs().max(1e-9))
                    .min(1.0);
            let _ = writeln!(
                s,
                r##"<g class="leader"><line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#222222" stroke-width="1"/><circle cx="{}" cy="{}" r="2.4" fill="#222222"/></g>"##,
                fmt_px(ax),
                fmt_px(ay),
                fmt_px(ax + t * dx),
                fmt_px(ay + t * dy),
                fmt_px(ax),
                fmt_px(ay)
            );
        }
        let _ = writeln!(
            s,
            r#"<text class="camera-label" data-m="{}" data-h="{}" x="{}" y="{}" font-size="17" font-weight="bold">{}</text>"#,
            f.m_of(p.anchor.0),
            f.h_of(p.anchor.1),
            fmt_px(x),
            fmt_px(y - 1.0),
            p.camera.label()
        );
        let _ = writeln!(
            s,
            r#"<text class="camera-tori" x="{}" y="{}" font-size="11">{}</text>"#,
            fmt_px(x),
            fmt_px(y + 12.0),
            tori_text(p.tori)
        );
    }
    let _ = writeln!(s, "</g>");
}
