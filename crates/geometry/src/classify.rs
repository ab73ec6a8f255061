//! The decomposition Q = Q″Q′ of sec. 2 measured on the motion: which radicals change sign on
//! the torus, the pendulum-type motions (semi-moving frame, eq. 2.6; the two partial motions of
//! eq. 2.8, driven by F₁* and by F₂) as oscillation or rotation, and the coordinate planes each
//! connected bearing surface is symmetric to, measured on the meshes.
//!
//! Nothing here reads the paper's tables: every answer comes from sampled closed-form values.

use rsts_closed_form::{Camera, ExplicitMotion, ExplicitState, TorusChoice};
use serde::Serialize;

use crate::mesh::{all_tori, local_spacing, Surface, TorusMesh};
use crate::nearest::KdTree;
use crate::GeometryError;

/// A pendulum-type motion (fixed axis of instant rotation): an oscillation if the angular
/// velocity periodically reverses, a rotation if its direction is constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PendulumKind {
    Oscillation,
    Rotation,
}

impl PendulumKind {
    pub fn as_str(&self) -> &'static str {
        match self {
            PendulumKind::Oscillation => "oscillation",
            PendulumKind::Rotation => "rotation",
        }
    }

    fn from_sign_change(changes: bool) -> Self {
        if changes {
            PendulumKind::Oscillation
        } else {
            PendulumKind::Rotation
        }
    }
}

/// Samples per angle for the sign analysis.
pub const SIGN_SAMPLES: usize = 256;

/// Whether sampled values of a periodic function change sign: some cyclically adjacent pair
/// has strictly opposite signs. Zeros are skipped (a zero between opposite signs still counts).
pub fn changes_sign(values: &[f64]) -> bool {
    let signs: Vec<f64> = values
        .iter()
        .filter(|v| **v != 0.0 && v.is_finite())
        .map(|v| v.signum())
        .collect();
    signs.iter().any(|s| *s != signs[0])
}

/// The signs of the four radicals along the torus.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RadicalSignChanges {
    /// F₁* along ψ₁.
    pub f1: bool,
    /// G₁* along ψ₁.
    pub g1: bool,
    /// F₂ along ψ₂.
    pub f2: bool,
    /// G₂ along ψ₂.
    pub g2: bool,
}

/// The pendulum-type motions of one torus, from the motion itself.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionKinds {
    pub radicals_change_sign: RadicalSignChanges,
    /// Partial motion ω″₍₁₎ (eq. 2.8), driven by F₁*: oscillation iff F₁* changes sign.
    pub first_partial: PendulumKind,
    /// Partial motion ω″₍₂₎, driven by F₂.
    pub second_partial: PendulumKind,
    /// Semi-moving frame relative to the body, ω′ = (0, 0, ω′₃) (eq. 2.6): oscillation iff ω′₃
    /// changes sign on the torus (the motion is dense on a non-resonant torus).
    pub semi_moving: PendulumKind,
    /// min and max of ω′₃ over the torus.
    pub omega3_prime_range: (f64, f64),
}

