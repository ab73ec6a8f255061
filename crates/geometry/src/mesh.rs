//! Meshes of the bearing surfaces: a uniform grid in the angle coordinates (ψ₁, ψ₂) of one
//! Liouville torus, mapped by the closed form to ω (the P-surface, body frame) and to Ω = Qω (the
//! Π-surface, fixed frame). The grid wraps around in both angles, so the triangles close the
//! torus; the image may fold and self-intersect (it is the image of a torus, not an embedding).

use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};

use crate::GeometryError;

/// The two bearing surfaces of one torus on the same (ψ₁, ψ₂) grid.
#[derive(Clone, Debug)]
pub struct TorusMesh {
    /// The torus (0..tori).
    pub torus: usize,
    /// Grid size along ψ₁ and ψ₂.
    pub n1: usize,
    pub n2: usize,
    /// (ψ₁, ψ₂) of each vertex; vertex (i, j) has index i·n2 + j and ψ = 2π(i/n1, j/n2).
    pub angles: Vec<[f64; 2]>,
    /// P-surface vertices: ω at each (ψ₁, ψ₂).
    pub omega: Vec<[f64; 3]>,
    /// Π-surface vertices: Ω = Qω at each (ψ₁, ψ₂).
    pub omega_fixed: Vec<[f64; 3]>,
    /// Triangles (vertex indices, shared by both surfaces), two per grid cell, wrapping around.
    pub triangles: Vec<[u32; 3]>,
}

/// Smallest and largest grid accepted (per angle).
pub const MIN_GRID: usize = 4;
pub const MAX_GRID: usize = 1024;

/// The angle of grid index `i` of `n`.
pub fn grid_angle(i: usize, n: usize) -> f64 {
    std::f64::consts::TAU * i as f64 / n as f64
}

/// Triangles of an n1 × n2 grid wrapping around in both directions.
pub fn torus_triangles(n1: usize, n2: usize) -> Vec<[u32; 3]> {
    let idx = |i: usize, j: usize| ((i % n1) * n2 + (j % n2)) as u32;
    let mut t = Vec::with_capacity(2 * n1 * n2);
    for i in 0..n1 {
        for j in 0..n2 {
            t.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            t.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    t
}

fn vec3(v: &[f64; 3]) -> [f64; 3] {
    *v
}

impl TorusMesh {
    /// Evaluate the closed form on the n1 × n2 grid of the motion's torus.
    pub fn new(motion: &ExplicitMotion<f64>, n1: usize, n2: usize) -> Result<Self, GeometryError> {
        for n in [n1, n2] {
            if !(MIN_GRID..=MAX_GRID).contains(&n) {
                return Err(GeometryError::Input(format!(
                    "grid size {n} outside {MIN_GRID}..={MAX_GRID}"
                )));
            }
        }
        let mut angles = Vec::with_capacity(n1 * n2);
        let mut omega = Vec::with_capacity(n1 * n2);
        let mut omega_fixed = Vec::with_capacity(n1 * n2);
        for i in 0..n1 {
            for j in 0..n2 {
                let (p1, p2) = (grid_angle(i, n1), grid_angle(j, n2));
                let s: ExplicitState<f64> = motion.at_angles(&p1, &p2);
                if !s.omega.iter().chain(&s.omega_fixed).all(|x| x.is_finite()) {
                    return Err(GeometryError::Numerical(format!(
                        "non-finite state at (ψ1, ψ2) = ({p1}, {p2})"
                    )));
                }
                angles.push([p1, p2]);
                omega.push(vec3(&s.omega));
                omega_fixed.push(vec3(&s.omega_fixed));
            }
        }
        Ok(Self {
            torus: motion.choice.torus,
            n1,
            n2,
            angles,
            omega,
            omega_fixed,
            triangles: torus_triangles(n1, n2),
        })
    }

    /// The vertices of one surface.
    pub fn vertices(&self, surface: Surface) -> &[[f64; 3]] {
        match surface {
            Surface::P => &self.omega,
            Surface::Pi => &self.omega_fixed,
        }
    }
}

/// Which bearing surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Surface {
    /// P-surface: ω in the body frame (P-space).
    P,
    /// Π-surface: Ω = Qω in the fixed frame (Π-space).
    Pi,
}

impl Surface {
    pub const BOTH: [Surface; 2] = [Surface::P, Surface::Pi];

    /// Short name used in file names: `p` or `pi`.
    pub fn file_stem(&self) -> &'static str {
        match self {
            Surface::P => "p",
            Surface::Pi => "pi",
        }
    }

    /// Human name.
    pub fn title(&self) -> &'static str {
        match self {
            Surface::P => "P-surface (ω, body frame)",
            Surface::Pi => "Π-surface (Ω, fixed frame)",
        }
    }

    /// Names of the coordinates.
    pub fn axis_names(&self) -> [&'static str; 3] {
        match self {
            Surface::P => ["omega1", "omega2", "omega3"],
            Surface::Pi => ["Omega1", "Omega2", "Omega3"],
        }
    }
}

