//! The data of the seed's Table 1 (roots of Φ and oscillation segments, computed at a
//! representative point of each camera) and of Table 2 with the text of sec. 3 (pendulum-type
//! motions and the symmetry planes of the connected bearing surfaces, measured).

use rsts_closed_form::constants::IntegralConstants;
use rsts_closed_form::diagram::default_window;
use rsts_closed_form::roots::{Root, RootLabel};
use rsts_closed_form::separated::segments;
use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice, EXAMPLE_POINTS_A1_B05};
use serde::Serialize;

use crate::classify::{camera_geometry, plane_names, CameraGeometry, PendulumKind};
use crate::mesh::Surface;
use crate::GeometryError;

/// The camera at (m, h) from the oscillation segments alone (f64, no elliptic functions).
pub fn quick_camera(a: f64, b: f64, m: f64, h: f64) -> Option<Camera> {
    let c = IntegralConstants::new(a, b, m, h).ok()?;
    let (f1, g1) = c.radicands_x();
    let (f2, g2) = c.radicands_s2();
    let s1 = segments(&f1, &g1);
    let s2 = segments(&f2, &g2);
    let (x, y) = (s1.first()?, s2.first()?);
    Camera::from_segments([x.0.label, x.1.label], [y.0.label, y.1.label], m < 0.0)
}

/// Grid of the scan for representative points (per side).
const SCAN: usize = 240;

/// A point (m, h) well inside each camera for the fields (a, b): the repository's test points
/// scaled when b/a = 1/2 ((m, h) → (m/a, a·h) leaves ℓ and the camera unchanged), otherwise the
/// grid point of the default diagram window farthest (in window-normalised units) from every
/// other camera. Cameras not found on the grid are missing from the result.
pub fn representative_points(a: f64, b: f64) -> Result<Vec<(Camera, f64, f64)>, GeometryError> {
    let ((m_lo, m_hi), (h_lo, h_hi)) = default_window(a, b)?;
    if b == 0.5 * a {
        return Ok(EXAMPLE_POINTS_A1_B05
            .iter()
            .map(|&(c, m, h)| (c, m / a, a * h))
            .collect());
    }
    let mut out = interior_points(a, b, SCAN, ((m_lo, m_hi), (h_lo, h_hi)));
    if out.len() < Camera::ALL.len() {
        // Thin cameras (VI for small b/a, V for b near a) can fall between the grid points.
        let fine = interior_points(a, b, 4 * SCAN, ((m_lo, m_hi), (h_lo, h_hi)));
        out = Camera::ALL
            .iter()
            .filter_map(|c| out.iter().chain(fine.iter()).find(|p| p.0 == *c).copied())
            .collect();
    }
    Ok(out)
}

/// One row of Table 1, computed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table1Row {
    pub camera: Camera,
    pub m: f64,
    pub h: f64,
    pub theta1: f64,
    pub theta2: f64,
    /// All six roots ±a, ±b, θ₁, θ₂ in increasing order, as computed.
    pub roots_order: String,
    /// The paper's (partial) order of the roots of Φ.
    pub paper_roots: &'static str,
    /// Whether the computed values satisfy the paper's chain of inequalities.
    pub roots_agree: bool,
    /// Oscillation segments of s₁ and s₂ from the computed x = 1/s₁ and s₂ segments.
    pub s1_segment: String,
    pub s2_segment: String,
    pub paper_s1: &'static str,
    pub paper_s2: &'static str,
    pub segments_agree: bool,
    /// Segments as numbers: x = 1/s₁ ∈ [λ, μ], s₂ ∈ [λ, μ].
    pub x_segment: (f64, f64),
    pub s2_values: (f64, f64),
    pub tori: usize,
}

/// The label as printed in Table 1.
pub fn root_name(l: RootLabel) -> &'static str {
    match l {
        RootLabel::PlusA => "a",
        RootLabel::MinusA => "-a",
        RootLabel::PlusB => "b",
        RootLabel::MinusB => "-b",
        RootLabel::Theta1 => "θ1",
        RootLabel::Theta2 => "θ2",
    }
}

/// The s₁ segment from the x = 1/s₁ segment [λ, μ]: s₁ runs from 1/μ to 1/λ, through ±∞ when
/// λ < 0 < μ (printed `[A (±∞) B]` as in Table 1).
pub fn s1_segment_text(lambda: &Root<f64>, mu: &Root<f64>) -> String {
    let through_infinity = lambda.value_f64() < 0.0 && mu.value_f64() > 0.0;
    let sep = if through_infinity { " (±∞) " } else { ", " };
    format!("[{}{sep}{}]", root_name(mu.label), root_name(lambda.label))
}

