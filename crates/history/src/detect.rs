//! Regressions from a history, per series.
//!
//! - Exact figures (errors, drifts, correct digits, observed order, steps, evaluations) are
//!   deterministic for one build and CPU path, so any change of any bit of any run of a series
//!   between two nights is a change, dated to the night (and commit) where it appeared. A series
//!   is regressed when its latest changes made it worse (larger errors or cost, fewer digits, a
//!   lower order) or changed it both ways; from the first of those changes on it is "bad".
//! - Timings are noisy: the ln of each night's least time over the series' runs (its tori; a
//!   busy machine only adds time) is fitted by steps ([`crate::steps`]);
//!   the series is regressed when its latest level, held for at least [`MIN_NIGHTS`] nights, is
//!   above an earlier level by more than [`Z`] standard errors of the fit's noise (and by more
//!   than 5 %, asv's default threshold). No fixed factor: the noise decides.

use serde::Serialize;

use crate::series::{summary, Data, Metric, Point, SeriesKey};
use crate::steps::{self, Piece};

/// The latest timing level must have held this many nights to count.
pub const MIN_NIGHTS: usize = 2;
/// Standard errors a timing step must exceed.
pub const Z: f64 = 4.0;
/// Smallest relative timing step reported (asv's default regression threshold).
pub const MIN_STEP: f64 = 0.05;

/// Which way a change went.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    Worse,
    Better,
    /// Some runs better, some worse.
    Mixed,
}

/// A change of a series from one of its nights to the next (index into its points).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Change {
    pub point: usize,
    pub direction: Direction,
    /// The run whose figure changed most (in ulps; timing: the series' first run).
    pub run_id: String,
    /// Largest change in units in the last place over the runs (exact figures only).
    pub ulps: Option<u64>,
}

/// What the analysis says of one series.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SeriesVerdict {
    /// Exact figures: every change; timings: the steps of the fit (up or down).
    pub changes: Vec<Change>,
    /// Timings: the fitted pieces (indices into the points, level in seconds).
    pub pieces: Vec<Piece>,
    /// The regression, if the series is regressed.
    pub regression: Option<Regression>,
}

/// A regressed series.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Regression {
    pub run_id: String,
    pub suite: String,
    pub case: String,
    pub method: String,
    pub tolerance: String,
    pub metric: &'static str,
    /// `accuracy` or `timing`.
    pub kind: &'static str,
    /// The environment's id in the history and its description.
    pub environment: i64,
    pub environment_text: String,
    pub first_bad_night: String,
    pub first_bad_commit: String,
    pub last_good_night: String,
    pub last_good_commit: String,
    /// The figure before and after (worst run; timing: the levels' medians in seconds).
    pub before: f64,
    pub after: f64,
    /// Exact figures: the largest change in ulps over the runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ulps: Option<u64>,
    /// Timings: the step in standard errors of the noise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// Index (into the series' points) of the first bad night.
    #[serde(skip)]
    pub point: usize,
}

/// Units in the last place between two finite doubles of one sign (or the ordered distance of
/// their bit patterns); `u64::MAX` when one is NaN.
pub fn ulps(a: f64, b: f64) -> u64 {
    if a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    let key = |x: f64| {
        let bits = x.to_bits() as i64;
        if bits < 0 {
            i64::MIN - bits
        } else {
            bits
        }
    };
    key(a).abs_diff(key(b))
}

/// The worst value of a night (max, or min for figures where larger is better; NaN wins).
fn worst(metric: Metric, p: &Point) -> f64 {
    let values: Vec<f64> = p.runs.iter().map(|r| r.1).collect();
    if values.iter().any(|v| v.is_nan()) {
        return f64::NAN;
    }
    let pick = if metric.larger_is_worse() {
        f64::max
    } else {
        f64::min
    };
    values.into_iter().reduce(pick).unwrap_or(f64::NAN)
}

/// Whether `now` is worse than `before` for this metric (NaN is worse than any number).
fn is_worse(metric: Metric, before: f64, now: f64) -> bool {
    match (before.is_nan(), now.is_nan()) {
        (false, true) => true,
        (_, false) if before.is_nan() => false,
        _ if metric.larger_is_worse() => now > before,
        _ => now < before,
    }
}

/// Changes of an exact series from night to night.
fn exact_changes(metric: Metric, points: &[Point]) -> Vec<Change> {
    let mut out = Vec::new();
    for (k, w) in points.windows(2).enumerate() {
        let (a, b) = (&w[0], &w[1]);
        let (mut worse, mut better) = (false, false);
        let mut most: Option<(u64, &str)> = None;
        for (id, now) in &b.runs {
            let Some((_, before)) = a.runs.iter().find(|r| &r.0 == id) else {
                continue;
            };
            let same = before.to_bits() == now.to_bits() || (before.is_nan() && now.is_nan());
            if same {
                continue;
            }
            if is_worse(metric, *before, *now) {
                worse = true;
            } else {
                better = true;
            }
            let u = ulps(*before, *now);
            if most.is_none_or(|m| u > m.0) {
                most = Some((u, id));
            }
        }
        if let Some((u, id)) = most {
            out.push(Change {
                point: k + 1,
                direction: match (worse, better) {
                    (true, false) => Direction::Worse,
                    (false, _) => Direction::Better,
                    _ => Direction::Mixed,
                },
                run_id: id.to_string(),
                ulps: Some(u),
            });
        }
    }
    out
}

