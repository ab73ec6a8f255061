//! The bifurcation diagram as a picture and a description of one point of the (m, h) plane.
//!
//! [`diagram_svg`] draws the admissible region of the (m, h) plane (seed sec. 1) with each camera
//! of Table 1 filled in its own colour, the curves of Σ on top (the outer boundary thick, the
//! half-lines inside thin), a label with the number of Liouville tori inside every camera, axes
//! and a legend with the order of the roots of Φ. The cameras are found by sweeping the plane in
//! narrow vertical strips whose edges include every point where two curves of Σ meet or touch:
//! inside a strip the curves do not cross, so the region between two vertically consecutive
//! curves is a single camera, classified at its middle point (by the oscillation segments, as in
//! [`ExplicitMotion::new`]); the pieces of one camera are joined from strip to strip into
//! polygons. Labels go to the point of each camera farthest from its boundary (on a ~3 px
//! raster) where the text fits; otherwise to the nearest empty place with a leader line, and a
//! camera only a few px thick is labelled in a zoomed inset below the legend.
//!
//! [`describe_point`] gives, for one point (m, h), the camera, the oscillation segments of s₁
//! and s₂ in the notation of Table 1 and numerically, the elliptic moduli, periods, frequencies,
//! the rotation number and the radicals that keep a constant sign.

use std::fmt::{self, Write as _};

use serde::{Serialize, Serializer};

use crate::camera::Camera;
use crate::constants::{IntegralConstants, SigmaCurve};
use crate::error::ClosedFormError;
use crate::motion::{ExplicitMotion, TorusChoice};
use crate::roots::RootLabel;
use crate::separated::{segments, Radicand, SeparatedVariable};

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
            "the diagram needs a > b > 0 (got a = {a}, b = {b}); b = 0 (Kovalevskaya) and b = a (Yehia) are reducible cases without the manifold N"
        )));
    }
    Ok(())
}

/// The camera at (m, h), if the point is admissible and off Σ: the same choice as
/// [`ExplicitMotion::new`] (the first oscillation segment of each variable), without building
/// the elliptic parametrisation — cheap enough for a raster.
fn camera_at(a: f64, b: f64, m: f64, h: f64) -> Option<Camera> {
    let c = IntegralConstants::new(a, b, m, h).ok()?;
    let (f1, g1) = c.radicands_x();
    let (f2, g2) = c.radicands_s2();
    let s1 = segments(&f1, &g1);
    let s2 = segments(&f2, &g2);
    let (x, y) = (s1.first()?, s2.first()?);
    Camera::from_segments([x.0.label, x.1.label], [y.0.label, y.1.label], c.m < 0.0)
}

/// The camera and number of tori at (m, h), if the point is admissible and off Σ.
fn classify(a: f64, b: f64, m: f64, h: f64) -> Option<(Camera, usize)> {
    ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())
        .ok()
        .map(|e| (e.camera, e.tori))
}