/// Sample F₁*, G₁* over one period of ψ₁ and F₂, G₂ over ψ₂ (at a generic value of the other
/// angle), and ω′₃ on an n × n grid of the torus; half-step offsets avoid the turning points.
pub fn motion_kinds(motion: &ExplicitMotion<f64>) -> MotionKinds {
    let n = SIGN_SAMPLES;
    let at = |i: usize| std::f64::consts::TAU * (i as f64 + 0.5) / n as f64;
    let generic = 0.7;
    let along1: Vec<ExplicitState<f64>> =
        (0..n).map(|i| motion.at_angles(&at(i), &generic)).collect();
    let along2: Vec<ExplicitState<f64>> =
        (0..n).map(|i| motion.at_angles(&generic, &at(i))).collect();
    let ch = |states: &[ExplicitState<f64>], f: fn(&ExplicitState<f64>) -> f64| {
        changes_sign(&states.iter().map(f).collect::<Vec<_>>())
    };
    let radicals = RadicalSignChanges {
        f1: ch(&along1, |s| s.coords.f1),
        g1: ch(&along1, |s| s.coords.g1),
        f2: ch(&along2, |s| s.coords.f2),
        g2: ch(&along2, |s| s.coords.g2),
    };
    let m = 64;
    let mut w3 = Vec::with_capacity(m * m);
    for i in 0..m {
        for j in 0..m {
            let p1 = std::f64::consts::TAU * (i as f64 + 0.25) / m as f64;
            let p2 = std::f64::consts::TAU * (j as f64 + 0.25) / m as f64;
            w3.push(motion.at_angles(&p1, &p2).omega_prime[2]);
        }
    }
    let lo = w3.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = w3.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    MotionKinds {
        radicals_change_sign: radicals,
        first_partial: PendulumKind::from_sign_change(radicals.f1),
        second_partial: PendulumKind::from_sign_change(radicals.f2),
        semi_moving: PendulumKind::from_sign_change(changes_sign(&w3)),
        omega3_prime_range: (lo, hi),
    }
}

/// |ω − (ω′ + Q′ᵀ(ω″₍₁₎ + ω″₍₂₎))|∞ at one state (sec. 2: ω = ω′ + Q′ᵀω″, ω″ = ω″₍₁₎ + ω″₍₂₎).
pub fn decomposition_residual(s: &ExplicitState<f64>) -> f64 {
    let w2: [f64; 3] = std::array::from_fn(|k| s.omega_second_1[k] + s.omega_second_2[k]);
    (0..3)
        .map(|i| {
            let qt: f64 = (0..3).map(|k| s.q_prime[k][i] * w2[k]).sum();
            (s.omega[i] - s.omega_prime[i] - qt).abs()
        })
        .fold(0.0, f64::max)
}

/// A reflection counts as a symmetry when every reflected vertex lies within this fraction of
/// its local mesh spacing (longest incident edge) from a vertex of the target mesh.
pub const SYMMETRY_TOLERANCE: f64 = 0.5;

/// max over vertices v of dist(R_axis v, target vertices) / spacing(v): ≈ 0 when the reflection
/// maps the grid onto itself, ≲ 1 for any symmetry, ≫ 1 when the reflection is not one.
pub fn reflection_score(
    source: &[[f64; 3]],
    spacing: &[f64],
    target: &KdTree<'_>,
    axis: usize,
) -> f64 {
    let mut worst = 0.0f64;
    for (p, s) in source.iter().zip(spacing) {
        let mut q = *p;
        q[axis] = -q[axis];
        let d = target.nearest_distance(q);
        let ratio = if *s > 0.0 {
            d / s
        } else if d > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        worst = worst.max(ratio);
    }
    worst
}

/// Symmetries of the bearing surfaces of one torus under the three coordinate reflections.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TorusSymmetry {
    pub torus: usize,
    /// [`reflection_score`] of the P-surface onto itself, per plane ω₁ = 0, ω₂ = 0, ω₃ = 0.
    pub p_self_score: [f64; 3],
    /// The same for the Π-surface.
    pub pi_self_score: [f64; 3],
    /// For each plane, the tori whose P-surface the reflection of this one lands on.
    pub p_images: [Vec<usize>; 3],
}

/// Reflect every torus's surfaces through each coordinate plane and compare with every torus.
pub fn symmetries(meshes: &[TorusMesh]) -> Vec<TorusSymmetry> {
    let trees: Vec<[KdTree<'_>; 2]> = meshes
        .iter()
        .map(|m| Surface::BOTH.map(|s| KdTree::new(m.vertices(s))))
        .collect();
    let spacing: Vec<[Vec<f64>; 2]> = meshes
        .iter()
        .map(|m| Surface::BOTH.map(|s| local_spacing(m.vertices(s), &m.triangles)))
        .collect();
    meshes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let self_score = |si: usize| -> [f64; 3] {
                std::array::from_fn(|axis| {
                    reflection_score(
                        m.vertices(Surface::BOTH[si]),
                        &spacing[k][si],
                        &trees[k][si],
                        axis,
                    )
                })
            };
            let p_images = std::array::from_fn(|axis| {
                (0..meshes.len())
                    .filter(|&j| {
                        reflection_score(&m.omega, &spacing[k][0], &trees[j][0], axis)
                            < SYMMETRY_TOLERANCE
                    })
                    .collect()
            });
            TorusSymmetry {
                torus: m.torus,
                p_self_score: self_score(0),
                pi_self_score: self_score(1),
                p_images,
            }
        })
        .collect()
}