/// Judge one series.
pub fn judge(data: &Data, key: &SeriesKey, points: &[Point]) -> SeriesVerdict {
    let make = |point: usize, good: usize, run_id: &str, before: f64, after: f64| {
        let night = |k: usize| &data.nights[points[k].night];
        Regression {
            run_id: run_id.to_string(),
            suite: key.suite.clone(),
            case: key.case.clone(),
            method: key.method.clone(),
            tolerance: key.tolerance.clone(),
            metric: key.metric.name(),
            kind: if key.metric.is_timing() {
                "timing"
            } else {
                "accuracy"
            },
            environment: key.environment,
            environment_text: data
                .environments
                .get(&key.environment)
                .map(|e| format!("{}, {} cores, SIMD {}, {}", e.cpu, e.cores, e.simd, e.os))
                .unwrap_or_default(),
            first_bad_night: night(point).night.clone(),
            first_bad_commit: night(point).commit.clone(),
            last_good_night: night(good).night.clone(),
            last_good_commit: night(good).commit.clone(),
            before,
            after,
            ulps: None,
            z: None,
            point,
        }
    };
    if !key.metric.is_timing() {
        let changes = exact_changes(key.metric, points);
        // The trailing changes that are not improvements: the first of them starts the bad run.
        let bad: Vec<&Change> = changes
            .iter()
            .rev()
            .take_while(|c| c.direction != Direction::Better)
            .collect();
        let regression = bad.last().map(|first| {
            let mut r = make(
                first.point,
                first.point - 1,
                &first.run_id,
                worst(key.metric, &points[first.point - 1]),
                worst(key.metric, &points[points.len() - 1]),
            );
            r.ulps = bad.iter().filter_map(|c| c.ulps).max();
            r
        });
        return SeriesVerdict {
            changes,
            pieces: Vec::new(),
            regression,
        };
    }
    // Timing: the last WINDOW nights with a positive, finite time.
    let start = points.len().saturating_sub(steps::WINDOW);
    let usable: Vec<(usize, f64)> = (start..points.len())
        .filter_map(|k| {
            let values: Vec<f64> = points[k].runs.iter().map(|r| r.1).collect();
            // The least time of the night's runs: a busy machine only ever adds time.
            let (_, least, _) = summary(&values);
            (least.is_finite() && least > 0.0).then(|| (k, least.ln()))
        })
        .collect();
    let y: Vec<f64> = usable.iter().map(|u| u.1).collect();
    let fitted = steps::fit(&y);
    let noise = steps::noise(&y, &fitted);
    // Pieces and changes in the series' own indices.
    let pieces: Vec<Piece> = fitted
        .iter()
        .map(|p| Piece {
            from: usable[p.from].0,
            to: usable[p.to - 1].0 + 1,
            level: p.level.exp(),
        })
        .collect();
    let first_run = |k: usize| points[k].runs.first().map_or("", |r| r.0.as_str());
    let changes: Vec<Change> = pieces
        .windows(2)
        .map(|w| Change {
            point: w[1].from,
            direction: if w[1].level > w[0].level {
                Direction::Worse
            } else {
                Direction::Better
            },
            run_id: first_run(w[1].from).to_string(),
            ulps: None,
        })
        .collect();
    let mut regression = None;
    if let Some(last) = fitted.last() {
        let n_last = (last.to - last.from) as f64;
        if last.to - last.from >= MIN_NIGHTS {
            for (j, p) in fitted.iter().enumerate().rev().skip(1) {
                // A level of one night is an outlier (a busy machine), neither a good level nor
                // one that ends the search (asv accepts short intervals only conditionally).
                if p.to - p.from < MIN_NIGHTS {
                    continue;
                }
                let se = noise * (1.0 / (p.to - p.from) as f64 + 1.0 / n_last).sqrt();
                let z = (last.level - p.level) / se;
                if z > Z && last.level - p.level > MIN_STEP.ln_1p() {
                    let first = usable[fitted[j + 1].from].0;
                    let good = usable[p.to - 1].0;
                    let mut r = make(
                        first,
                        good,
                        first_run(first),
                        p.level.exp(),
                        last.level.exp(),
                    );
                    r.z = Some(z);
                    regression = Some(r);
                    break;
                }
                if -z > Z {
                    // An earlier level clearly slower than now: nothing regressed since.
                    break;
                }
            }
        }
    }
    SeriesVerdict {
        changes,
        pieces,
        regression,
    }
}