fn tori_text(n: usize) -> String {
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

/// a, b and the derived constants, for the curves of Σ as functions h(m).
#[derive(Clone, Copy, Debug)]
struct Geometry {
    a: f64,
    b: f64,
    p2: f64,
    r2: f64,
}

impl Geometry {
    fn new(a: f64, b: f64) -> Self {
        Self {
            a,
            b,
            p2: a * a + b * b,
            r2: a * a - b * b,
        }
    }

    /// h on the curve at m (the hyperbola's branch m < 0: h = −p²m − 1/(2m)).
    fn curve_h(&self, c: SigmaCurve, m: f64) -> f64 {
        let (a, b, r2) = (self.a, self.b, self.r2);
        match c {
            SigmaCurve::OuterA => r2 * m - 2.0 * a,
            SigmaCurve::OuterB => -r2 * m - 2.0 * b,
            SigmaCurve::Hyperbola => -self.p2 * m - 0.5 / m,
            SigmaCurve::InnerA => r2 * m + 2.0 * a,
            SigmaCurve::InnerB => -r2 * m + 2.0 * b,
        }
    }

    /// The m-interval of the part of the curve that belongs to Σ.
    fn domain(&self, c: SigmaCurve) -> (f64, f64) {
        let (a, b) = (self.a, self.b);
        match c {
            SigmaCurve::OuterA => (1.0 / (a + b), f64::INFINITY),
            SigmaCurve::OuterB => (f64::NEG_INFINITY, 1.0 / (a + b)),
            SigmaCurve::Hyperbola => (f64::NEG_INFINITY, 0.0),
            SigmaCurve::InnerA => (-1.0 / (a - b), f64::INFINITY),
            SigmaCurve::InnerB => (f64::NEG_INFINITY, 1.0 / (a - b)),
        }
    }

    fn is_outer(c: SigmaCurve) -> bool {
        matches!(
            c,
            SigmaCurve::OuterA | SigmaCurve::OuterB | SigmaCurve::Hyperbola
        )
    }

    /// The m where the curve reaches the level h = level (inside its domain).
    fn crossings(&self, c: SigmaCurve, level: f64) -> Vec<f64> {
        let (a, b, r2, p2) = (self.a, self.b, self.r2, self.p2);
        let ms = match c {
            SigmaCurve::OuterA => vec![(level + 2.0 * a) / r2],
            SigmaCurve::OuterB => vec![-(level + 2.0 * b) / r2],
            SigmaCurve::InnerA => vec![(level - 2.0 * a) / r2],
            SigmaCurve::InnerB => vec![-(level - 2.0 * b) / r2],
            SigmaCurve::Hyperbola => {
                // 2p²m² + 2·level·m + 1 = 0.
                let disc = level * level - 2.0 * p2;
                if disc < 0.0 {
                    vec![]
                } else {
                    let s = disc.sqrt();
                    vec![(-level - s) / (2.0 * p2), (-level + s) / (2.0 * p2)]
                }
            }
        };
        let (d0, d1) = self.domain(c);
        ms.into_iter()
            .filter(|m| m.is_finite() && *m > d0 && *m < d1)
            .collect()
    }

    /// Points where curves of Σ start, meet or touch (the m of each).
    fn special_ms(&self) -> Vec<f64> {
        let (a, b) = (self.a, self.b);
        vec![
            0.0,
            1.0 / (a + b),
            -1.0 / (a + b),
            1.0 / (a - b),
            -1.0 / (a - b),
            -0.5 / a,
            -0.5 / b,
        ]
    }
}

/// The pixel frame of the plot.
#[derive(Clone, Copy, Debug)]
struct Frame {
    m_lo: f64,
    m_hi: f64,
    h_lo: f64,
    h_hi: f64,
    x0: f64,
    y0: f64,
    w: f64,
    h: f64,
}

impl Frame {
    fn px(&self, m: f64) -> f64 {
        self.x0 + (m - self.m_lo) / (self.m_hi - self.m_lo) * self.w
    }
    fn py(&self, h: f64) -> f64 {
        self.y0 + (self.h_hi - h) / (self.h_hi - self.h_lo) * self.h
    }
    fn m_of(&self, x: f64) -> f64 {
        self.m_lo + (x - self.x0) / self.w * (self.m_hi - self.m_lo)
    }
    fn h_of(&self, y: f64) -> f64 {
        self.h_hi - (y - self.y0) / self.h * (self.h_hi - self.h_lo)
    }
}

/// A chain of strip pieces of one camera, as a polygon: the upper edge left to right and the
/// lower edge left to right.
#[derive(Clone, Debug)]
struct Chain {
    camera: Camera,
    upper: Vec<(f64, f64)>,
    lower: Vec<(f64, f64)>,
    /// The middle (m, h) of its tallest piece and the piece's height.
    widest: (f64, f64, f64),
}

fn push_point(v: &mut Vec<(f64, f64)>, p: (f64, f64)) {
    if v.last() != Some(&p) {
        v.push(p);
    }
}

/// One piece of a strip: the region between two consecutive bounds.
#[derive(Clone, Debug)]
struct Piece {
    camera: Option<Camera>,
    /// Where it was classified and its height at that m.
    sample: (f64, f64, f64),
    /// (lower, upper) at the left and right edge of the strip.
    left: (f64, f64),
    right: (f64, f64),
}

/// Sweep the window in vertical strips; return the camera polygons (in (m, h)).
fn camera_chains(g: &Geometry, f: &Frame) -> Vec<Chain> {
    let (m_lo, m_hi, h_lo, h_hi) = (f.m_lo, f.m_hi, f.h_lo, f.h_hi);
    let mut bps: Vec<f64> = Vec::new();
    let n_uniform = 480;
    for i in 0..=n_uniform {
        bps.push(m_lo + (m_hi - m_lo) * i as f64 / n_uniform as f64);
    }
    bps.extend(g.special_ms());
    let n_levels = 240;
    for c in SigmaCurve::ALL {
        bps.extend(g.crossings(c, h_lo));
        bps.extend(g.crossings(c, h_hi));
    }
    // The hyperbola is steep near m = 0: sample it in h too.
    for i in 0..=n_levels {
        let level = h_lo + (h_hi - h_lo) * i as f64 / n_levels as f64;
        bps.extend(g.crossings(SigmaCurve::Hyperbola, level));
    }
    bps.retain(|m| m.is_finite() && *m >= m_lo && *m <= m_hi);
    bps.sort_by(|p, q| p.total_cmp(q));
    let tiny = 1e-12 * (m_hi - m_lo);
    bps.dedup_by(|p, q| (*p - *q).abs() <= tiny);

    let h_tiny = 1e-9 * (h_hi - h_lo);
    let clamp = |h: f64| h.clamp(h_lo, h_hi);
    let mut chains: Vec<Chain> = Vec::new();
    // Pieces of the previous strip with the chain each belongs to.
    let mut prev: Vec<(Piece, Option<usize>)> = Vec::new();
    for w in bps.windows(2) {
        let (m0, m1) = (w[0], w[1]);
        if m1 - m0 <= tiny {
            continue;
        }
        let mm = 0.5 * (m0 + m1);
        // Bounds: (mid, left, right).
        let mut bounds: Vec<(f64, f64, f64)> = vec![(h_lo, h_lo, h_lo), (h_hi, h_hi, h_hi)];
        for c in SigmaCurve::ALL {
            let (d0, d1) = g.domain(c);
            if !(mm > d0 && mm < d1) {
                continue;
            }
            let hm = g.curve_h(c, mm);
            if !(hm > h_lo && hm < h_hi) {
                continue;
            }
            bounds.push((hm, clamp(g.curve_h(c, m0)), clamp(g.curve_h(c, m1))));
        }
        bounds.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut pieces: Vec<Piece> = Vec::new();
        for pair in bounds.windows(2) {
            let (lo, hi) = (pair[0], pair[1]);
            if hi.0 - lo.0 <= h_tiny {
                continue;
            }
            let hc = 0.5 * (lo.0 + hi.0);
            pieces.push(Piece {
                camera: camera_at(g.a, g.b, mm, hc),
                sample: (mm, hc, hi.0 - lo.0),
                left: (lo.1, hi.1),
                right: (lo.2, hi.2),
            });
        }
        // Link to the previous strip: same camera and overlapping edges, one to one.
        let overlaps = |p: &Piece, q: &Piece| {
            p.camera.is_some()
                && p.camera == q.camera
                && p.right.1.min(q.left.1) - p.right.0.max(q.left.0) > h_tiny
        };
        let mut next: Vec<(Piece, Option<usize>)> = Vec::new();
        for q in &pieces {
            let Some(camera) = q.camera else {
                next.push((q.clone(), None));
                continue;
            };
            let preds: Vec<usize> = (0..prev.len())
                .filter(|&i| overlaps(&prev[i].0, q))
                .collect();
            let chain = match preds.as_slice() {
                [i] if pieces.iter().filter(|q2| overlaps(&prev[*i].0, q2)).count() == 1 => {
                    prev[*i].1
                }
                _ => None,
            };
            let idx = match chain {
                Some(idx) => idx,
                None => {
                    chains.push(Chain {
                        camera,
                        upper: Vec::new(),
                        lower: Vec::new(),
                        widest: q.sample,
                    });
                    chains.len() - 1
                }
            };
            let ch = &mut chains[idx];
            if q.sample.2 > ch.widest.2 {
                ch.widest = q.sample;
            }
            push_point(&mut ch.upper, (m0, q.left.1));
            push_point(&mut ch.upper, (m1, q.right.1));
            push_point(&mut ch.lower, (m0, q.left.0));
            push_point(&mut ch.lower, (m1, q.right.0));
            next.push((q.clone(), Some(idx)));
        }
        prev = next;
    }
    chains
}

/// Drop the points of a closed ring (in px) that lie within `tol` of the segment joining their
/// neighbours that are kept.
fn simplify_ring(pts: &[(f64, f64)], tol: f64) -> Vec<(f64, f64)> {
    if pts.len() <= 3 {
        return pts.to_vec();
    }
    let mut out: Vec<(f64, f64)> = vec![pts[0]];
    for i in 1..pts.len() {
        let p = pts[i];
        let next = if i + 1 < pts.len() {
            pts[i + 1]
        } else {
            pts[0]
        };
        let prev = *out.last().unwrap();
        let (dx, dy) = (next.0 - prev.0, next.1 - prev.1);
        let len = (dx * dx + dy * dy).sqrt();
        let dist = if len == 0.0 {
            ((p.0 - prev.0).powi(2) + (p.1 - prev.1).powi(2)).sqrt()
        } else {
            ((p.0 - prev.0) * dy - (p.1 - prev.1) * dx).abs() / len
        };
        // Keep the point unless it is on the segment (between its ends) within tol.
        let along = (p.0 - prev.0) * dx + (p.1 - prev.1) * dy;
        if dist > tol || along < 0.0 || along > len * len {
            out.push(p);
        }
    }
    out
}

fn fmt_px(x: f64) -> String {
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

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Fill colour of each camera: one hue per Roman numeral, lighter for the part with m > 0.
fn camera_colour(c: Camera) -> &'static str {
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

/// Where a camera's label goes.
#[derive(Clone, Copy, Debug)]
struct LabelPlacement {
    camera: Camera,
    tori: usize,
    /// A point well inside the camera (px).
    anchor: (f64, f64),
    /// Centre of the label text (px); differs from `anchor` when the label does not fit in the
    /// camera and is set outside with a leader line.
    text: (f64, f64),
    /// Distance (px, about) from the anchor to the camera's boundary; 0 for a camera too thin for
    /// the raster.
    room: f64,
}

/// Chamfer 3-4 distance of each cell of the mask to the nearest cell outside it (cells beyond
/// the raster count as outside).
fn distance_transform(inside: &[bool], nx: usize, ny: usize) -> Vec<u32> {
    let big = u32::MAX / 4;
    let mut d: Vec<u32> = inside.iter().map(|&x| if x { big } else { 0 }).collect();
    let at = |i: usize, j: usize| j * nx + i;
    for j in 0..ny {
        for i in 0..nx {
            let k = at(i, j);
            if d[k] == 0 {
                continue;
            }
            let mut v = d[k];
            if i == 0 || j == 0 || i + 1 == nx || j + 1 == ny {
                v = v.min(3);
            }
            if i > 0 {
                v = v.min(d[at(i - 1, j)] + 3);
            }
            if j > 0 {
                v = v.min(d[at(i, j - 1)] + 3);
                if i > 0 {
                    v = v.min(d[at(i - 1, j - 1)] + 4);
                }
                if i + 1 < nx {
                    v = v.min(d[at(i + 1, j - 1)] + 4);
                }
            }
            d[k] = v;
        }
    }
    for j in (0..ny).rev() {
        for i in (0..nx).rev() {
            let k = at(i, j);
            if d[k] == 0 {
                continue;
            }
            let mut v = d[k];
            if i + 1 < nx {
                v = v.min(d[at(i + 1, j)] + 3);
            }
            if j + 1 < ny {
                v = v.min(d[at(i, j + 1)] + 3);
                if i + 1 < nx {
                    v = v.min(d[at(i + 1, j + 1)] + 4);
                }
                if i > 0 {
                    v = v.min(d[at(i - 1, j + 1)] + 4);
                }
            }
            d[k] = v;
        }
    }
    d
}

/// The ink of a label centred at (x, y): the name (bold 17 px, baseline y − 1) and the number of
/// tori (11 px, baseline y + 12), as rectangles (x, y, w, h) grown by `pad` px.
fn label_boxes(camera: Camera, x: f64, y: f64, pad: f64) -> [(f64, f64, f64, f64); 2] {
    let name_w = 11.0 * camera.label().len() as f64 + 2.0;
    let tori_w = 31.0;
    [
        (
            x - 0.5 * name_w - pad,
            y - 13.0 - pad,
            name_w + 2.0 * pad,
            13.0 + 2.0 * pad,
        ),
        (
            x - 0.5 * tori_w - pad,
            y + 3.0 - pad,
            tori_w + 2.0 * pad,
            10.0 + 2.0 * pad,
        ),
    ]
}

/// Where to put each camera's label: the point of a pixel raster of the camera farthest from
/// its boundary (the pole of inaccessibility, by a chamfer distance transform), preferring a
/// point where the label's ink fits in the camera. When it fits nowhere, the text goes to the
/// nearest empty (inadmissible) place where it fits, with a leader line to the anchor.
///
/// Only the `cameras` listed get a label; `thin` gives an anchor (px) and the number of tori for
/// cameras the raster misses (thinner than its step).
fn label_positions(
    g: &Geometry,
    f: &Frame,
    cameras: &[Camera],
    thin: &[(Camera, (f64, f64), usize)],
) -> Vec<LabelPlacement> {
    // About 3 px cells, at most ~60 000 of them.
    let step = (f.w * f.h / 60_000.0).sqrt().max(3.0);
    let nx = (f.w / step).floor() as usize;
    let ny = (f.h / step).floor() as usize;
    let mut cells: Vec<Option<Camera>> = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = f.x0 + (i as f64 + 0.5) * step;
            let y = f.y0 + (j as f64 + 0.5) * step;
            cells.push(camera_at(g.a, g.b, f.m_of(x), f.h_of(y)));
        }
    }
    let at = |i: usize, j: usize| j * nx + i;
    let centre = |k: usize| {
        (
            f.x0 + ((k % nx) as f64 + 0.5) * step,
            f.y0 + ((k / nx) as f64 + 0.5) * step,
        )
    };
    // Do all cells that meet the rectangles lie in the mask?
    let in_mask = |mask: &[bool], boxes: &[(f64, f64, f64, f64)]| {
        boxes.iter().all(|&(x, y, w, h)| {
            let i0 = ((x - f.x0) / step).floor();
            let i1 = ((x + w - f.x0) / step).floor();
            let j0 = ((y - f.y0) / step).floor();
            let j1 = ((y + h - f.y0) / step).floor();
            if i0 < 0.0 || j0 < 0.0 || i1 >= nx as f64 || j1 >= ny as f64 {
                return false;
            }
            let (i0, i1, j0, j1) = (i0 as usize, i1 as usize, j0 as usize, j1 as usize);
            (j0..=j1).all(|j| (i0..=i1).all(|i| mask[at(i, j)]))
        })
    };
    let mark = |mask: &mut [bool], boxes: &[(f64, f64, f64, f64)]| {
        for &(x, y, w, h) in boxes {
            let i0 = ((x - f.x0) / step).floor().max(0.0) as usize;
            let j0 = ((y - f.y0) / step).floor().max(0.0) as usize;
            let i1 = (((x + w - f.x0) / step).floor().max(0.0) as usize).min(nx - 1);
            let j1 = (((y + h - f.y0) / step).floor().max(0.0) as usize).min(ny - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    mask[at(i, j)] = false;
                }
            }
        }
    };
    // Empty (inadmissible) cells not yet taken by a label set outside its camera.
    let mut empty: Vec<bool> = cells.iter().map(|c| c.is_none()).collect();
    let mut out = Vec::new();
    for &camera in cameras {
        let inside: Vec<bool> = cells.iter().map(|c| *c == Some(camera)).collect();
        let (anchor, tori, fits, room) = if inside.iter().any(|&x| x) {
            let d = distance_transform(&inside, nx, ny);
            let mut order: Vec<usize> = (0..d.len()).filter(|&k| d[k] > 0).collect();
            order.sort_by(|&p, &q| d[q].cmp(&d[p]).then(p.cmp(&q)));
            let fitting = order.iter().copied().find(|&k| {
                let (x, y) = centre(k);
                in_mask(&inside, &label_boxes(camera, x, y, 2.0))
            });
            let best = fitting.unwrap_or(order[0]);
            let (x, y) = centre(best);
            let tori = classify(g.a, g.b, f.m_of(x), f.h_of(y)).map_or(0, |(_, t)| t);
            let room = d[order[0]] as f64 / 3.0 * step;
            (centre(best), tori, fitting.is_some(), room)
        } else if let Some(&(_, anchor, tori)) = thin.iter().find(|t| t.0 == camera) {
            (anchor, tori, false, 0.0)
        } else {
            continue;
        };
        let text = if fits {
            anchor
        } else {
            // Nearest empty place at least 36 px away; it is then taken.
            let spot = (0..cells.len())
                .filter(|&k| empty[k])
                .map(|k| {
                    let c = centre(k);
                    (c, (c.0 - anchor.0).hypot(c.1 - anchor.1))
                })
                .filter(|&(_, dist)| dist >= 36.0)
                .filter(|&(c, _)| in_mask(&empty, &label_boxes(camera, c.0, c.1, 6.0)))
                .min_by(|p, q| p.1.total_cmp(&q.1))
                .map(|(c, _)| c);
            match spot {
                Some(c) => {
                    mark(&mut empty, &label_boxes(camera, c.0, c.1, 10.0));
                    c
                }
                None => anchor,
            }
        };
        out.push(LabelPlacement {
            camera,
            tori,
            anchor,
            text,
            room,
        });
    }
    out
}

