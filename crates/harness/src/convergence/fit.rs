//! The fit of an observed order (docs/convergence.md, "The window, the regimes and the floor"):
//! the runs of agreeing local slopes (regimes, each with its fitted order), the floor below
//! them judged against the round-off the method's precision allows, and why every other step
//! is left out.

use serde::{Deserialize, Serialize};

/// The round-off a fixed-step method accumulates: unit round-off u = 2^−bits, a state of size
/// |x| (the largest |component| along the motion), n steps. Rounding errors that cancel give
/// u·|x|·√n (a random walk), errors that add up u·|x|·n; [`RoundOff::expected`] is the upper
/// end, and an error floor is round-off when it lies within [`ROUND_OFF_MARGIN`] of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundOff {
    /// Bits of the method's scalar (53 for f64, 106 for double-double).
    pub bits: u32,
    /// |x|: the largest |component| of the state along the motion.
    pub size: f64,
}

impl RoundOff {
    /// u = 2^−bits.
    pub fn unit(&self) -> f64 {
        2f64.powi(-(self.bits.min(2000) as i32))
    }

    /// u·|x|·n: the most round-off n steps can hold.
    pub fn expected(&self, steps: f64) -> f64 {
        self.unit() * self.size * steps.max(1.0)
    }

    /// u·|x|·√n: the round-off of n steps whose rounding errors cancel.
    pub fn cancelling(&self, steps: f64) -> f64 {
        self.unit() * self.size * steps.max(1.0).sqrt()
    }
}

/// A floor is round-off when its error is at most this times the expected round-off u·|x|·n
/// (the constants of a method: stages, the nine components, a phase error that grows with t).
pub const ROUND_OFF_MARGIN: f64 = 2.0;

/// A regime below noise must fall this many times below every error above it.
pub const NOISE_DECADE: f64 = 10.0;

/// Smallest median slope of a window: the error must fall with the step.
pub const MIN_WINDOW_SLOPE: f64 = 0.5;

/// How far a local slope may lie from the window's median m: max(0.15, 0.05·|m|).
pub fn slope_tolerance(m: f64) -> f64 {
    (0.05 * m.abs()).max(0.15)
}

/// One run of agreeing local slopes and the order fitted over it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Regime {
    /// Least-squares slope of log10(max_error) against log10(step) over the window.
    pub order: f64,
    /// Its standard error (n − 2 degrees of freedom).
    pub order_stderr: f64,
    /// The smallest and largest step of the window.
    pub window: [f64; 2],
    /// log10(C) of the fitted line (drawn in diagrams; not in the JSON).
    #[serde(skip)]
    pub log10_constant: f64,
}

/// Is an error floor what rounding explains?
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FloorKind {
    /// Within [`ROUND_OFF_MARGIN`] of the expected round-off.
    #[serde(rename = "round-off")]
    RoundOff,
    /// Far above it: a solver tolerance, an inconsistent coefficient, …
    #[serde(rename = "above round-off")]
    AboveRoundOff,
}

impl FloorKind {
    pub fn as_str(&self) -> &'static str {
        match self {
            FloorKind::RoundOff => "round-off",
            FloorKind::AboveRoundOff => "above round-off",
        }
    }
}

/// Where the error stops falling below the smallest regime: of the steps there, the one
/// farthest above the round-off expected at it — its error and that round-off. The floor is
/// round-off when every step there is within [`ROUND_OFF_MARGIN`] of its expected round-off.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Floor {
    pub error: f64,
    /// u·|x|·n at that step ([`RoundOff::expected`]).
    pub expected_round_off: f64,
    pub kind: FloorKind,
}

/// Why a step is not in a regime.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ExcludedKind {
    /// Its error is not a positive finite number.
    #[serde(rename = "no error")]
    NoError,
    /// Above the regimes: the higher-order terms are not yet small.
    #[serde(rename = "pre-asymptotic")]
    PreAsymptotic,
    /// Between two regimes.
    #[serde(rename = "between regimes")]
    Between,
    /// Below the regimes, at the round-off level.
    #[serde(rename = "round-off floor")]
    RoundOffFloor,
    /// Below the regimes, the error stops falling far above round-off.
    #[serde(rename = "floor above round-off")]
    FloorAboveRoundOff,
    /// The error grows as the step halves (or falls as it grows): noise.
    #[serde(rename = "noise")]
    Noise,
    /// Below the regimes, still falling but on no window.
    #[serde(rename = "off the line")]
    OffTheLine,
}