/// Whether the chain "r1 < r2 < …" of root names holds for the values.
fn chain_holds(chain: &str, value: impl Fn(&str) -> Option<f64>) -> bool {
    let vals: Option<Vec<f64>> = chain.split('<').map(|s| value(s.trim())).collect();
    vals.is_some_and(|v| v.windows(2).all(|w| w[0] < w[1]))
}

/// Table 1 at the representative points of (a, b).
pub fn table1(a: f64, b: f64) -> Result<Vec<Table1Row>, GeometryError> {
    let mut rows = Vec::new();
    for (camera, m, h) in representative_points(a, b)? {
        let motion = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())?;
        let c = &motion.constants;
        let [(t1n, t1d), (t2n, t2d)] = c.thetas();
        let (theta1, theta2) = (t1n / t1d, t2n / t2d);
        let value = |name: &str| -> Option<f64> {
            Some(match name {
                "a" => a,
                "-a" => -a,
                "b" => b,
                "-b" => -b,
                "θ1" => theta1,
                "θ2" => theta2,
                _ => return None,
            })
        };
        let mut all = [
            ("-a", -a),
            ("-b", -b),
            ("b", b),
            ("a", a),
            ("θ1", theta1),
            ("θ2", theta2),
        ];
        all.sort_by(|p, q| p.1.total_cmp(&q.1));
        let roots_order = all.iter().map(|p| p.0).collect::<Vec<_>>().join(" < ");
        let paper_roots = motion.camera.table1_roots();
        let (paper_s1, paper_s2) = motion.camera.table1_segments();
        let s1 = s1_segment_text(&motion.first.lambda, &motion.first.mu);
        let s2 = format!(
            "[{}, {}]",
            root_name(motion.second.lambda.label),
            root_name(motion.second.mu.label)
        );
        let norm = |s: &str| s.replace(' ', "");
        rows.push(Table1Row {
            camera,
            m,
            h,
            theta1,
            theta2,
            roots_order,
            paper_roots,
            roots_agree: chain_holds(paper_roots, value) && motion.camera == camera,
            segments_agree: norm(&s1) == norm(paper_s1) && norm(&s2) == norm(paper_s2),
            s1_segment: s1,
            s2_segment: s2,
            paper_s1,
            paper_s2,
            x_segment: motion.first.segment(),
            s2_values: motion.second.segment(),
            tori: motion.tori,
        });
    }
    Ok(rows)
}

/// What the seed says (sec. 3) for a camera: the first and second partial motions, the
/// semi-moving frame ("always an oscillation") and the one symmetry plane named per camera.
/// Only for comparison columns; nothing is computed from it.
pub fn paper_claims(camera: Camera) -> (PendulumKind, PendulumKind, PendulumKind, usize) {
    use Camera::*;
    use PendulumKind::{Oscillation as O, Rotation as R};
    match camera {
        IPlus | IMinus => (O, O, O, 2),
        IIPlus | IIMinus => (O, R, O, 2),
        III => (R, O, O, 2),
        IVPlus | IVMinus => (O, R, O, 1),
        V => (R, R, O, 2),
        VI => (R, O, O, 0),
    }
}

/// One row of Table 2 (the JSON of `rsts table2`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table2Row {
    pub camera: &'static str,
    pub m: f64,
    pub h: f64,
    pub tori: usize,
    pub first_partial: PendulumKind,
    pub second_partial: PendulumKind,
    pub semi_moving: PendulumKind,
    /// Planes ωᵢ = 0 every connected P-surface is symmetric to.
    pub symmetry_planes: Vec<&'static str>,
    /// Planes Ωᵢ = 0 every connected Π-surface is symmetric to.
    pub pi_symmetry_planes: Vec<&'static str>,
    /// Radicals changing sign on the torus (F1*, G1* along ψ1; F2, G2 along ψ2).
    pub radicals_changing_sign: Vec<&'static str>,
    /// Worst [`crate::classify::reflection_score`] per plane on torus 0 (P-surface).
    pub p_scores: [f64; 3],
    /// Where the row differs from the seed's text.
    pub differs_from_paper: Vec<String>,
}

