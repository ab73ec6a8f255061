//! The curves of Σ as functions h(m), the pixel frame of a plot, the camera at a point, and the
//! sweep of the window in vertical strips that joins the pieces of each camera into polygons.

use crate::camera::Camera;
use crate::constants::{IntegralConstants, SigmaCurve};
use crate::motion::{ExplicitMotion, TorusChoice};
use crate::separated::segments;

/// The camera at (m, h), if the point is admissible and off Σ: the same choice as
/// [`ExplicitMotion::new`] (the first oscillation segment of each variable), without building
/// the elliptic parametrisation — cheap enough for a raster.
pub fn camera_at(a: f64, b: f64, m: f64, h: f64) -> Option<Camera> {
    let c = IntegralConstants::new(a, b, m, h).ok()?;
    let (f1, g1) = c.radicands_x();
    let (f2, g2) = c.radicands_s2();
    let s1 = segments(&f1, &g1);
    let s2 = segments(&f2, &g2);
    let (x, y) = (s1.first()?, s2.first()?);
    Camera::from_segments([x.0.label, x.1.label], [y.0.label, y.1.label], c.m < 0.0)
}

/// The camera and number of tori at (m, h), if the point is admissible and off Σ.
pub(super) fn classify(a: f64, b: f64, m: f64, h: f64) -> Option<(Camera, usize)> {
    ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())
        .ok()
        .map(|e| (e.camera, e.tori))
}

/// a, b and the derived constants, for the curves of Σ as functions h(m).
#[derive(Clone, Copy, Debug)]
pub(super) struct Geometry {
    pub(super) a: f64,
    pub(super) b: f64,
    p2: f64,
    r2: f64,
}

impl Geometry {
    pub(super) fn new(a: f64, b: f64) -> Self {
        Self {
            a,
            b,
            p2: a * a + b * b,
            r2: a * a - b * b,
        }
    }

    /// h on the curve at m (the hyperbola's branch m < 0: h = −p²m − 1/(2m)).
    pub(super) fn curve_h(&self, c: SigmaCurve, m: f64) -> f64 {
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
    pub(super) fn domain(&self, c: SigmaCurve) -> (f64, f64) {
        let (a, b) = (self.a, self.b);
        match c {
            SigmaCurve::OuterA => (1.0 / (a + b), f64::INFINITY),
            SigmaCurve::OuterB => (f64::NEG_INFINITY, 1.0 / (a + b)),
            SigmaCurve::Hyperbola => (f64::NEG_INFINITY, 0.0),
            SigmaCurve::InnerA => (-1.0 / (a - b), f64::INFINITY),
            SigmaCurve::InnerB => (f64::NEG_INFINITY, 1.0 / (a - b)),
        }
    }

    pub(super) fn is_outer(c: SigmaCurve) -> bool {
        matches!(
            c,
            SigmaCurve::OuterA | SigmaCurve::OuterB | SigmaCurve::Hyperbola
        )
    }

    /// The m where the curve reaches the level h = level (inside its domain).
    pub(super) fn crossings(&self, c: SigmaCurve, level: f64) -> Vec<f64> {
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
pub(super) struct Frame {
    pub(super) m_lo: f64,
    pub(super) m_hi: f64,
    pub(super) h_lo: f64,
    pub(super) h_hi: f64,
    pub(super) x0: f64,
    pub(super) y0: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

impl Frame {
    pub(super) fn px(&self, m: f64) -> f64 {
        self.x0 + (m - self.m_lo) / (self.m_hi - self.m_lo) * self.w
    }
    pub(super) fn py(&self, h: f64) -> f64 {
        self.y0 + (self.h_hi - h) / (self.h_hi - self.h_lo) * self.h
    }
    pub(super) fn m_of(&self, x: f64) -> f64 {
        self.m_lo + (x - self.x0) / self.w * (self.m_hi - self.m_lo)
    }
    pub(super) fn h_of(&self, y: f64) -> f64 {
        self.h_hi - (y - self.y0) / self.h * (self.h_hi - self.h_lo)
    }
}

/// A chain of strip pieces of one camera, as a polygon: the upper edge left to right and the
/// lower edge left to right.
#[derive(Clone, Debug)]
pub(super) struct Chain {
    pub(super) camera: Camera,
    pub(super) upper: Vec<(f64, f64)>,
    pub(super) lower: Vec<(f64, f64)>,
    /// The middle (m, h) of its tallest piece and the piece's height.
    pub(super) widest: (f64, f64, f64),
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
pub(super) fn camera_chains(g: &Geometry, f: &Frame) -> Vec<Chain> {
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
pub(super) fn simplify_ring(pts: &[(f64, f64)], tol: f64) -> Vec<(f64, f64)> {
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
