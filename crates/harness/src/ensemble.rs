//! Ensembles of motions (`rsts bench --ensemble N`, issue 18): N motions drawn from the cameras
//! asked — a point (m, h) well inside the camera, a torus and two phases — reproducible from a
//! seed, each measured exactly as `rsts compare … --pieces 1` runs it
//! ([`crate::bench::bench_ensemble`]), and per method and tolerance the median and the 5–95 %
//! band of the error and of the time over the motions ([`bands`], [`percentile`]).
//!
//! Drawing (docs/benchmarks.md): motion k belongs to camera `cameras[k mod len]`. The window
//! of the bifurcation diagram ([`default_window`]) is cut into a [`RASTER`] × [`RASTER`] grid of
//! cells; a cell is *inside* a camera when its centre and the centres of its eight neighbours
//! all lie in that camera (so the points drawn keep about a cell's width from Σ). A motion takes
//! a uniformly random inside cell of its camera, a uniform point in that cell, rounded to six
//! significant digits (rechecked), a uniform torus among the camera's tori and phases uniform in
//! [0, 2π) rounded to 1e-4. The random numbers come from SplitMix64 (a fixed, documented
//! generator, so a seed gives the same motions on every machine and rsts version).

use rsts_closed_form::diagram::{camera_at, default_window, Window};
use rsts_closed_form::{Camera, ExplicitMotion, TorusChoice};
use serde::{Deserialize, Serialize};

use crate::bench::BenchRow;
use crate::case::Case;

/// Most motions of an ensemble.
pub const MAX_MOTIONS: usize = 1000;
/// The seed used when none is given.
pub const DEFAULT_SEED: u64 = 2013;
/// Cells per side of the raster of the diagram's window the points are drawn from.
pub const RASTER: usize = 200;
/// Finer rasters tried for a camera too thin for the first.
pub const ZOOMS: usize = 3;

/// Why an ensemble cannot be drawn; [`EnsembleError::parameters`] names the settings concerned.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EnsembleError {
    #[error("{0}")]
    Count(String),
    #[error("{0}")]
    Cameras(String),
    #[error("{0}")]
    Fields(String),
}

impl EnsembleError {
    /// The settings the error concerns (options of `rsts bench` without their dashes).
    pub fn parameters(&self) -> &'static [&'static str] {
        match self {
            EnsembleError::Count(_) => &["ensemble"],
            EnsembleError::Cameras(_) => &["cameras"],
            EnsembleError::Fields(_) => &["a", "b"],
        }
    }
}

/// One motion of an ensemble: where it is on N.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnsembleMotion {
    pub m: f64,
    pub h: f64,
    pub torus: usize,
    pub phase1: f64,
    pub phase2: f64,
    /// The camera of (m, h), labelled as in Table 1 ("I+", "V", …).
    pub camera: String,
}

/// The motions of an ensemble and the seed they were drawn from (`ensemble` in the JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ensemble {
    pub n: usize,
    pub seed: u64,
    pub motions: Vec<EnsembleMotion>,
}

impl Ensemble {
    /// The case of motion `k`: `base` (a, b, T, samples) at the motion's point, torus and phases.
    pub fn case(&self, base: &Case, k: usize) -> Case {
        let mo = &self.motions[k];
        // The motion the report prints: each drawn number is the decimal of its shortest
        // text, as JSON shows it, so `--m 0.123…` of a printed motion is the motion measured.
        let exact =
            |x: f64| rsts_closed_form::Decimal::shortest(x).expect("a drawn motion is finite");
        let motion = rsts_closed_form::Motion {
            m: exact(mo.m),
            h: exact(mo.h),
            ..base
                .motion
                .on_torus(mo.torus, [exact(mo.phase1), exact(mo.phase2)])
        };
        Case::new(motion, base.t_end.clone(), base.samples)
    }
}

/// Per method and tolerance, the spread over the motions (`bands` in the JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Band {
    pub method: String,
    pub tolerance: f64,
    /// Motions measured (the rows of this method and tolerance).
    pub motions: usize,
    pub error_p05: f64,
    pub error_median: f64,
    pub error_p95: f64,
    /// Percentiles of the rows' times (each the median of its repeats).
    pub time_p05: f64,
    pub time_median: f64,
    pub time_p95: f64,
}

/// SplitMix64 (Steele, Lea & Flood 2014): the generator of the ensembles, fixed here so a seed
/// draws the same motions everywhere.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1): the top 53 bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in 0..n (n ≥ 1).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }
}

/// `x` rounded to `digits` significant digits.
fn round_sig(x: f64, digits: usize) -> f64 {
    format!("{x:.*e}", digits - 1).parse().unwrap_or(x)
}

