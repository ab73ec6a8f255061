//! How an error grows along a run: least-squares fits of log(error) against log(t) (polynomial,
//! error ≈ C t^p) and against t (exponential, error ≈ C e^{λt}); exponential when it implies a
//! large growth ([`EXPONENTIAL_MIN_GROWTH`]) and either its fit is clearly better
//! ([`EXPONENTIAL_RMS_RATIO`]) or its rate is the same on both halves of the window
//! ([`EXPONENTIAL_SLOPE_RATIO`]: a power law's rate in t falls like 1/t, to about a quarter
//! from the first half to the second of a window [T/20, T]), else polynomial.
//!
//! What is fitted is the running maximum of the error (its envelope: errors of a motion on a torus
//! oscillate). Fitted samples: those before the first error above [`SATURATION`] (an
//! error of order one no longer grows: the state is bounded), from a twentieth of their span on
//! (the start is round-off noise), with errors above 1e-300.

use serde::{Deserialize, Serialize};

/// Errors above this are saturated: the fit stops there.
pub const SATURATION: f64 = 1e-2;
/// Fewer fitted samples than this: no fit.
pub const MIN_POINTS: usize = 8;

/// The exponential model is chosen only when its rms residual is below this fraction of the
/// polynomial fit's…
pub const EXPONENTIAL_RMS_RATIO: f64 = 0.5;
/// …and e^{λ·span} over the fitted span is at least this: over a short window a slow exponential
/// and a power law cannot be told apart, and such growth is reported as polynomial.
pub const EXPONENTIAL_MIN_GROWTH: f64 = 1e3;
/// The rate in t fitted on the second half of the window over that on the first: within these
/// bounds the growth is exponential (the envelope of an oscillating error is too jagged for
/// the rms test alone to tell e^{λt} from t⁵ over a few e-foldings; t^p gives ≈ 0.27).
pub const EXPONENTIAL_SLOPE_RATIO: (f64, f64) = (0.6, 1.6);

/// The better of the two fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    Polynomial,
    Exponential,
}

/// Both fits of one error series.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Growth {
    pub model: Model,
    /// Exponent p of error ≈ C t^p.
    pub p: f64,
    /// Rate λ of error ≈ C e^{λt} (per unit time).
    pub lambda: f64,
    /// Root-mean-square residuals (in ln error) of the two fits.
    pub rms_polynomial: f64,
    pub rms_exponential: f64,
    /// Number of samples fitted and the time span they cover.
    pub points: usize,
    pub t_from: f64,
    pub t_to: f64,
}

impl Growth {
    /// `t^1.02` or `e^(0.31 t)`.
    pub fn describe(&self) -> String {
        match self.model {
            Model::Polynomial => format!("~t^{:.2}", self.p),
            Model::Exponential => format!("~e^({:.3e} t)", self.lambda),
        }
    }
}

/// Least squares y ≈ c + s x: (slope, rms residual).
fn line_fit(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let c = my - slope * mx;
    let ss: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - c - slope * a).powi(2))
        .sum();
    Some((slope, (ss / n).sqrt()))
}