/// The meshes of every torus of the integral manifold through (a, b, m, h).
pub fn all_tori(
    a: f64,
    b: f64,
    m: f64,
    h: f64,
    n1: usize,
    n2: usize,
) -> Result<Vec<TorusMesh>, GeometryError> {
    let first = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())?;
    let mut out = Vec::with_capacity(first.tori);
    for torus in 0..first.tori {
        let motion = ExplicitMotion::<f64>::new(
            a,
            b,
            m,
            h,
            TorusChoice {
                torus,
                ..TorusChoice::default()
            },
        )?;
        out.push(TorusMesh::new(&motion, n1, n2)?);
    }
    Ok(out)
}

fn sub(p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
}

fn cross(p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    [
        p[1] * q[2] - p[2] * q[1],
        p[2] * q[0] - p[0] * q[2],
        p[0] * q[1] - p[1] * q[0],
    ]
}

pub(crate) fn norm(p: [f64; 3]) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

/// Unit normal of a triangle (zero for a degenerate one).
pub fn triangle_normal(v: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [p, q, r] = t.map(|i| v[i as usize]);
    unit(cross(sub(q, p), sub(r, p)))
}

/// `n / |n|`, or zero for a zero or non-finite vector.
pub fn unit(n: [f64; 3]) -> [f64; 3] {
    let l = norm(n);
    if l > 0.0 && l.is_finite() {
        n.map(|x| x / l)
    } else {
        [0.0; 3]
    }
}

/// Area-weighted vertex normals (unit, or zero where every incident triangle is degenerate).
pub fn vertex_normals(v: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut acc = vec![[0.0f64; 3]; v.len()];
    for t in triangles {
        let [p, q, r] = t.map(|i| v[i as usize]);
        let n = cross(sub(q, p), sub(r, p));
        for &i in t {
            for k in 0..3 {
                acc[i as usize][k] += n[k];
            }
        }
    }
    acc.into_iter().map(unit).collect()
}

/// For each vertex the longest incident edge: the local mesh spacing.
pub fn local_spacing(v: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<f64> {
    let mut s = vec![0.0f64; v.len()];
    for t in triangles {
        for k in 0..3 {
            let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
            let d = norm(sub(v[i], v[j]));
            s[i] = s[i].max(d);
            s[j] = s[j].max(d);
        }
    }
    s
}

/// Axis-aligned bounding box (min, max).
pub fn bounds(v: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in v {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// A stretch of the motion: times, ω (moving hodograph), Ω (fixed hodograph) and Q.
#[derive(Clone, Debug)]
pub struct Hodograph {
    pub t: Vec<f64>,
    pub omega: Vec<[f64; 3]>,
    pub omega_fixed: Vec<[f64; 3]>,
    pub q: Vec<[[f64; 3]; 3]>,
}

/// `samples` states of the motion at equal steps over [0, t_end].
pub fn hodograph(
    motion: &ExplicitMotion<f64>,
    t_end: f64,
    samples: usize,
) -> Result<Hodograph, GeometryError> {
    if !(t_end.is_finite() && t_end > 0.0) {
        return Err(GeometryError::Input(format!(
            "t_end must be > 0, got {t_end}"
        )));
    }
    if !(2..=1_000_000).contains(&samples) {
        return Err(GeometryError::Input(format!(
            "samples must be in 2..=1000000, got {samples}"
        )));
    }
    let mut out = Hodograph {
        t: Vec::with_capacity(samples),
        omega: Vec::with_capacity(samples),
        omega_fixed: Vec::with_capacity(samples),
        q: Vec::with_capacity(samples),
    };
    for i in 0..samples {
        let t = t_end * i as f64 / (samples - 1) as f64;
        let s = motion.at(&t);
        out.t.push(t);
        out.omega.push(s.omega);
        out.omega_fixed.push(s.omega_fixed);
        out.q.push(s.orientation());
    }
    Ok(out)
}