/// The cells inside one camera: their centres and the cell size (dm, dh).
#[derive(Clone, Debug, Default)]
struct Cells {
    centres: Vec<(f64, f64)>,
    size: (f64, f64),
}

/// The camera at the centre of each cell of a [`RASTER`]² grid over `window`, row by row.
fn raster(a: f64, b: f64, window: Window) -> Vec<Option<Camera>> {
    let ((m_lo, m_hi), (h_lo, h_hi)) = window;
    let (dm, dh) = ((m_hi - m_lo) / RASTER as f64, (h_hi - h_lo) / RASTER as f64);
    (0..RASTER * RASTER)
        .map(|k| {
            let (i, j) = (k % RASTER, k / RASTER);
            camera_at(
                a,
                b,
                m_lo + (i as f64 + 0.5) * dm,
                h_lo + (j as f64 + 0.5) * dh,
            )
        })
        .collect()
}

/// The cells of `grid` (over `window`) inside `camera`, and the window around all cells whose
/// centre is in it (`None`: no cell is).
fn inside(grid: &[Option<Camera>], window: Window, camera: Camera) -> (Cells, Option<Window>) {
    let ((m_lo, m_hi), (h_lo, h_hi)) = window;
    let (dm, dh) = ((m_hi - m_lo) / RASTER as f64, (h_hi - h_lo) / RASTER as f64);
    let at = |i: usize, j: usize| grid[j * RASTER + i] == Some(camera);
    let mut cells = Cells {
        centres: Vec::new(),
        size: (dm, dh),
    };
    let (mut lo, mut hi) = ((usize::MAX, usize::MAX), (0, 0));
    for j in 0..RASTER {
        for i in 0..RASTER {
            if !at(i, j) {
                continue;
            }
            (lo, hi) = ((lo.0.min(i), lo.1.min(j)), (hi.0.max(i), hi.1.max(j)));
            let interior = (1..RASTER - 1).contains(&i) && (1..RASTER - 1).contains(&j);
            if interior && (j - 1..=j + 1).all(|jj| (i - 1..=i + 1).all(|ii| at(ii, jj))) {
                let c = (m_lo + (i as f64 + 0.5) * dm, h_lo + (j as f64 + 0.5) * dh);
                cells.centres.push(c);
            }
        }
    }
    let bounds = (lo.0 != usize::MAX).then_some({
        (
            (
                m_lo + (lo.0 as f64 - 1.0) * dm,
                m_lo + (hi.0 as f64 + 2.0) * dm,
            ),
            (
                h_lo + (lo.1 as f64 - 1.0) * dh,
                h_lo + (hi.1 as f64 + 2.0) * dh,
            ),
        )
    });
    (cells, bounds)
}

/// The cells inside each of `cameras` (see the module doc); a camera too thin for any cell of
/// the diagram's window to be inside it is looked for again in a raster of the box around it,
/// up to [`ZOOMS`] times.
fn inside_cells(a: f64, b: f64, cameras: &[Camera]) -> Result<Vec<Cells>, EnsembleError> {
    let window = default_window(a, b).map_err(|e| EnsembleError::Fields(e.to_string()))?;
    let grid = raster(a, b, window);
    Ok(cameras
        .iter()
        .map(|&c| {
            let (mut cells, mut bounds) = inside(&grid, window, c);
            for _ in 0..ZOOMS {
                match bounds {
                    Some(w) if cells.centres.is_empty() => {
                        (cells, bounds) = inside(&raster(a, b, w), w, c);
                    }
                    _ => break,
                }
            }
            cells
        })
        .collect())
}

