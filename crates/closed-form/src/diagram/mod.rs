//! The bifurcation diagram as a picture and a description of one point of the (m, h) plane.
//!
//! [`diagram_svg`] draws the admissible region of the (m, h) plane (seed sec. 1) with each camera
//! of Table 1 filled in its own colour, the curves of Σ on top (the outer boundary thick, the
//! half-lines inside thin), a label with the number of Liouville tori inside every camera, axes
//! and a legend with the order of the roots of Φ. The cameras are found by sweeping the plane in
//! narrow vertical strips whose edges include every point where two curves of Σ meet or touch:
//! inside a strip the curves do not cross, so the region between two vertically consecutive
//! curves is a single camera, classified at its middle point (by the oscillation segments, as in
//! [`ExplicitMotion::new`](crate::motion::ExplicitMotion::new)); the pieces of one camera are
//! joined from strip to strip into polygons. Labels go to the point of each camera farthest from
//! its boundary (on a ~3 px raster) where the text fits; otherwise to the nearest empty place
//! with a leader line, and a camera only a few px thick is labelled in a zoomed inset below the
//! legend.
//!
//! [`describe_point`] gives, for one point (m, h), the camera, the oscillation segments of s₁
//! and s₂ in the notation of Table 1 and numerically, the elliptic moduli, periods, frequencies,
//! the rotation number and the radicals that keep a constant sign.

// This file: the public API of the picture (options, window, `diagram_svg`: frame, title, legend
// and inset) and the checks of a, b.
// `describe_point` and `PointDescription` (re-exported here).
mod describe;
// SVG of one plot (camera fills, m = 0, Σ), axes and labels; colours and number formatting.
mod draw;
// Label placement: distance transform on a raster of each camera, label boxes, thin anchors.
mod labels;
// Curves of Σ as h(m), the pixel frame, the camera at a point, the strip sweep into polygons.
mod regions;

use std::fmt::Write as _;

use crate::camera::Camera;
use crate::constants::SigmaCurve;
use crate::error::ClosedFormError;

pub use describe::{
    describe_point, NormalDescription, PointDescription, RadicalDescription, SegmentEnd,
    VariableDescription,
};

use draw::{camera_colour, draw_axes, draw_labels, draw_plot, fmt_px, xml_escape};
use labels::{label_positions, thin_anchors, LabelPlacement};
pub use regions::camera_at;
use regions::{Frame, Geometry};

// ---------------------------------------------------------------------------------------------
// Parameters
// ---------------------------------------------------------------------------------------------

fn check_fields(a: f64, b: f64) -> Result<(), ClosedFormError> {
    if !(a.is_finite() && b.is_finite()) {
        return Err(ClosedFormError::Parameters(format!(
            "a and b must be finite numbers (got a = {a}, b = {b})"
        )));
    }
    if !(b > 0.0 && a > b) {
        return Err(ClosedFormError::Parameters(format!(
            "the diagram needs a > b > 0 (got a = {}, b = {}); b = 0 (Kovalevskaya) and b = a (Yehia) are reducible cases without the manifold N",
            rsts_dynamics::short(a),
            rsts_dynamics::short(b)
        )));
    }
    crate::constants::check_ranges(&a, &b, &0.0, &0.0)
}

/// "1 torus", "n tori" (in the picture's labels and in a point's description).
pub fn tori_text(n: usize) -> String {
    if n == 1 {
        "1 torus".to_string()
    } else {
        format!("{n} tori")
    }
}

// ---------------------------------------------------------------------------------------------
// Diagram
// ---------------------------------------------------------------------------------------------

/// Options of [`diagram_svg`]. `Default` gives a 1000 × 720 picture of the window
/// [`default_window`].
#[derive(Clone, Debug, PartialEq)]
pub struct DiagramOptions {
    /// The m-range shown; `None`: from [`default_window`].
    pub m_range: Option<(f64, f64)>,
    /// The h-range shown; `None`: from [`default_window`].
    pub h_range: Option<(f64, f64)>,
    /// Size of the picture in px (700 × 540 to 8000 × 8000; the legend takes 270 px on the right).
    pub width: u32,
    pub height: u32,
    /// Replaces the title "Admissible region and cameras, a = …, b = …".
    pub title: Option<String>,
}