impl ExcludedKind {
    /// The name in the JSON.
    pub fn as_str(&self) -> &'static str {
        match self {
            ExcludedKind::NoError => "no error",
            ExcludedKind::PreAsymptotic => "pre-asymptotic",
            ExcludedKind::Between => "between regimes",
            ExcludedKind::RoundOffFloor => "round-off floor",
            ExcludedKind::FloorAboveRoundOff => "floor above round-off",
            ExcludedKind::Noise => "noise",
            ExcludedKind::OffTheLine => "off the line",
        }
    }
}

/// A step left out of a fit, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Excluded {
    pub step: f64,
    pub kind: ExcludedKind,
    pub why: String,
}

/// The observed order of one method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrderFit {
    pub method: String,
    /// The asymptotic order: that of the regime of the smallest steps.
    pub order: f64,
    /// Its standard error (from the residuals; n − 2 degrees of freedom).
    pub order_stderr: f64,
    /// The smallest and largest step of that regime.
    pub window: [f64; 2],
    /// log10(C) of its fitted line (drawn in diagrams; not in the JSON).
    #[serde(skip)]
    pub log10_constant: f64,
    /// Every regime, from the largest steps to the smallest (the last is the asymptotic one).
    pub regimes: Vec<Regime>,
    /// Two regimes of different order separated by a floor or noise: which one is asymptotic
    /// cannot be told.
    pub competing: bool,
    /// The floor below the regimes (`None`: the error still falls at the smallest step).
    pub floor: Option<Floor>,
    pub excluded: Vec<Excluded>,
}

/// A value with two significant digits, as many decimals as that takes (`0.0051`, `0.086`,
/// `1.2`, `12`).
pub fn two_digits(x: f64) -> String {
    format!("{x:.*}", decimals_for(x))
}

/// Decimals that show `x` to two significant digits (0 for x ≥ 10 or not finite and positive).
fn decimals_for(x: f64) -> usize {
    if !(x.is_finite() && x > 0.0) {
        return 2;
    }
    (1 - x.log10().floor() as i64).clamp(0, 17) as usize
}

/// `4.0240 ± 0.0051`: an order to the decimal of its uncertainty shown with two significant
/// digits.
pub fn order_with_error(order: f64, stderr: f64) -> String {
    let d = decimals_for(stderr);
    format!("{order:.d$} ± {}", two_digits(stderr))
}

