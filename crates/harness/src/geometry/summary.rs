//! What the geometry adds to a report: the summaries of a run (max and final values, growth
//! fits) and the split of the state error at the last sample before it saturates.

use rsts_closed_form::manifold::NormalType;
use serde::{Deserialize, Deserializer, Serialize};

use super::Series;
use crate::growth::{self, Growth, Model};

/// max and final value of a series.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MaxFinal {
    #[serde(deserialize_with = "nan_if_null")]
    pub max: f64,
    #[serde(rename = "final", deserialize_with = "nan_if_null")]
    pub last: f64,
}

/// JSON writes a NaN as null: read it back as NaN (validate's report.json and baselines).
fn nan_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Option::<f64>::deserialize(d).map(|x| x.unwrap_or(f64::NAN))
}

impl MaxFinal {
    pub(super) fn absorb(&mut self, x: f64) {
        if x.is_finite() {
            self.max = self.max.max(x);
        }
        self.last = x;
    }
}

/// How a series grows: "polynomial" (~t^exponent) or "exponential" (~e^{rate·t}), with both
/// fitted numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrowthSummary {
    pub kind: Model,
    /// λ of the exponential fit (per unit time).
    pub rate: f64,
    /// p of the polynomial fit.
    pub exponent: f64,
}

impl GrowthSummary {
    pub(super) fn of(g: &Option<Growth>) -> Option<Self> {
        g.as_ref().map(|g| Self {
            kind: g.model,
            rate: g.lambda,
            exponent: g.p,
        })
    }

    /// "e^{0.241 t}" or "t^2.03".
    pub fn describe(&self) -> String {
        match self.kind {
            Model::Exponential => format!("e^({:.3} t)", self.rate),
            Model::Polynomial => format!("t^{:.2}", self.exponent),
        }
    }
}

/// The departure from N over a run (the `normal` object of the compare JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NormalSummary {
    /// "elliptic", "hyperbolic" or "degenerate": the normal type of N at (m, h).
    #[serde(rename = "type")]
    pub kind: NormalType,
    /// λ² = −4r⁴mℓ².
    pub lambda2: f64,
    /// Distance of the integrated state from N (state units).
    #[serde(rename = "distance_from_N")]
    pub distance_from_n: MaxFinal,
    /// |X_Φ| along the run.
    pub x_phi: MaxFinal,
    /// Growth of the distance from N (null: too few samples).
    pub growth: Option<GrowthSummary>,
}

/// The phase error over a run (the `phase_error` object of the compare JSON).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PhaseErrorSummary {
    /// |Δψ₁|, |Δψ₂| (radians): largest and at the last sample.
    pub psi1: MaxFinal,
    pub psi2: MaxFinal,
    /// Drift of the torus: largest |δm|, |δh| of the nearest point.
    pub dm: f64,
    pub dh: f64,
    /// Growth of max(|Δψ₁|, |Δψ₂|).
    pub growth: Option<GrowthSummary>,
}

/// What dominates the state error, at the last sample before it saturates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorSplit {
    /// The sample's time and its two parts: along N and the departure from N.
    pub t: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub along_n: f64,
    #[serde(rename = "departure_from_N", deserialize_with = "nan_if_null")]
    pub departure_from_n: f64,
    /// "drift along the torus" or "departure from N".
    pub dominant: String,
    /// The sentence the table shows.
    pub summary: String,
}

/// Everything the geometry adds to a report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GeometrySummary {
    pub normal: NormalSummary,
    pub phase_error: PhaseErrorSummary,
    pub error_split: Option<ErrorSplit>,
}

/// The split at the last sample before the state error saturates ([`growth::SATURATION`]).
pub(super) fn split(
    s: &Series,
    normal: &NormalSummary,
    phase: &PhaseErrorSummary,
) -> Option<ErrorSplit> {
    let k = s
        .state_error
        .iter()
        .rposition(|e| *e <= growth::SATURATION && e.is_finite())?;
    let (along, departure) = (s.along[k], s.distance[k]);
    // Hyperbolic N: a departure grows like e^{λt} and drags a drift along N with it (its
    // unstable direction is not orthogonal to N), so the two parts are compared by how they
    // grow, not by size: an exponentially growing departure is the cause.
    let unstable = normal
        .growth
        .as_ref()
        .is_some_and(|g| g.kind == Model::Exponential);
    let departs = unstable || departure > along || along.is_nan();
    let summary = if departs {
        let how = match &normal.growth {
            Some(g) if unstable => format!("e^(λt) with λ = {:.3} per unit time", g.rate),
            Some(g) => format!("growing like {}", g.describe()),
            None => "too few samples to fit its growth".to_string(),
        };
        let why = match normal.kind {
            NormalType::Hyperbolic => "N is normally hyperbolic here (m < 0)",
            NormalType::Elliptic => "N is normally elliptic here",
            NormalType::Degenerate => "N is normally degenerate here",
        };
        format!("departure from N, {how}: {why}")
    } else {
        let how = match &phase.growth {
            Some(g) if g.kind == Model::Polynomial && (g.exponent - 1.0).abs() < 0.3 => {
                "phase error linear in t".to_string()
            }
            Some(g) if g.kind == Model::Polynomial && (g.exponent - 2.0).abs() < 0.3 => {
                "phase error quadratic in t".to_string()
            }
            Some(g) => format!("phase error growing like {}", g.describe()),
            None => "too few samples to fit the phase error's growth".to_string(),
        };
        format!("drift along the torus, {how}")
    };
    Some(ErrorSplit {
        t: s.t[k],
        along_n: along,
        departure_from_n: departure,
        dominant: if departs {
            "departure from N"
        } else {
            "drift along the torus"
        }
        .to_string(),
        summary,
    })
}