/// Draw `n` motions for the fields a > b > 0 from `cameras` (each camera once; empty: all nine)
/// with `seed` (see the module doc). Errors: n = 0 or above [`MAX_MOTIONS`], a camera repeated,
/// a camera with no point inside the window for these a, b, fields that have no diagram.
pub fn draw_ensemble(
    a: f64,
    b: f64,
    cameras: &[Camera],
    n: usize,
    seed: u64,
) -> Result<Ensemble, EnsembleError> {
    if n == 0 || n > MAX_MOTIONS {
        return Err(EnsembleError::Count(format!(
            "an ensemble has 1 to {MAX_MOTIONS} motions, got {n}"
        )));
    }
    let cameras: Vec<Camera> = if cameras.is_empty() {
        Camera::ALL.to_vec()
    } else {
        cameras.to_vec()
    };
    for (k, c) in cameras.iter().enumerate() {
        if cameras[..k].contains(c) {
            return Err(EnsembleError::Cameras(format!("camera {c} is given twice")));
        }
    }
    let cells = inside_cells(a, b, &cameras)?;
    let empty: Vec<String> = cameras
        .iter()
        .zip(&cells)
        .filter(|(_, c)| c.centres.is_empty())
        .map(|(c, _)| c.to_string())
        .collect();
    if !empty.is_empty() {
        return Err(EnsembleError::Cameras(format!(
            "no admissible point well inside camera {} for a = {a}, b = {b} (looked for in rasters \
             of {RASTER}² cells over the diagram's window, then around each camera; `rsts diagram` \
             shows the cameras)",
            empty.join(", ")
        )));
    }
    let mut rng = SplitMix64::new(seed);
    let mut motions = Vec::with_capacity(n);
    for k in 0..n {
        let camera = cameras[k % cameras.len()];
        let Cells {
            centres,
            size: (dm, dh),
        } = &cells[k % cameras.len()];
        let mut drawn = None;
        for _ in 0..1000 {
            let (mc, hc) = centres[rng.below(centres.len())];
            let m = round_sig(mc + (rng.uniform() - 0.5) * dm, 6);
            let h = round_sig(hc + (rng.uniform() - 0.5) * dh, 6);
            if camera_at(a, b, m, h) != Some(camera) {
                continue;
            }
            if let Ok(motion) = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default()) {
                drawn = Some((m, h, motion.tori));
                break;
            }
        }
        let (m, h, tori) = drawn.ok_or_else(|| {
            EnsembleError::Cameras(format!(
                "no admissible point of camera {camera} found for a = {a}, b = {b}"
            ))
        })?;
        let torus = rng.below(tori.max(1));
        let phase = |u: f64| (u * std::f64::consts::TAU * 1e4).floor() / 1e4;
        let phase1 = phase(rng.uniform());
        let phase2 = phase(rng.uniform());
        motions.push(EnsembleMotion {
            m,
            h,
            torus,
            phase1,
            phase2,
            camera: camera.to_string(),
        });
    }
    Ok(Ensemble { n, seed, motions })
}

/// The p-th percentile (0 ≤ p ≤ 1) of `values` by linear interpolation between closest ranks
/// (Hyndman & Fan type 7, numpy's default): sorted x₀ ≤ … ≤ x_{n−1}, r = p·(n − 1),
/// x_⌊r⌋ + (r − ⌊r⌋)·(x_⌊r⌋₊₁ − x_⌊r⌋). NaN for an empty list.
pub fn percentile(values: &[f64], p: f64) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    let r = p.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let lo = r.floor() as usize;
    let hi = (lo + 1).min(v.len() - 1);
    v[lo] + (r - lo as f64) * (v[hi] - v[lo])
}

/// The bands of `rows`: one per method and tolerance, in the order they first appear.
pub fn bands(rows: &[BenchRow]) -> Vec<Band> {
    let mut keys: Vec<(String, u64)> = Vec::new();
    for r in rows {
        let key = (r.method.clone(), r.tolerance.to_bits());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(method, tol)| {
            let of: Vec<&BenchRow> = rows
                .iter()
                .filter(|r| r.method == method && r.tolerance.to_bits() == tol)
                .collect();
            let errors: Vec<f64> = of.iter().map(|r| r.max_error).collect();
            let times: Vec<f64> = of.iter().map(|r| r.integration_seconds).collect();
            Band {
                method,
                tolerance: f64::from_bits(tol),
                motions: of.len(),
                error_p05: percentile(&errors, 0.05),
                error_median: percentile(&errors, 0.5),
                error_p95: percentile(&errors, 0.95),
                time_p05: percentile(&times, 0.05),
                time_median: percentile(&times, 0.5),
                time_p95: percentile(&times, 0.95),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-checked: sorted [1, 2, 3, 4, 10], r = 0.05·4 = 0.2 → 1.2; r = 2 → 3; r = 3.8 →
    /// 4 + 0.8·6 = 8.8. Even count [1, 2, 3, 4]: median 2.5.
    #[test]
    fn percentiles_interpolate_linearly_between_ranks() {
        let v = [10.0, 3.0, 1.0, 4.0, 2.0];
        assert!((percentile(&v, 0.05) - 1.2).abs() < 1e-15);
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert!((percentile(&v, 0.95) - 8.8).abs() < 1e-14);
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 10.0);
        assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0], 0.5), 2.5);
        assert_eq!(percentile(&[7.0], 0.95), 7.0);
        assert!(percentile(&[], 0.5).is_nan());
    }

    /// The first outputs of SplitMix64 for seed 0 (the reference values of its authors' C code).
    #[test]
    fn splitmix_matches_its_reference_outputs() {
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
    }
}
