//! Growth laws of the invariants' drift: |H(t) − H(0)|, |K(t) − K(0)|, |G(t) − G(0)| and the
//! constraint residual fitted as C·t^p (the [`growth::fit`] of the running maximum, after the
//! first [`FIRST_SAMPLES`] samples) and named as heyoka's energy studies do:
//! `bounded` (p < 0.2), `random-walk` (p < 0.75: round-off, Brouwer's law √t), `linear`
//! (p ≤ 1.3: truncation drift), `faster` (p > 1.3) or `exponential` (the exponential model of
//! [`growth::fit`] wins).
//!
//! The drifts are kept as a bounded summary ([`LogSpacedEnvelope`]): the running maximum at
//! log-spaced times (a few points per octave of t), so a run of any length, or a streaming
//! check, fits from a few hundred points.

use serde::{Deserialize, Serialize};

use crate::growth::{self, Model};

/// Samples before this index are left out of the fit (the start is round-off noise).
pub const FIRST_SAMPLES: usize = 4;
/// Points kept per octave of t.
pub const PER_OCTAVE: f64 = 8.0;

/// The name of a growth law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GrowthKind {
    Bounded,
    RandomWalk,
    Linear,
    Faster,
    Exponential,
}

impl GrowthKind {
    /// The law of the exponent p of C·t^p (polynomial growth).
    pub fn of_exponent(p: f64) -> Self {
        if p < 0.2 {
            Self::Bounded
        } else if p < 0.75 {
            Self::RandomWalk
        } else if p <= 1.3 {
            Self::Linear
        } else {
            Self::Faster
        }
    }

    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Bounded => "bounded",
            Self::RandomWalk => "random-walk",
            Self::Linear => "linear",
            Self::Faster => "faster",
            Self::Exponential => "exponential",
        }
    }
}

/// The fitted law of one drift.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrowthLaw {
    /// p of C·t^p.
    pub exponent: f64,
    pub kind: GrowthKind,
}

/// The laws of the four drifts (`drift.growth` of the compare/check JSON); `null` for a drift
/// with too few samples to fit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriftGrowth {
    #[serde(rename = "H")]
    pub h: Option<GrowthLaw>,
    #[serde(rename = "K")]
    pub k: Option<GrowthLaw>,
    #[serde(rename = "G")]
    pub g: Option<GrowthLaw>,
    pub constraints: Option<GrowthLaw>,
}

impl DriftGrowth {
    /// `H linear (t^1.01), K bounded (t^0.03), …` for the table.
    pub fn describe(&self) -> String {
        [
            ("H", self.h),
            ("K", self.k),
            ("G", self.g),
            ("constraints", self.constraints),
        ]
        .iter()
        .map(|(name, law)| match law {
            Some(l) => format!("{name} {} (t^{:.2})", l.kind.as_str(), l.exponent),
            None => format!("{name} -"),
        })
        .collect::<Vec<_>>()
        .join(", ")
    }
}

/// The running maxima of a few series at log-spaced times: one point per bucket
/// ⌊[`PER_OCTAVE`]·log2(t/t₁)⌋ (t₁ the first positive time), the last sample of each bucket.
#[derive(Clone, Debug)]
pub struct LogSpacedEnvelope<const N: usize> {
    t1: Option<f64>,
    seen: usize,
    envelope: [f64; N],
    /// (bucket, time, envelope) of the points kept.
    points: Vec<(i64, f64, [f64; N])>,
    /// Times below this fall in the last point's bucket or before: a bound a little below
    /// that bucket's end (by 1e-9 relative, far beyond the logarithm's rounding), so most
    /// samples need no logarithm. −∞ while no point is kept.
    within: f64,
}

impl<const N: usize> Default for LogSpacedEnvelope<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> LogSpacedEnvelope<N> {
    pub fn new() -> Self {
        Self {
            t1: None,
            seen: 0,
            envelope: [0.0; N],
            points: Vec::new(),
            within: f64::NEG_INFINITY,
        }
    }

    /// Add the next sample (time order). Samples before [`FIRST_SAMPLES`] or at t ≤ 0 enter
    /// the envelope but are not kept; a non-finite value makes its envelope infinite.
    pub fn push(&mut self, t: f64, values: [f64; N]) {
        let index = self.seen;
        self.seen += 1;
        for (e, v) in self.envelope.iter_mut().zip(values) {
            *e = if v.is_nan() { f64::INFINITY } else { e.max(v) };
        }
        if index < FIRST_SAMPLES || !(t > 0.0 && t.is_finite()) {
            return;
        }
        if t < self.within {
            if let Some(last) = self.points.last_mut() {
                *last = (last.0, t, self.envelope);
                return;
            }
        }
        let t1 = *self.t1.get_or_insert(t);
        let bucket = (PER_OCTAVE * (t / t1).log2()).floor() as i64;
        match self.points.last_mut() {
            Some(last) if last.0 >= bucket => *last = (last.0, t, self.envelope),
            _ => self.points.push((bucket, t, self.envelope)),
        }
        if let Some(last) = self.points.last() {
            let end = t1 * ((last.0 + 1) as f64 / PER_OCTAVE).exp2();
            self.within = end * (1.0 - 1e-9);
        }
    }