/// Fit the growth of `errors` along `times` (same length).
pub fn fit(times: &[f64], errors: &[f64]) -> Option<Growth> {
    // The samples before saturation, then the envelope from a twentieth of that span on.
    let n = times
        .iter()
        .zip(errors)
        .position(|(_, e)| !e.is_finite() || *e > SATURATION)
        .unwrap_or(times.len().min(errors.len()));
    let t_end = times[..n].iter().copied().fold(0.0, f64::max);
    if t_end <= 0.0 {
        return None;
    }
    let mut t = Vec::new();
    let mut y = Vec::new();
    // The running maximum: the envelope of an oscillating error.
    let mut envelope = 0.0f64;
    for (&ti, &ei) in times[..n].iter().zip(&errors[..n]) {
        envelope = envelope.max(ei);
        if ti >= t_end / 20.0 && ti > 0.0 && envelope > 1e-300 {
            t.push(ti);
            y.push(envelope.ln());
        }
    }
    if t.len() < MIN_POINTS {
        return None;
    }
    let lt: Vec<f64> = t.iter().map(|v| v.ln()).collect();
    let (p, rms_p) = line_fit(&lt, &y)?;
    let (lambda, rms_e) = line_fit(&t, &y)?;
    let half = t.len() / 2;
    let steady = match (
        line_fit(&t[..half], &y[..half]),
        line_fit(&t[half..], &y[half..]),
    ) {
        (Some((s1, _)), Some((s2, _))) if s1 > 0.0 => {
            let (lo, hi) = EXPONENTIAL_SLOPE_RATIO;
            (lo..=hi).contains(&(s2 / s1))
        }
        _ => false,
    };
    Some(Growth {
        model: if (rms_e < EXPONENTIAL_RMS_RATIO * rms_p || steady)
            && lambda * (t[t.len() - 1] - t[0]) >= EXPONENTIAL_MIN_GROWTH.ln()
        {
            Model::Exponential
        } else {
            Model::Polynomial
        },
        p,
        lambda,
        rms_polynomial: rms_p,
        rms_exponential: rms_e,
        points: t.len(),
        t_from: t[0],
        t_to: *t.last().expect("non-empty"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, t_end: f64) -> Vec<f64> {
        (0..n).map(|k| t_end * k as f64 / (n - 1) as f64).collect()
    }

    #[test]
    fn a_power_law_is_polynomial_with_its_exponent() {
        let t = grid(400, 1000.0);
        let e: Vec<f64> = t
            .iter()
            .map(|x| 1e-14 * x.powf(1.5) * (1.0 + 0.1 * (x * 3.1).sin()))
            .collect();
        let g = fit(&t, &e).unwrap();
        assert_eq!(g.model, Model::Polynomial);
        assert!((g.p - 1.5).abs() < 0.05, "{g:?}");
    }

    #[test]
    fn an_exponential_is_exponential_with_its_rate_and_saturation_stops_the_fit() {
        let t = grid(400, 100.0);
        let e: Vec<f64> = t
            .iter()
            .map(|x| (1e-15 * (0.4 * x).exp()).min(2.0))
            .collect();
        let g = fit(&t, &e).unwrap();
        assert_eq!(g.model, Model::Exponential);
        assert!((g.lambda - 0.4).abs() < 1e-6, "{g:?}");
        // 1e-15 e^{0.4 t} passes 1e-2 at t = ln(1e13)/0.4 ≈ 74.8: the fit stops there.
        assert!(g.t_to < 74.9 && g.t_to > 74.0, "{g:?}");
    }

    #[test]
    fn a_jagged_exponential_is_exponential_and_a_power_law_above_a_floor_is_not() {
        // e^{0.24 t} under rare ×1000 bursts: the running maximum climbs in steps that spoil
        // the rms test (rms ratio 0.82 here), the rate on both halves agrees (ratio 0.87).
        let t = grid(1000, 60.0);
        let e: Vec<f64> = t
            .iter()
            .map(|x| 1e-9 * (0.24 * x).exp() * (1.0 + 1e3 * (0.5 + 0.5 * (0.3 * x).sin()).powi(20)))
            .collect();
        let g = fit(&t, &e).unwrap();
        assert!(
            g.rms_exponential > EXPONENTIAL_RMS_RATIO * g.rms_polynomial,
            "{g:?}"
        );
        assert_eq!(g.model, Model::Exponential, "{g:?}");
        assert!((g.lambda - 0.24).abs() < 0.05, "{g:?}");
        // A floor then t²: polynomial, whatever the halves do.
        let t = grid(1000, 1000.0);
        let e: Vec<f64> = t.iter().map(|x| 1e-12 + 1e-14 * x * x).collect();
        assert_eq!(fit(&t, &e).unwrap().model, Model::Polynomial);
        let e: Vec<f64> = t.iter().map(|x| 1e-16 * x.powi(5)).collect();
        assert_eq!(fit(&t, &e).unwrap().model, Model::Polynomial);
    }

    #[test]
    fn too_few_points_or_no_time_give_no_fit() {
        assert!(fit(&[0.0, 0.0], &[1e-16, 1e-16]).is_none());
        let t = grid(5, 10.0);
        assert!(fit(&t, &[1e-16; 5]).is_none());
        let t = grid(100, 10.0);
        assert!(fit(&t, &[0.0; 100]).is_none());
    }
}