/// Planes (0, 1, 2 for ω₁, ω₂, ω₃ = 0) with score below [`SYMMETRY_TOLERANCE`].
pub fn planes_of(scores: &[f64; 3]) -> Vec<usize> {
    (0..3).filter(|&i| scores[i] < SYMMETRY_TOLERANCE).collect()
}

/// Everything table 2 says about one camera, measured at one point (m, h).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraGeometry {
    pub camera: Camera,
    pub m: f64,
    pub h: f64,
    pub tori: usize,
    /// From torus 0 (the same on every torus: checked, see `consistent`).
    pub kinds: MotionKinds,
    /// Planes every connected P-surface is symmetric to (intersection over the tori).
    pub p_planes: Vec<usize>,
    /// The same for the Π-surfaces.
    pub pi_planes: Vec<usize>,
    pub tori_symmetry: Vec<TorusSymmetry>,
    /// Whether every torus gave the same kinds and the same planes.
    pub consistent: bool,
}

/// Grid per angle used for the symmetry measurement.
pub const SYMMETRY_GRID: usize = 64;

/// Classify the motions and measure the symmetries at (a, b, m, h), over all tori.
pub fn camera_geometry(a: f64, b: f64, m: f64, h: f64) -> Result<CameraGeometry, GeometryError> {
    let meshes = all_tori(a, b, m, h, SYMMETRY_GRID, SYMMETRY_GRID)?;
    let mut kinds = Vec::new();
    let mut camera = None;
    for torus in 0..meshes.len() {
        let choice = TorusChoice {
            torus,
            ..TorusChoice::default()
        };
        let motion = ExplicitMotion::<f64>::new(a, b, m, h, choice)?;
        camera = Some(motion.camera);
        kinds.push(motion_kinds(&motion));
    }
    let camera = camera.ok_or_else(|| GeometryError::Numerical("no torus".into()))?;
    let sym = symmetries(&meshes);
    let per_torus_p: Vec<Vec<usize>> = sym.iter().map(|s| planes_of(&s.p_self_score)).collect();
    let per_torus_pi: Vec<Vec<usize>> = sym.iter().map(|s| planes_of(&s.pi_self_score)).collect();
    let inter = |v: &[Vec<usize>]| -> Vec<usize> {
        (0..3).filter(|i| v.iter().all(|p| p.contains(i))).collect()
    };
    let same_kind = kinds.iter().all(|k| {
        k.first_partial == kinds[0].first_partial
            && k.second_partial == kinds[0].second_partial
            && k.semi_moving == kinds[0].semi_moving
            && k.radicals_change_sign == kinds[0].radicals_change_sign
    });
    let consistent = same_kind
        && per_torus_p.iter().all(|p| *p == per_torus_p[0])
        && per_torus_pi.iter().all(|p| *p == per_torus_pi[0]);
    Ok(CameraGeometry {
        camera,
        m,
        h,
        tori: meshes.len(),
        kinds: kinds.swap_remove(0),
        p_planes: inter(&per_torus_p),
        pi_planes: inter(&per_torus_pi),
        tori_symmetry: sym,
        consistent,
    })
}

/// `omega1`, `omega2`, `omega3` (or the Ω names) for plane indices.
pub fn plane_names(planes: &[usize], surface: Surface) -> Vec<&'static str> {
    planes.iter().map(|&i| surface.axis_names()[i]).collect()
}