impl OrderFit {
    /// What `--strict` (and the suite threshold `floor = "round-off"`) fails on: a floor above
    /// round-off, competing windows.
    pub fn doubts(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(f) = &self.floor {
            if f.kind == FloorKind::AboveRoundOff {
                out.push(format!(
                    "{}: the error floor {:.2e} is above round-off (expected at most {:.2e})",
                    self.method, f.error, f.expected_round_off
                ));
            }
        }
        if self.competing {
            out.push(format!(
                "{}: windows of different order compete ({})",
                self.method,
                self.regimes
                    .iter()
                    .map(|r| format!("order {:.2}", r.order))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        out
    }

    /// The fit in words (table and diagram): the regimes, their relation, the floor.
    pub fn describe(&self) -> String {
        let mut s = String::new();
        let span = |r: &Regime| format!("steps {:.3e} to {:.3e}", r.window[0], r.window[1]);
        match self.regimes.as_slice() {
            [] => {}
            [one] => s.push_str(&format!(
                "observed order {} over {}",
                order_with_error(one.order, one.order_stderr),
                span(one)
            )),
            many => {
                if self.competing {
                    s.push_str("windows of different order compete, separated by a floor or noise (which one is asymptotic cannot be told): ");
                    let parts: Vec<String> = many
                        .iter()
                        .map(|r| {
                            format!(
                                "order {} over {}",
                                order_with_error(r.order, r.order_stderr),
                                span(r)
                            )
                        })
                        .collect();
                    s.push_str(&parts.join("; "));
                } else {
                    let mut parts = Vec::new();
                    for (k, r) in many.iter().enumerate() {
                        let o = order_with_error(r.order, r.order_stderr);
                        if k + 1 < many.len() {
                            parts.push(format!("order {o} down to h = {:.3e}", r.window[0]));
                        } else {
                            parts.push(format!(
                                "then order {o} over {} (the asymptotic order)",
                                span(r)
                            ));
                        }
                    }
                    s.push_str(&parts.join(", "));
                    let (first, last) = (&many[0], &many[many.len() - 1]);
                    if last.order < first.order {
                        s.push_str(": a lower order at smaller steps, an order condition nearly satisfied (a coefficient slightly off)");
                    }
                }
            }
        }
        match &self.floor {
            None => s.push_str("; no floor: the error still falls at the smallest step"),
            Some(f) => s.push_str(&format!(
                "; floor {:.2e}, {} (round-off expected there at most {:.2e})",
                f.error,
                f.kind.as_str(),
                f.expected_round_off
            )),
        }
        s
    }
}

/// One measured step.
#[derive(Clone, Copy, Debug)]
struct Point {
    h: f64,
    e: f64,
    /// Expected round-off at this step.
    r: f64,
}

impl Point {
    fn at_round_off(&self) -> bool {
        self.e <= ROUND_OFF_MARGIN * self.r
    }
}

fn median(v: &[f64]) -> f64 {
    crate::bench::median(v)
}

/// The median of `slopes` when they form a window (at least 2, median ≥
/// [`MIN_WINDOW_SLOPE`], each within [`slope_tolerance`] of it).
fn agreeing(slopes: &[f64]) -> Option<f64> {
    if slopes.len() < 2 {
        return None;
    }
    let m = median(slopes);
    (m >= MIN_WINDOW_SLOPE && slopes.iter().all(|s| (s - m).abs() <= slope_tolerance(m)))
        .then_some(m)
}

/// Windows as slope ranges [i, j) (points i..=j): the longest run of agreeing slopes (ties: the
/// smaller steps), then the longest in what is left on either side, and so on.
fn windows(slopes: &[f64]) -> Vec<(usize, usize, f64)> {
    let mut found = Vec::new();
    let mut free = vec![(0usize, slopes.len())];
    loop {
        let mut best: Option<(usize, usize, f64)> = None;
        for &(lo, hi) in &free {
            for i in lo..hi {
                for j in (i + 2)..=hi {
                    let Some(m) = agreeing(&slopes[i..j]) else {
                        continue;
                    };
                    if best.is_none_or(|(bi, bj, _)| j - i > bj - bi) {
                        best = Some((i, j, m));
                    }
                }
            }
        }
        let Some((i, j, m)) = best else {
            return found;
        };
        found.push((i, j, m));
        free = free
            .into_iter()
            .flat_map(|(lo, hi)| {
                if lo <= i && j <= hi {
                    vec![(lo, i), (j, hi)]
                } else {
                    vec![(lo, hi)]
                }
            })
            .filter(|(lo, hi)| hi > lo)
            .collect();
    }
}

/// The order of error ≈ C·hᵖ (docs/convergence.md): `steps`, their `errors` and the round-off
/// expected at each ([`RoundOff::expected`]); `method` of the answer is empty. Errors: fewer
/// than 3 usable points, no window of 3 steps above round-off.
pub fn fit_order(steps: &[f64], errors: &[f64], round_off: &[f64]) -> Result<OrderFit, String> {
    let mut excluded = Vec::new();
    let mut pts: Vec<Point> = Vec::new();
    for ((&h, &e), &r) in steps.iter().zip(errors).zip(round_off) {
        if e.is_finite() && e > 0.0 {
            pts.push(Point { h, e, r });
        } else {
            excluded.push(Excluded {
                step: h,
                kind: ExcludedKind::NoError,
                why: format!("error {e} is not positive and finite: nothing to fit"),
            });
        }
    }
    pts.sort_by(|a, b| a.h.total_cmp(&b.h));
    if pts.len() < 3 {
        return Err(format!(
            "an order needs at least 3 steps with a positive finite error, got {} (no order \
             is fitted on fewer)",
            pts.len()
        ));
    }
    let log: Vec<(f64, f64)> = pts.iter().map(|p| (p.h.log10(), p.e.log10())).collect();
    let slopes: Vec<f64> = log
        .windows(2)
        .map(|w| (w[1].1 - w[0].1) / (w[1].0 - w[0].0))
        .collect();
    // Regimes: windows with a point above round-off, from the largest steps down.
    let mut found: Vec<(usize, usize, f64)> = windows(&slopes)
        .into_iter()
        .filter(|&(i, j, _)| (i..=j).any(|k| !pts[k].at_round_off()))
        .collect();
    found.sort_by_key(|w| std::cmp::Reverse(w.0));
    // A window below a step where the error grew as the step halved is a regime only when it
    // falls a decade below every error above it; otherwise it is a run inside the noise.
    let mut kept: Vec<(usize, usize, f64)> = Vec::new();
    for w in found {
        if let Some(prev) = kept.last() {
            let noisy = slopes[w.1..prev.0].iter().any(|&s| s <= -MIN_WINDOW_SLOPE);
            let above = pts[w.1 + 1..]
                .iter()
                .map(|p| p.e)
                .fold(f64::INFINITY, f64::min);
            let lowest = pts[w.0..=w.1]
                .iter()
                .map(|p| p.e)
                .fold(f64::INFINITY, f64::min);
            if noisy && lowest * NOISE_DECADE >= above {
                continue;
            }
        }
        kept.push(w);
    }
    let found = kept;
    if found.is_empty() {
        let shown: Vec<String> = slopes.iter().map(|s| format!("{s:.2}")).collect();
        return Err(format!(
            "no asymptotic window: no 3 neighbouring steps above round-off whose local slopes \
             agree, so no order is fitted (slopes from the smallest step up: {}); add steps \
             between the floor and the pre-asymptotic range",
            shown.join(", ")
        ));
    }
    let regimes: Vec<Regime> = found
        .iter()
        .map(|&(i, j, _)| {
            let (order, order_stderr, log10_constant) = least_squares(&log[i..=j]);
            Regime {
                order,
                order_stderr,
                window: [pts[i].h, pts[j].h],
                log10_constant,
            }
        })
        .collect();
    // Neighbouring regimes of different order with a floor or noise between them compete.
    let competing = found.windows(2).zip(regimes.windows(2)).any(|(w, r)| {
        let (upper, lower) = (w[0], w[1]);
        let gap = &slopes[lower.1..upper.0];
        let (p, q) = (r[0].order, r[1].order);
        gap.iter().any(|&s| s < MIN_WINDOW_SLOPE) && (p - q).abs() > slope_tolerance(p.max(q))
    });
    let in_window = |k: usize| found.iter().any(|&(i, j, _)| (i..=j).contains(&k));
    let (top, top_m) = (found[0].1, found[0].2);
    let (bottom, bottom_m) = (found[found.len() - 1].0, found[found.len() - 1].2);
    // Below the regimes, the largest step where the error grows as the step halves (by more
    // than √2: a slope ≤ −0.5): from there down the errors are noise.
    let noise_from = (0..bottom).rev().find(|&k| slopes[k] <= -MIN_WINDOW_SLOPE);
    let mut floor: Option<Floor> = None;
    for (k, p) in pts.iter().enumerate() {
        if in_window(k) {
            continue;
        }
        let (kind, why) = if k > top {
            let s = slopes[k - 1];
            if s < 0.0 {
                (
                    ExcludedKind::Noise,
                    format!(
                        "noise: the error is {:.2}× smaller than at the next smaller step (local \
                         slope {s:.2})",
                        pts[k - 1].e / p.e
                    ),
                )
            } else {
                (
                    ExcludedKind::PreAsymptotic,
                    format!(
                        "pre-asymptotic: local slope {s:.2} from the next smaller step, far from \
                         {top_m:.2} in the window"
                    ),
                )
            }
        } else if k > bottom {
            let s = slopes[k];
            if s < 0.0 {
                (
                    ExcludedKind::Noise,
                    format!(
                        "noise: the error grows {:.2}× as the step halves (local slope {s:.2} to \
                         the next larger step), between two regimes",
                        p.e / pts[k + 1].e
                    ),
                )
            } else {
                (
                    ExcludedKind::Between,
                    format!("between two regimes (local slope {s:.2} to the next larger step)"),
                )
            }
        } else {
            let s = slopes[k];
            let ratio = p.e / p.r;
            let kind = if p.at_round_off() {
                ExcludedKind::RoundOffFloor
            } else if noise_from.is_some_and(|n| k <= n) {
                ExcludedKind::Noise
            } else if s < MIN_WINDOW_SLOPE {
                ExcludedKind::FloorAboveRoundOff
            } else {
                ExcludedKind::OffTheLine
            };
            if kind != ExcludedKind::OffTheLine
                && floor.is_none_or(|f: Floor| ratio > f.error / f.expected_round_off)
            {
                floor = Some(Floor {
                    error: p.e,
                    expected_round_off: p.r,
                    kind: FloorKind::RoundOff,
                });
            }
            let why = match kind {
                ExcludedKind::RoundOffFloor => format!(
                    "round-off floor: error {:.2e}, within {ROUND_OFF_MARGIN}× the round-off \
                     expected at this step ({:.2e}; local slope {s:.2} to the next larger step)",
                    p.e, p.r
                ),
                ExcludedKind::Noise if s <= -MIN_WINDOW_SLOPE => format!(
                    "noise: the error grows {:.2}× as the step halves (local slope {s:.2} to the \
                     next larger step), {ratio:.1e}× the round-off expected at this step",
                    p.e / pts[k + 1].e
                ),
                ExcludedKind::Noise => format!(
                    "noise: below the step {:.3e} where the error grew as the step halved (local \
                     slope {s:.2} to the next larger step), {ratio:.1e}× the round-off expected \
                     at this step",
                    pts[noise_from.unwrap_or(k)].h
                ),
                ExcludedKind::FloorAboveRoundOff => format!(
                    "floor above round-off: the error stops falling (local slope {s:.2} to the \
                     next larger step) at {:.2e}, {ratio:.1e}× the round-off expected at this \
                     step ({:.2e})",
                    p.e, p.r
                ),
                _ => format!(
                    "off the line: the error still falls (local slope {s:.2} to the next larger \
                     step) but far from {bottom_m:.2} in the window; not fitted"
                ),
            };
            (kind, why)
        };
        excluded.push(Excluded {
            step: p.h,
            kind,
            why,
        });
    }
    if let Some(f) = &mut floor {
        if f.error > ROUND_OFF_MARGIN * f.expected_round_off {
            f.kind = FloorKind::AboveRoundOff;
            // A low error inside a floor above round-off is not a round-off floor.
            let (worst, worst_h) = (f.error, pts.iter().find(|p| p.e == f.error).map(|p| p.h));
            for e in excluded.iter_mut() {
                if e.kind == ExcludedKind::RoundOffFloor {
                    let below_noise = noise_from.is_some_and(|n| e.step <= pts[n].h);
                    e.kind = if below_noise {
                        ExcludedKind::Noise
                    } else {
                        ExcludedKind::FloorAboveRoundOff
                    };
                    e.why = format!(
                        "{}: near the round-off level here, but the floor is above round-off \
                         ({worst:.2e} at step {:.3e}); {}",
                        e.kind.as_str(),
                        worst_h.unwrap_or(f64::NAN),
                        e.why.trim_start_matches("round-off floor: ")
                    );
                }
            }
        }
    }
    excluded.sort_by(|a, b| b.step.total_cmp(&a.step));
    let last = regimes[regimes.len() - 1].clone();
    Ok(OrderFit {
        method: String::new(),
        order: last.order,
        order_stderr: last.order_stderr,
        window: last.window,
        log10_constant: last.log10_constant,
        regimes,
        competing,
        floor,
        excluded,
    })
}

/// Slope, its standard error and intercept of y = c + p·x by least squares (n ≥ 3).
pub fn least_squares(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    let c = my - slope * mx;
    let ssr: f64 = points.iter().map(|p| (p.1 - c - slope * p.0).powi(2)).sum();
    let stderr = (ssr / (n - 2.0) / sxx).sqrt();
    (slope, stderr, c)
}
