//! Step detection in a noisy series (timings), after airspeed velocity (asv, `asv/step_detect.py`):
//! the series is fitted by a piecewise constant function minimising the L1 (Laplace-noise)
//! Potts functional of Friedrich et al. (2008), the number of pieces chosen by asv's variant of
//! the Schwarz criterion (Yao 1988),
//!
//!   k̂ = argmin_k  β k + ln(σ₀ + S_k / n),   β = B ln n / n,
//!
//! where S_k is the least L1 distance of the data from k pieces (each at its median) and σ₀ a
//! floor that keeps a perfect fit from winning (asv's: a tenth of the smallest jump, 1e-3 for one
//! or two pieces). Unlike asv, which solves the Potts problem approximately for a range of
//! penalties, the best k-piece fit is found exactly for every k ≤ [`MAX_PIECES`] by dynamic
//! programming (the histories are short: at most [`WINDOW`] nights are looked at).

/// Nights looked at (the most recent); conbench's lookback is 100 runs too.
pub const WINDOW: usize = 100;
/// Most pieces a fit may have.
pub const MAX_PIECES: usize = 8;
/// Fewest nights in a piece (asv's `min_size`): a one-night outlier — a run slowed twenty-fold
/// by a busy machine — is absorbed by the median of its neighbours instead of making a level,
/// and the fit cannot chase the noise with many tiny pieces.
pub const MIN_PIECE: usize = 2;
/// B of the penalty β = B ln n / n. asv's default is 4; with 3 a 2× step at night 6 of ten nights
/// of ±30 % noise is found there 85 % of the time instead of 66 % (asv: 0.3 % false alarms), at 1.3 % false alarms
/// per noise-only series (0.4 % over twenty nights): docs/validation.md has the measurement.
pub const PENALTY: f64 = 3.0;

/// One piece of the fit: nights `from..to` (indices into the series) at `level`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Piece {
    pub from: usize,
    pub to: usize,
    /// The median of the piece.
    pub level: f64,
}

/// Largest distance of one night from its level that counts in the fit (ln 3: a night three times
/// slower or faster than its level counts as three times): a run descheduled on a busy machine
/// can take twenty times as long, and would otherwise weigh more than a true step of all the
/// other nights (a truncated L1 distance; the levels are medians all the same).
pub const CAP: f64 = 1.098_612_288_668_11; // ln 3

/// Medians and (truncated, [`CAP`]) L1 distances of every stretch `l..=r` of `y`.
struct Stretches {
    n: usize,
    median: Vec<f64>,
    dist: Vec<f64>,
}

impl Stretches {
    fn new(y: &[f64]) -> Self {
        let n = y.len();
        let mut median = vec![0.0; n * n];
        let mut dist = vec![0.0; n * n];
        for l in 0..n {
            let mut sorted: Vec<f64> = Vec::with_capacity(n - l);
            for r in l..n {
                let at = sorted.partition_point(|&v| v < y[r]);
                sorted.insert(at, y[r]);
                let m = sorted.len();
                let med = if m % 2 == 1 {
                    sorted[m / 2]
                } else {
                    0.5 * (sorted[m / 2 - 1] + sorted[m / 2])
                };
                median[l * n + r] = med;
                dist[l * n + r] = sorted.iter().map(|v| (v - med).abs().min(CAP)).sum();
            }
        }
        Stretches { n, median, dist }
    }
    fn median(&self, l: usize, r: usize) -> f64 {
        self.median[l * self.n + r]
    }
    fn dist(&self, l: usize, r: usize) -> f64 {
        self.dist[l * self.n + r]
    }
}

/// The best fit of `y` by pieces (finite values only; an empty `y` has none).
pub fn fit(y: &[f64]) -> Vec<Piece> {
    let n = y.len();
    if n == 0 {
        return Vec::new();
    }
    let st = Stretches::new(y);
    let kmax = MAX_PIECES.min(n / MIN_PIECE).max(1);
    // cost[k][r]: least L1 distance of y[..r] from k pieces; from[k][r]: where the last starts.
    let mut cost = vec![vec![f64::INFINITY; n + 1]; kmax + 1];
    let mut from = vec![vec![0usize; n + 1]; kmax + 1];
    cost[0][0] = 0.0;
    for k in 1..=kmax {
        for r in k..=n {
            for l in (k - 1)..r {
                // Pieces of MIN_PIECE nights or more (a single piece may be shorter).
                if r - l < MIN_PIECE && !(k == 1 && r == n) {
                    continue;
                }
                let c = cost[k - 1][l] + st.dist(l, r - 1);
                if c < cost[k][r] {
                    cost[k][r] = c;
                    from[k][r] = l;
                }
            }
        }
    }
    let beta = PENALTY * (n as f64).ln() / n as f64;
    let mut best: Option<(f64, Vec<Piece>)> = None;
    for (k, row) in cost.iter().enumerate().skip(1) {
        let total = row[n];
        if !total.is_finite() {
            continue;
        }
        let mut pieces = Vec::with_capacity(k);
        let mut r = n;
        for kk in (1..=k).rev() {
            let l = from[kk][r];
            pieces.push(Piece {
                from: l,
                to: r,
                level: st.median(l, r - 1),
            });
            r = l;
        }
        pieces.reverse();
        let floor = if k > 2 {
            0.1 * pieces
                .windows(2)
                .map(|w| (w[1].level - w[0].level).abs())
                .fold(f64::INFINITY, f64::min)
        } else {
            1e-3
        };
        let objective = beta * k as f64 + (floor.max(1e-300) + total / n as f64).ln();
        if best.as_ref().is_none_or(|(b, _)| objective < *b - 1e-12) {
            best = Some((objective, pieces));
        }
    }
    best.map(|(_, p)| p).unwrap_or_default()
}

/// The noise scale of a fit: the median absolute distance of the data from it, × 1.4826 (the
/// standard deviation for Gaussian noise; robust: a night slowed twenty-fold by a busy machine
/// does not inflate it), at least 1e-3 (a tenth of a percent in ln time).
pub fn noise(y: &[f64], pieces: &[Piece]) -> f64 {
    let mut dev: Vec<f64> = pieces
        .iter()
        .flat_map(|p| y[p.from..p.to].iter().map(move |v| (v - p.level).abs()))
        .collect();
    if dev.is_empty() {
        return 1e-3;
    }
    dev.sort_by(f64::total_cmp);
    let m = dev.len();
    let mad = if m % 2 == 1 {
        dev[m / 2]
    } else {
        0.5 * (dev[m / 2 - 1] + dev[m / 2])
    };
    (1.4826 * mad).max(1e-3)
}