/// Write the clip path, background, camera fills, the line m = 0 and Σ of one plot; return the
/// camera polygons. `prefix` makes the ids unique ("" for the main plot).
fn draw_plot(
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
fn draw_axes(s: &mut String, f: &Frame, ticks: f64, font: f64, grid: bool) {
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

fn draw_labels(s: &mut String, f: &Frame, labels: &[LabelPlacement]) {
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

/// Anchors (px) for cameras that the label raster misses but the strip sweep found.
fn thin_anchors(g: &Geometry, f: &Frame, chains: &[Chain]) -> Vec<(Camera, (f64, f64), usize)> {
    let mut out: Vec<(Camera, (f64, f64), usize)> = Vec::new();
    for camera in Camera::ALL {
        let best = chains
            .iter()
            .filter(|c| c.camera == camera)
            .max_by(|p, q| p.widest.2.total_cmp(&q.widest.2));
        if let Some(ch) = best {
            let (m, h, _) = ch.widest;
            let tori = classify(g.a, g.b, m, h).map_or(0, |(_, t)| t);
            out.push((camera, (f.px(m), f.py(h)), tori));
        }
    }
    out
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

// ---------------------------------------------------------------------------------------------
// Point description
// ---------------------------------------------------------------------------------------------

fn finite_or_null<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_some(x)
    } else {
        s.serialize_none()
    }
}

/// One end of an oscillation segment in the variable s (s₁ or s₂).
#[derive(Clone, Debug, Serialize)]
pub struct SegmentEnd {
    /// The root it stands for: "a", "-a", "b", "-b", "theta1", "theta2".
    pub label: RootLabel,
    /// Its value in s (±∞ only for s₁ at m = 0, where θ₂ = ∞; serialized as null).
    #[serde(serialize_with = "finite_or_null")]
    pub value: f64,
}

/// One radical of a separated variable and whether it keeps a constant sign on the torus.
#[derive(Clone, Debug, Serialize)]
pub struct RadicalDescription {
    /// "F1*", "G1*" (F₁/s₁, G₁/s₁, of x = 1/s₁; seed eq. 3.2), "F2", "G2".
    pub name: &'static str,
    /// True when neither end of the segment is a root of this radical: its sign is a free
    /// constant that tells the Liouville tori apart.
    pub constant_sign: bool,
    /// Its sign on torus 0 (+1 or −1; for a radical that changes sign: the sign while the
    /// variable leaves the lower end λ of the segment in its coordinate).
    pub sign_on_torus0: i32,
}

/// One separated variable at a point (m, h).
#[derive(Clone, Debug, Serialize)]
pub struct VariableDescription {
    /// "s1" or "s2".
    pub variable: &'static str,
    /// The coordinate the motion is computed in: "x = 1/s1" or "s2".
    pub coordinate: &'static str,
    /// The oscillation segment [λ, μ] in that coordinate.
    pub coordinate_segment: [f64; 2],
    /// The segment in s. For s₁ through infinity (Table 1's `[A (±∞) B]`, B < 0 < A): s₁ runs
    /// from `start` = A up through ±∞ to `end` = B; otherwise `start` ≤ `end`.
    pub start: SegmentEnd,
    pub end: SegmentEnd,
    pub through_infinity: bool,
    /// The segment in Table 1's notation, e.g. "[a, θ2]", "[a (±∞) -a]", "[-b, θ1]".
    pub table1: String,
    /// k² and k′² of the Jacobi functions.
    pub k2: f64,
    pub kc2: f64,
    /// Period in time of the angle on the torus and its angular frequency 2π/period.
    pub period: f64,
    pub frequency: f64,
    pub radicals: [RadicalDescription; 2],
}

/// Everything about one point (m, h) of the admissible region for fields a > b > 0.
#[derive(Clone, Debug, Serialize)]
pub struct PointDescription {
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    /// ℓ = √(2p²m² + 2hm + 1).
    pub ell: f64,
    /// θ₁ = (ℓ − 1)/(2m), θ₂ = (ℓ + 1)/(2m), the roots of Φ (θ₂ = ±∞ at m = 0: null).
    #[serde(serialize_with = "finite_or_null")]
    pub theta1: f64,
    #[serde(serialize_with = "finite_or_null")]
    pub theta2: f64,
    /// "I+", "I-", …, "VI".
    pub camera: Camera,
    /// Table 1's order of the roots of Φ among ±a, ±b in this camera.
    pub table1_roots: &'static str,
    /// Number of Liouville tori of the integral manifold.
    pub tori: usize,
    pub s1: VariableDescription,
    pub s2: VariableDescription,
    /// ν₁/ν₂.
    pub rotation_number: f64,
}

fn radical_descriptions(
    radicands: (&Radicand<f64>, &Radicand<f64>),
    var: &SeparatedVariable<f64>,
) -> [RadicalDescription; 2] {
    let ends = [var.lambda.label, var.mu.label];
    let (sf, sg) = var.signs();
    let one = |r: &Radicand<f64>, sign: i32| RadicalDescription {
        name: r.name,
        constant_sign: r.roots.iter().all(|root| !ends.contains(&root.label)),
        sign_on_torus0: sign,
    };
    [one(radicands.0, sf), one(radicands.1, sg)]
}

fn describe_variable(
    var: &SeparatedVariable<f64>,
    radicands: (&Radicand<f64>, &Radicand<f64>),
    first: bool,
    period: f64,
    frequency: f64,
) -> VariableDescription {
    let (lam, mu) = var.segment();
    let (start, end, through_infinity) = if first {
        // x = 1/s1 on [λ, μ]: s1 = 1/x.
        let s_of = |x: f64, lower_end: bool| {
            if x != 0.0 {
                1.0 / x
            } else if lower_end {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            }
        };
        let s_lam = SegmentEnd {
            label: var.lambda.label,
            value: s_of(lam, true),
        };
        let s_mu = SegmentEnd {
            label: var.mu.label,
            value: s_of(mu, false),
        };
        // x on one side of 0: s1 ∈ [1/μ, 1/λ]; x through 0: s1 runs from A = 1/μ > 0 up to +∞,
        // then from −∞ to B = 1/λ < 0.
        (s_mu, s_lam, lam < 0.0 && mu > 0.0)
    } else {
        (
            SegmentEnd {
                label: var.lambda.label,
                value: lam,
            },
            SegmentEnd {
                label: var.mu.label,
                value: mu,
            },
            false,
        )
    };
    let table1 = if through_infinity {
        format!("[{} (±∞) {}]", start.label, end.label)
    } else {
        format!("[{}, {}]", start.label, end.label)
    };
    VariableDescription {
        variable: if first { "s1" } else { "s2" },
        coordinate: var.name,
        coordinate_segment: [lam, mu],
        start,
        end,
        through_infinity,
        table1,
        k2: var.modulus.k2,
        kc2: var.modulus.kc2,
        period,
        frequency,
        radicals: radical_descriptions(radicands, var),
    }
}

/// Describe the point (m, h) for the fields a > b > 0: its camera and everything about the
/// motion on its tori (see [`PointDescription`]). Errors: a ≤ b or b ≤ 0 or non-finite input
/// ([`ClosedFormError::Parameters`]), a point outside the admissible region
/// ([`ClosedFormError::NotAdmissible`], naming the boundary it is beyond) or on Σ
/// ([`ClosedFormError::OnSigma`], naming the curve).
pub fn describe_point(a: f64, b: f64, m: f64, h: f64) -> Result<PointDescription, ClosedFormError> {
    check_fields(a, b)?;
    let motion = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())?;
    let c: &IntegralConstants<f64> = &motion.constants;
    let [(t1n, t1d), (t2n, t2d)] = c.thetas();
    let periods = motion.periods();
    let freqs = motion.frequencies();
    let (f1, g1) = c.radicands_x();
    let (f2, g2) = c.radicands_s2();
    let s1 = describe_variable(&motion.first, (&f1, &g1), true, periods[0], freqs[0]);
    let s2 = describe_variable(&motion.second, (&f2, &g2), false, periods[1], freqs[1]);
    Ok(PointDescription {
        a,
        b,
        m,
        h,
        ell: c.ell,
        theta1: t1n / t1d,
        theta2: t2n / t2d,
        camera: motion.camera,
        table1_roots: motion.camera.table1_roots(),
        tori: motion.tori,
        s1,
        s2,
        rotation_number: motion.rotation_number(),
    })
}

fn num(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x.is_infinite() {
        if x > 0.0 { "+∞" } else { "−∞" }.to_string()
    } else if x != 0.0 && (x.abs() >= 1e6 || x.abs() < 1e-4) {
        format!("{x:.6e}")
    } else {
        format!("{x:.6}")
    }
}

impl fmt::Display for PointDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Point (m, h) = ({}, {}) for a = {}, b = {}",
            self.m, self.h, self.a, self.b
        )?;
        writeln!(
            f,
            "  ℓ = {}   θ1 = {}   θ2 = {}",
            num(self.ell),
            num(self.theta1),
            num(self.theta2)
        )?;
        writeln!(
            f,
            "  camera {}   roots of Φ: {}   {}",
            self.camera,
            self.table1_roots,
            tori_text(self.tori)
        )?;
        writeln!(f)?;
        writeln!(
            f,
            "  {:<4} {:<15} {:<36} {:<10} {:<10} {:<12} {:<12} radicals",
            "var", "segment", "numeric (in s)", "k²", "k′²", "period", "frequency"
        )?;
        for v in [&self.s1, &self.s2] {
            let numeric = if v.through_infinity {
                format!("[{} (±∞) {}]", num(v.start.value), num(v.end.value))
            } else {
                format!("[{}, {}]", num(v.start.value), num(v.end.value))
            };
            let radicals: Vec<String> = v
                .radicals
                .iter()
                .map(|r| {
                    if r.constant_sign {
                        format!("{} constant sign", r.name)
                    } else {
                        format!("{} changes sign", r.name)
                    }
                })
                .collect();
            writeln!(
                f,
                "  {:<4} {:<15} {:<36} {:<10} {:<10} {:<12} {:<12} {}",
                v.variable,
                v.table1,
                numeric,
                format!("{:.6}", v.k2),
                format!("{:.6}", v.kc2),
                num(v.period),
                num(v.frequency),
                radicals.join(", ")
            )?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "  x = 1/s1 oscillates on [{}, {}]; rotation number ν1/ν2 = {}",
            num(self.s1.coordinate_segment[0]),
            num(self.s1.coordinate_segment[1]),
            num(self.rotation_number)
        )
    }
}