impl Table2Row {
    pub fn from_geometry(g: &CameraGeometry) -> Self {
        let r = g.kinds.radicals_change_sign;
        let radicals = [("F1*", r.f1), ("G1*", r.g1), ("F2", r.f2), ("G2", r.g2)]
            .iter()
            .filter(|p| p.1)
            .map(|p| p.0)
            .collect();
        let (pf, ps, pm, plane) = paper_claims(g.camera);
        let mut diff = Vec::new();
        let kinds = [
            ("first partial", pf, g.kinds.first_partial),
            ("second partial", ps, g.kinds.second_partial),
            ("semi-moving", pm, g.kinds.semi_moving),
        ];
        for (what, paper, ours) in kinds {
            if paper != ours {
                diff.push(format!(
                    "{what}: paper {}, computed {}",
                    paper.as_str(),
                    ours.as_str()
                ));
            }
        }
        let names = Surface::P.axis_names();
        if g.p_planes != [plane] {
            diff.push(format!(
                "symmetry planes: paper {}, computed [{}]",
                names[plane],
                plane_names(&g.p_planes, Surface::P).join(", ")
            ));
        }
        Self {
            camera: g.camera.label(),
            m: g.m,
            h: g.h,
            tori: g.tori,
            first_partial: g.kinds.first_partial,
            second_partial: g.kinds.second_partial,
            semi_moving: g.kinds.semi_moving,
            symmetry_planes: plane_names(&g.p_planes, Surface::P),
            pi_symmetry_planes: plane_names(&g.pi_planes, Surface::Pi),
            radicals_changing_sign: radicals,
            p_scores: g
                .tori_symmetry
                .first()
                .map_or([f64::NAN; 3], |s| s.p_self_score),
            differs_from_paper: diff,
        }
    }
}

/// Table 2 at the representative points of (a, b).
pub fn table2(a: f64, b: f64) -> Result<Vec<Table2Row>, GeometryError> {
    representative_points(a, b)?
        .into_iter()
        .map(|(_, m, h)| camera_geometry(a, b, m, h).map(|g| Table2Row::from_geometry(&g)))
        .collect()
}

/// For each camera met on an n × n grid of the window, the grid point farthest from every other
/// camera and from the inadmissible region (two-pass chamfer distance in cells).
fn interior_points(
    a: f64,
    b: f64,
    n: usize,
    window: ((f64, f64), (f64, f64)),
) -> Vec<(Camera, f64, f64)> {
    let ((m_lo, m_hi), (h_lo, h_hi)) = window;
    let at = |i: usize, lo: f64, hi: f64| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
    let label: Vec<Option<Camera>> = (0..n * n)
        .map(|k| quick_camera(a, b, at(k % n, m_lo, m_hi), at(k / n, h_lo, h_hi)))
        .collect();
    // Two-pass chamfer distance (in cells) to the nearest cell of another label.
    let mut dist: Vec<f64> = vec![f64::INFINITY; n * n];
    for k in 0..n * n {
        let (i, j) = (k % n, k / n);
        let edge = i == 0 || j == 0 || i + 1 == n || j + 1 == n;
        let differs = [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .any(|(di, dj)| {
                let (p, q) = (i as i64 + di, j as i64 + dj);
                p >= 0 && q >= 0 && (p as usize) < n && (q as usize) < n && {
                    label[q as usize * n + p as usize] != label[k]
                }
            });
        if label[k].is_none() || differs || edge {
            dist[k] = 0.0;
        }
    }
    let r2 = std::f64::consts::SQRT_2;
    let fwd = [(-1i64, 0i64, 1.0), (0, -1, 1.0), (-1, -1, r2), (1, -1, r2)];
    for pass in 0..2 {
        for step in 0..n * n {
            let k = if pass == 0 { step } else { n * n - 1 - step };
            let (i, j) = ((k % n) as i64, (k / n) as i64);
            for &(di, dj, w) in &fwd {
                let (di, dj) = if pass == 0 { (di, dj) } else { (-di, -dj) };
                let (p, q) = (i + di, j + dj);
                if p >= 0 && q >= 0 && (p as usize) < n && (q as usize) < n {
                    let d = dist[q as usize * n + p as usize] + w;
                    if d < dist[k] {
                        dist[k] = d;
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    for camera in Camera::ALL {
        let best = (0..n * n)
            .filter(|&k| label[k] == Some(camera) && dist[k] > 0.0)
            .max_by(|&p, &q| dist[p].total_cmp(&dist[q]));
        if let Some(k) = best {
            out.push((camera, at(k % n, m_lo, m_hi), at(k / n, h_lo, h_hi)));
        }
    }
    out
}