impl Default for DiagramOptions {
    fn default() -> Self {
        Self {
            m_range: None,
            h_range: None,
            width: 1000,
            height: 720,
            title: None,
        }
    }
}

/// The ranges ((m_lo, m_hi), (h_lo, h_hi)) of a picture.
pub type Window = ((f64, f64), (f64, f64));

/// A window ((m_lo, m_hi), (h_lo, h_hi)) that shows all nine cameras. With R = min(1/(a−b),
/// 3/(a+b)) (R = 1/(a−b) is where the inner half-lines start on the boundary; for b close to a
/// they start far out and the window stops at 3/(a+b)): m from −1.5·max(R, 1/(2b)) (camera VI
/// lies along the hyperbola beyond its tangency with h = −r²m + 2b at m = −1/(2b)) to 1.15·R;
/// h from below the corner (1/(a+b), −a−b) of the boundary to above the hyperbola at the left
/// edge. For a = 1, b = 1/2: m ∈ [−3, 2.3]. Cameras too small to see at this scale get a zoomed
/// inset in [`diagram_svg`].
pub fn default_window(a: f64, b: f64) -> Result<Window, ClosedFormError> {
    check_fields(a, b)?;
    let g = Geometry::new(a, b);
    let reach = (1.0 / (a - b)).min(3.0 / (a + b));
    let m_lo = -1.5 * reach.max(1.0 / (2.0 * b));
    let m_hi = 1.15 * reach;
    let top = g.curve_h(SigmaCurve::Hyperbola, m_lo);
    let bottom = -(a + b);
    let pad = 0.08 * (top - bottom);
    Ok(((m_lo, m_hi), (bottom - pad, top + pad)))
}

