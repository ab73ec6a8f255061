//! Axis ranges and ticks. Log₁₀ axes: whole decades as limits when the data spans one or more,
//! a labelled tick every decade (every 2nd, 5th, 10th… decade when the labels would not fit, with
//! an unlabelled tick at each decade still), minor ticks at 2…9 × 10ᵏ, and 1-2-5 labels when the
//! range is short. Linear axes: 1-2-5 steps.

use crate::Scale;

/// A tick at `at` (in transformed units: log₁₀ of the value on log axes).
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    pub at: f64,
    /// The value, exactly as written (`2e-6`, `0.25`): the `data-v` attribute.
    pub value: String,
    pub label: Option<Label>,
    /// Major ticks get a grid line across the plot; minor ones only a short mark.
    pub major: bool,
}

/// Text of a tick label.
#[derive(Clone, Debug, PartialEq)]
pub enum Label {
    Plain(String),
    /// `mantissa × 10^exponent`; no mantissa: `10^exponent`.
    Power {
        mantissa: Option<String>,
        exponent: i32,
    },
}

/// The axis range (transformed units) for data in `lo..=hi`.
pub fn range(lo: f64, hi: f64, scale: Scale) -> (f64, f64) {
    if hi - lo < 1e-12 * lo.abs().max(1.0) {
        let half = if scale == Scale::Log10 {
            0.5
        } else {
            0.5 * lo.abs().max(1.0)
        };
        return (lo - half, hi + half);
    }
    if scale == Scale::Log10 && hi - lo >= 1.0 {
        // Whole decades, and a little room so that points on a limit are not cut by the frame.
        let (a, b) = ((lo + 1e-9).floor(), (hi - 1e-9).ceil());
        let pad = 0.02 * (b - a);
        return (a - pad, b + pad);
    }
    let pad = 0.06 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Ticks of an axis `length` px long; `label_space`: px a label needs along the axis.
pub fn ticks(scale: Scale, lo: f64, hi: f64, length: f64, label_space: f64) -> Vec<Tick> {
    match scale {
        Scale::Log10 => log_ticks(lo, hi, length, label_space),
        Scale::Linear => linear_ticks(lo, hi, length, label_space),
    }
}

fn inside(v: f64, lo: f64, hi: f64) -> bool {
    v >= lo - 1e-9 && v <= hi + 1e-9
}

/// Smallest gap in px between consecutive labelled ticks.
fn min_gap(ticks: &[Tick], px_per_unit: f64) -> f64 {
    let labelled: Vec<f64> = ticks
        .iter()
        .filter(|t| t.label.is_some())
        .map(|t| t.at)
        .collect();
    labelled
        .windows(2)
        .map(|w| (w[1] - w[0]) * px_per_unit)
        .fold(f64::INFINITY, f64::min)
}

fn log_ticks(lo: f64, hi: f64, length: f64, label_space: f64) -> Vec<Tick> {
    let px_per_decade = length / (hi - lo);
    let (k0, k1) = (lo.floor() as i32, hi.ceil() as i32);
    // Short ranges: 1-2-5 (or every mantissa 1…9) labelled, when they fit.
    for mantissas in [&[1, 2, 5][..], &[1, 2, 3, 4, 5, 6, 7, 8, 9][..]] {
        let mut t = Vec::new();
        for k in k0..=k1 {
            for m in 1..=9 {
                let at = (m as f64).log10() + k as f64;
                if !inside(at, lo, hi) {
                    continue;
                }
                let labelled = mantissas.contains(&m);
                t.push(Tick {
                    at,
                    value: format!("{m}e{k}"),
                    label: labelled.then(|| Label::Power {
                        mantissa: (m != 1).then(|| m.to_string()),
                        exponent: k,
                    }),
                    major: labelled,
                });
            }
        }
        let count = t.iter().filter(|x| x.label.is_some()).count();
        if count >= 2
            && min_gap(&t, px_per_decade) >= label_space
            && hi - lo <= 2.5
            && (mantissas.len() == 3 || hi - lo < 1.0)
        {
            return t;
        }
    }
    // Decades: every one ticked; labels every `step` decades so that they do not collide.
    let step = [1, 2, 5, 10, 20, 50, 100, 200, 500]
        .into_iter()
        .find(|&s| s as f64 * px_per_decade >= label_space)
        .unwrap_or(1000);
    let mut t = Vec::new();
    for k in k0..=k1 {
        if inside(k as f64, lo, hi) {
            t.push(Tick {
                at: k as f64,
                value: format!("1e{k}"),
                label: (k.rem_euclid(step) == 0).then_some(Label::Power {
                    mantissa: None,
                    exponent: k,
                }),
                major: true,
            });
        }
        // Minor ticks at 2…9 × 10ᵏ while there is room for them (≥ 2 px apart).
        if px_per_decade * (10f64.log10() - 9f64.log10()) >= 2.0 {
            for m in 2..=9 {
                let at = (m as f64).log10() + k as f64;
                if inside(at, lo, hi) {
                    t.push(Tick {
                        at,
                        value: format!("{m}e{k}"),
                        label: None,
                        major: false,
                    });
                }
            }
        }
    }
    if t.iter().filter(|x| x.label.is_some()).count() < 2 {
        // Fewer than two labels (a very short range between two decades): label the ends.
        for (at, end) in [(lo, 0), (hi, 1)] {
            let v = 10f64.powf(at);
            let e = v.log10().floor() as i32;
            let m = v / 10f64.powi(e);
            let label = Label::Power {
                mantissa: Some(
                    format!("{m:.2}")
                        .trim_end_matches('0')
                        .trim_end_matches('.')
                        .to_string(),
                ),
                exponent: e,
            };
            let at = if end == 0 { lo } else { hi };
            t.push(Tick {
                at,
                value: format!("{v:e}"),
                label: Some(label),
                major: true,
            });
        }
    }
    t.sort_by(|a, b| a.at.total_cmp(&b.at));
    t
}

fn linear_ticks(lo: f64, hi: f64, length: f64, label_space: f64) -> Vec<Tick> {
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let most = (length / label_space).floor().clamp(2.0, 10.0);
    let raw = span / most;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            let label = if (1e-3..1e5).contains(&step.abs()) {
                let decimals = (-step.log10().floor()).max(0.0) as usize;
                format!("{v:.decimals$}")
            } else {
                format!("{v:.0e}")
            };
            Tick {
                at: v,
                value: label.clone(),
                label: Some(Label::Plain(label)),
                major: true,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(t: &[Tick]) -> Vec<String> {
        t.iter()
            .filter(|t| t.label.is_some())
            .map(|t| t.value.clone())
            .collect()
    }

    #[test]
    fn every_decade_is_labelled_when_there_is_room() {
        let (lo, hi) = range(-12.3, -3.2, Scale::Log10);
        assert!(
            lo < -13.0 && lo > -13.5 && hi > -3.0 && hi < -2.7,
            "{lo} {hi}"
        );
        let t = ticks(Scale::Log10, lo, hi, 600.0, 40.0);
        let decades: Vec<i32> = t
            .iter()
            .filter(|t| t.label.is_some())
            .map(|t| t.at.round() as i32)
            .collect();
        assert_eq!(decades, (-13..=-3).collect::<Vec<_>>());
        // Minor ticks between the decades.
        assert!(t.iter().filter(|t| !t.major).count() >= 8 * 10);
    }

    #[test]
    fn many_decades_are_labelled_every_few_and_ticked_every_one() {
        let t = ticks(Scale::Log10, -81.0, -19.0, 600.0, 40.0);
        let labelled: Vec<i32> = t
            .iter()
            .filter(|t| t.label.is_some())
            .map(|t| t.at.round() as i32)
            .collect();
        assert_eq!(labelled, (-16..=-4).map(|k| 5 * k).collect::<Vec<_>>());
        assert_eq!(
            t.iter().filter(|t| t.major).count(),
            63,
            "a tick per decade"
        );
    }

    #[test]
    fn short_ranges_get_1_2_5_labels() {
        let (lo, hi) = range(3e-7f64.log10(), 1e-5f64.log10(), Scale::Log10);
        let v = labels(&ticks(Scale::Log10, lo, hi, 600.0, 50.0));
        assert_eq!(v, ["1e-7", "2e-7", "5e-7", "1e-6", "2e-6", "5e-6", "1e-5"]);
        // Wider than 2.5 decades: decades only.
        let v = labels(&ticks(Scale::Log10, -7.0, -4.0, 600.0, 50.0));
        assert_eq!(v, ["1e-7", "1e-6", "1e-5", "1e-4"]);
        // Within one decade: 2, 3, 4… when 1-2-5 gives fewer than two labels.
        let v = labels(&ticks(
            Scale::Log10,
            2.2e-3f64.log10(),
            4.5e-3f64.log10(),
            600.0,
            50.0,
        ));
        assert_eq!(v, ["3e-3", "4e-3"]);
    }

    #[test]
    fn linear_ticks_are_round_numbers() {
        let t = ticks(Scale::Linear, 0.0, 10.0, 600.0, 40.0);
        let l: Vec<String> = t
            .iter()
            .map(|t| match &t.label {
                Some(Label::Plain(s)) => s.clone(),
                _ => panic!(),
            })
            .collect();
        assert_eq!(l, ["0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "10"]);
        let t = ticks(Scale::Linear, 0.0, 10.0, 200.0, 40.0);
        assert_eq!(t.len(), 6, "0, 2, … 10 on a short axis");
    }
}