    /// Number of points kept.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The times and the envelope of series `k` at the points kept.
    pub fn series(&self, k: usize) -> (Vec<f64>, Vec<f64>) {
        self.points.iter().map(|(_, t, e)| (*t, e[k])).unzip()
    }

    /// The law of series `k`: an identically zero drift is bounded (p = 0); too few points, no
    /// law.
    pub fn law(&self, k: usize) -> Option<GrowthLaw> {
        let (t, e) = self.series(k);
        if t.len() >= growth::MIN_POINTS && e.iter().all(|&x| x == 0.0) {
            return Some(GrowthLaw {
                exponent: 0.0,
                kind: GrowthKind::Bounded,
            });
        }
        let g = growth::fit(&t, &e)?;
        Some(GrowthLaw {
            exponent: g.p,
            kind: match g.model {
                Model::Exponential => GrowthKind::Exponential,
                Model::Polynomial => GrowthKind::of_exponent(g.p),
            },
        })
    }
}

/// The drifts of H, K, G and of the constraints along a run.
pub type DriftSeries = LogSpacedEnvelope<4>;

impl DriftSeries {
    /// The four laws.
    pub fn laws(&self) -> DriftGrowth {
        DriftGrowth {
            h: self.law(0),
            k: self.law(1),
            g: self.law(2),
            constraints: self.law(3),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(n: usize, t_end: f64, f: impl Fn(f64) -> f64) -> LogSpacedEnvelope<1> {
        let mut s = LogSpacedEnvelope::<1>::new();
        for k in 0..n {
            let t = t_end * k as f64 / (n - 1) as f64;
            s.push(t, [f(t)]);
        }
        s
    }

    /// The points kept are those of the definition (a logarithm per sample): on times at the
    /// buckets' ends, one ulp either side, and in between, from several first times.
    #[test]
    fn the_points_are_those_of_a_logarithm_per_sample() {
        for t1 in [1e-3, 0.37, 1.0, 3.0, 1e5] {
            let mut times = vec![0.0, 0.0, 0.0, 0.0];
            for k in 0..400 {
                let end = t1 * (k as f64 / PER_OCTAVE).exp2();
                let (below, above) = (f64::from_bits(end.to_bits() - 1), end.next_up());
                times.extend([below, end, above, end * (1.0 + 1e-10), end * 1.03]);
            }
            let mut s = LogSpacedEnvelope::<1>::new();
            let mut points: Vec<(i64, f64, [f64; 1])> = Vec::new();
            for (k, &t) in times.iter().enumerate() {
                let v = [k as f64];
                s.push(t, v);
                if k < FIRST_SAMPLES || t <= 0.0 {
                    continue;
                }
                let bucket = (PER_OCTAVE * (t / times[FIRST_SAMPLES]).log2()).floor() as i64;
                match points.last_mut() {
                    Some(last) if last.0 >= bucket => *last = (last.0, t, v),
                    _ => points.push((bucket, t, v)),
                }
            }
            assert_eq!(s.points, points, "t1 = {t1}");
            assert!(points.len() > 390, "{}", points.len());
        }
    }

    #[test]
    fn laws_of_known_growths_and_the_summary_stays_small() {
        type Law<'a> = &'a dyn Fn(f64) -> f64;
        let cases: [(Law, GrowthKind, f64); 4] = [
            (
                &|t| 1e-15 * (1.0 + 0.5 * (3.0 * t).sin()),
                GrowthKind::Bounded,
                0.0,
            ),
            (
                &|t| 1e-16 * t.sqrt() * (1.2 + (7.0 * t).sin()),
                GrowthKind::RandomWalk,
                0.5,
            ),
            (
                &|t| 1e-12 * t * (1.0 + 0.1 * (2.0 * t).cos()),
                GrowthKind::Linear,
                1.0,
            ),
            (&|t| 1e-14 * t * t, GrowthKind::Faster, 2.0),
        ];
        for (f, kind, p) in cases {
            let s = run(100_001, 1000.0, f);
            assert!(s.len() < 200, "{} points kept", s.len());
            let law = s.law(0).unwrap();
            assert_eq!(law.kind, kind, "{law:?}");
            assert!((law.exponent - p).abs() < 0.15, "{law:?} vs {p}");
        }
        let s = run(2001, 200.0, |t| (1e-12 * (0.2 * t).exp()).min(1.0));
        assert_eq!(s.law(0).unwrap().kind, GrowthKind::Exponential);
        let s = run(100, 10.0, |_| 0.0);
        assert_eq!(s.law(0).unwrap().kind, GrowthKind::Bounded);
        assert!(run(5, 10.0, |t| t).law(0).is_none());
        assert_eq!(GrowthKind::of_exponent(0.5).as_str(), "random-walk");
        assert_eq!(
            serde_json::to_string(&GrowthKind::RandomWalk).unwrap(),
            "\"random-walk\""
        );
    }
}