/// An SVG picture of the (m, h) plane for the fields a > b > 0: the admissible region with its
/// cameras coloured and labelled (with the number of Liouville tori), the curves of Σ (outer
/// boundary thick, inner half-lines thin), the line m = 0 that splits the cameras I, II, IV into
/// their ± parts (dashed; not part of Σ), axes, a title and a legend with Table 1's order of the
/// roots of Φ in each camera. Cameras too small to label in the main plot are labelled in a
/// zoomed inset below the legend (its window is marked in the main plot).
///
/// Each camera label is a `<text class="camera-label" data-m=… data-h=…>` whose data attributes
/// give the (m, h) of the label's anchor, a point inside that camera; every camera in the window
/// is labelled exactly once.
pub fn diagram_svg(a: f64, b: f64, opts: &DiagramOptions) -> Result<String, ClosedFormError> {
    check_fields(a, b)?;
    let ((dm_lo, dm_hi), (dh_lo, dh_hi)) = default_window(a, b)?;
    let (m_lo, m_hi) = opts.m_range.unwrap_or((dm_lo, dm_hi));
    let (h_lo, h_hi) = opts.h_range.unwrap_or((dh_lo, dh_hi));
    for (name, lo, hi, given) in [
        ("m_range", m_lo, m_hi, opts.m_range.is_some()),
        ("h_range", h_lo, h_hi, opts.h_range.is_some()),
    ] {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            let origin = if given {
                ""
            } else {
                " (the default window for these a, b; pass m_range and h_range)"
            };
            return Err(ClosedFormError::Parameters(format!(
                "{name} must be two finite numbers lo < hi (got {lo}, {hi}){origin}"
            )));
        }
    }
    if !(700..=8000).contains(&opts.width) || !(540..=8000).contains(&opts.height) {
        return Err(ClosedFormError::Parameters(format!(
            "picture size must be between 700 × 540 and 8000 × 8000 px (got {} × {})",
            opts.width, opts.height
        )));
    }
    let g = Geometry::new(a, b);
    let (width, height) = (opts.width as f64, opts.height as f64);
    let legend_w = 270.0;
    let frame = Frame {
        m_lo,
        m_hi,
        h_lo,
        h_hi,
        x0: 72.0,
        y0: 56.0,
        w: width - 72.0 - legend_w,
        h: height - 56.0 - 62.0,
    };
    let f = &frame;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    let title = opts
        .title
        .clone()
        .unwrap_or_else(|| format!("Admissible region and cameras, a = {a}, b = {b}"));
    let _ = writeln!(s, "<title>{}</title>", xml_escape(&title));
    let _ = writeln!(
        s,
        r##"<rect x="0" y="0" width="{width}" height="{height}" fill="#ffffff"/>"##
    );
    let chains = draw_plot(&mut s, &g, f, "", 1.0);
    draw_axes(&mut s, f, 8.0, 13.0, true);
    let ybot = f.y0 + f.h;
    let _ = writeln!(
        s,
        r#"<text class="axis-label" x="{}" y="{}" text-anchor="middle" font-size="17" font-style="italic">m</text>"#,
        fmt_px(f.x0 + 0.5 * f.w),
        fmt_px(ybot + 45.0)
    );
    let _ = writeln!(
        s,
        r#"<text class="axis-label" x="{}" y="{}" text-anchor="middle" font-size="17" font-style="italic">h</text>"#,
        fmt_px(f.x0 - 52.0),
        fmt_px(f.y0 + 0.5 * f.h + 5.0)
    );
    let _ = writeln!(
        s,
        r##"<text class="title" x="{}" y="34" text-anchor="middle" font-size="20" font-weight="bold" fill="#000000">{}</text>"##,
        fmt_px(0.5 * width),
        xml_escape(&title)
    );

    // Labels: in the main plot for cameras with room, in the inset for the others.
    let present: Vec<Camera> = Camera::ALL
        .into_iter()
        .filter(|c| chains.iter().any(|ch| ch.camera == *c))
        .collect();
    let main_labels = label_positions(&g, f, &present, &thin_anchors(&g, f, &chains));
    let tiny: Vec<Camera> = main_labels
        .iter()
        .filter(|p| p.room < 4.0)
        .map(|p| p.camera)
        .collect();

    // Legend.
    let lx = f.x0 + f.w + 24.0;
    let mut ly = f.y0 + 6.0;
    let _ = writeln!(s, r##"<g class="legend" font-size="12.5" fill="#000000">"##);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" font-size="14" font-weight="bold">Σ (bifurcation diagram)</text>"#,
        fmt_px(lx),
        fmt_px(ly + 4.0)
    );
    ly += 24.0;
    for (text, w_px, dash) in [
        ("outer boundary", 2.6, ""),
        ("half-lines inside", 1.3, ""),
        ("m = 0 (not in Σ)", 1.0, r#" stroke-dasharray="5,4""#),
    ] {
        let _ = writeln!(
            s,
            r##"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#1a1a1a" stroke-width="{w_px}"{dash}/><text x="{}" y="{}">{}</text>"##,
            fmt_px(lx),
            fmt_px(ly),
            fmt_px(lx + 30.0),
            fmt_px(ly),
            fmt_px(lx + 38.0),
            fmt_px(ly + 4.5),
            text
        );
        ly += 20.0;
    }
    ly += 14.0;
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" font-size="14" font-weight="bold">Cameras: roots of Φ</text>"#,
        fmt_px(lx),
        fmt_px(ly)
    );
    ly += 20.0;
    for camera in Camera::ALL {
        let _ = writeln!(
            s,
            r##"<rect x="{}" y="{}" width="16" height="16" fill="{}" stroke="#777777" stroke-width="0.6"/><text x="{}" y="{}"><tspan font-weight="bold">{}</tspan><tspan x="{}">{}</tspan></text>"##,
            fmt_px(lx),
            fmt_px(ly - 12.0),
            camera_colour(camera),
            fmt_px(lx + 24.0),
            fmt_px(ly + 1.0),
            camera.label(),
            fmt_px(lx + 60.0),
            xml_escape(&camera.table1_roots().replace('-', "−"))
        );
        ly += 24.0;
    }
    ly += 6.0;
    for line in [
        "θ₁ = (ℓ − 1)/(2m), θ₂ = (ℓ + 1)/(2m),",
        "ℓ² = 2p²m² + 2hm + 1,",
        "p² = a² + b², r² = a² − b²",
    ] {
        let _ = writeln!(
            s,
            r##"<text x="{}" y="{}" font-size="11.5" fill="#333333">{}</text>"##,
            fmt_px(lx),
            fmt_px(ly),
            line
        );
        ly += 16.0;
    }
    let _ = writeln!(s, "</g>");

    // Inset for the cameras too small for a label in the main plot.
    let inset_top = ly + 26.0;
    let inset_h = ybot - inset_top;
    let mut labels: Vec<LabelPlacement> = main_labels.clone();
    if !tiny.is_empty() && inset_h >= 150.0 {
        // Window: the bounding box of the tiny cameras' polygons, enlarged for context, when it
        // is compact in the main plot; otherwise (a long thin sliver) a window around the
        // sliver's thickest piece, with the main plot's aspect, five times as tall as the sliver.
        let (mut b_m0, mut b_m1, mut b_h0, mut b_h1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for ch in chains.iter().filter(|c| tiny.contains(&c.camera)) {
            for &(m, h) in ch.upper.iter().chain(ch.lower.iter()) {
                b_m0 = b_m0.min(m);
                b_m1 = b_m1.max(m);
                b_h0 = b_h0.min(h);
                b_h1 = b_h1.max(h);
            }
        }
        let compact = f.px(b_m1) - f.px(b_m0) <= 60.0 && f.py(b_h0) - f.py(b_h1) <= 60.0;
        let (cm, ch_, half_m, half_h) = if compact {
            (
                0.5 * (b_m0 + b_m1),
                0.5 * (b_h0 + b_h1),
                (b_m1 - b_m0).max(1e-9 * (m_hi - m_lo)),
                (b_h1 - b_h0).max(1e-9 * (h_hi - h_lo)),
            )
        } else {
            let (m, h, height) = chains
                .iter()
                .filter(|c| tiny.contains(&c.camera))
                .map(|c| c.widest)
                .max_by(|p, q| p.2.total_cmp(&q.2))
                .unwrap_or((0.5 * (m_lo + m_hi), 0.5 * (h_lo + h_hi), h_hi - h_lo));
            let half_h = 2.5 * height.max(1e-9 * (h_hi - h_lo));
            let half_m = half_h * (m_hi - m_lo) / (h_hi - h_lo) * (f.h / f.w);
            let m = m.clamp(m_lo + half_m, (m_hi - half_m).max(m_lo + half_m));
            (m, h, half_m, half_h)
        };
        let inset = Frame {
            m_lo: cm - half_m,
            m_hi: cm + half_m,
            h_lo: ch_ - half_h,
            h_hi: ch_ + half_h,
            x0: lx + 40.0,
            y0: inset_top,
            w: width - lx - 40.0 - 14.0,
            h: inset_h,
        };
        // Mark the inset's window in the main plot (at least 8 px wide).
        let (x0, x1) = (f.px(inset.m_lo), f.px(inset.m_hi));
        let (y0, y1) = (f.py(inset.h_hi), f.py(inset.h_lo));
        let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (hw, hh) = ((0.5 * (x1 - x0)).max(5.0), (0.5 * (y1 - y0)).max(5.0));
        let _ = writeln!(
            s,
            r##"<rect class="inset-window" clip-path="url(#plot-area)" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#c0392b" stroke-width="1.3"/>"##,
            fmt_px(xc - hw),
            fmt_px(yc - hh),
            fmt_px(2.0 * hw),
            fmt_px(2.0 * hh)
        );
        let _ = writeln!(s, r#"<g class="inset">"#);
        let _ = writeln!(
            s,
            r##"<text x="{}" y="{}" font-size="12.5" font-weight="bold" fill="#c0392b">Zoom (red box)</text>"##,
            fmt_px(lx),
            fmt_px(inset_top - 10.0)
        );
        let inset_chains = draw_plot(&mut s, &g, &inset, "inset-", 0.7);
        draw_axes(&mut s, &inset, 3.0, 10.0, false);
        let _ = writeln!(
            s,
            r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#c0392b" stroke-width="1.6"/>"##,
            fmt_px(inset.x0),
            fmt_px(inset.y0),
            fmt_px(inset.w),
            fmt_px(inset.h)
        );
        let inset_labels =
            label_positions(&g, &inset, &tiny, &thin_anchors(&g, &inset, &inset_chains));
        draw_labels(&mut s, &inset, &inset_labels);
        let _ = writeln!(s, "</g>");
        let moved: Vec<Camera> = inset_labels.iter().map(|p| p.camera).collect();
        labels.retain(|p| !moved.contains(&p.camera));
    }
    draw_labels(&mut s, f, &labels);
    s.push_str("</svg>\n");
    Ok(s)
}
