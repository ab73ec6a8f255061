//! [`describe_point`]: the camera, oscillation segments, moduli, periods, frequencies, rotation
//! number and radicals at one point (m, h), as a serializable [`PointDescription`] with a
//! plain-text `Display`.

use std::fmt;

use serde::{Serialize, Serializer};

use crate::camera::Camera;
use crate::constants::IntegralConstants;
use crate::error::ClosedFormError;
use crate::manifold::normal::{normal_type, NormalType};
use crate::motion::{ExplicitMotion, TorusChoice};
use crate::roots::RootLabel;
use crate::separated::{Radicand, SeparatedVariable};

use super::{check_fields, tori_text};

fn finite_or_null<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_some(x)
    } else {
        s.serialize_none()
    }
}

/// One end of an oscillation segment in the variable s (s₁ or s₂).
#[derive(Clone, Debug, Serialize)]
pub struct SegmentEnd {
    /// The root it stands for: "a", "-a", "b", "-b", "theta1", "theta2".
    pub label: RootLabel,
    /// Its value in s (±∞ only for s₁ at m = 0, where θ₂ = ∞; serialized as null).
    #[serde(serialize_with = "finite_or_null")]
    pub value: f64,
}

/// One radical of a separated variable and whether it keeps a constant sign on the torus.
#[derive(Clone, Debug, Serialize)]
pub struct RadicalDescription {
    /// "F1*", "G1*" (F₁/s₁, G₁/s₁, of x = 1/s₁; seed eq. 3.2), "F2", "G2".
    pub name: &'static str,
    /// True when neither end of the segment is a root of this radical: its sign is a free
    /// constant that tells the Liouville tori apart.
    pub constant_sign: bool,
    /// Its sign on torus 0 (+1 or −1; for a radical that changes sign: the sign while the
    /// variable leaves the lower end λ of the segment in its coordinate).
    pub sign_on_torus0: i32,
}

/// One separated variable at a point (m, h).
#[derive(Clone, Debug, Serialize)]
pub struct VariableDescription {
    /// "s1" or "s2".
    pub variable: &'static str,
    /// The coordinate the motion is computed in: "x = 1/s1" or "s2".
    pub coordinate: &'static str,
    /// The oscillation segment [λ, μ] in that coordinate.
    pub coordinate_segment: [f64; 2],
    /// The segment in s. For s₁ through infinity (Table 1's `[A (±∞) B]`, B < 0 < A): s₁ runs
    /// from `start` = A up through ±∞ to `end` = B; otherwise `start` ≤ `end`.
    pub start: SegmentEnd,
    pub end: SegmentEnd,
    pub through_infinity: bool,
    /// The segment in Table 1's notation, e.g. "[a, θ2]", "[a (±∞) -a]", "[-b, θ1]".
    pub table1: String,
    /// k² and k′² of the Jacobi functions.
    pub k2: f64,
    pub kc2: f64,
    /// Period in time of the angle on the torus and its angular frequency 2π/period.
    pub period: f64,
    pub frequency: f64,
    pub radicals: [RadicalDescription; 2],
}

/// Everything about one point (m, h) of the admissible region for fields a > b > 0.
#[derive(Clone, Debug, Serialize)]
pub struct PointDescription {
    pub a: f64,
    pub b: f64,
    pub m: f64,
    pub h: f64,
    /// ℓ = √(2p²m² + 2hm + 1).
    pub ell: f64,
    /// θ₁ = (ℓ − 1)/(2m), θ₂ = (ℓ + 1)/(2m), the roots of Φ (θ₂ = ±∞ at m = 0: null).
    #[serde(serialize_with = "finite_or_null")]
    pub theta1: f64,
    #[serde(serialize_with = "finite_or_null")]
    pub theta2: f64,
    /// "I+", "I-", …, "VI".
    pub camera: Camera,
    /// Table 1's order of the roots of Φ among ±a, ±b in this camera.
    pub table1_roots: &'static str,
    /// Number of Liouville tori of the integral manifold.
    pub tori: usize,
    pub s1: VariableDescription,
    pub s2: VariableDescription,
    /// ν₁/ν₂.
    pub rotation_number: f64,
    /// The normal type of N at this level (issue 11): λ² = −4r⁴mℓ², elliptic for m > 0,
    /// hyperbolic for m < 0 (a departure from N grows exponentially).
    pub normal: NormalDescription,
}

/// The normal type of N at a point (m, h).
#[derive(Clone, Debug, Serialize)]
pub struct NormalDescription {
    #[serde(rename = "type")]
    pub kind: NormalType,
    /// λ² = −4r⁴mℓ² of the field of K − 2mL across N.
    pub lambda2: f64,
}

fn radical_descriptions(
    radicands: (&Radicand<f64>, &Radicand<f64>),
    var: &SeparatedVariable<f64>,
) -> [RadicalDescription; 2] {
    let ends = [var.lambda.label, var.mu.label];
    let (sf, sg) = var.signs();
    let one = |r: &Radicand<f64>, sign: i32| RadicalDescription {
        name: r.name,
        constant_sign: r.roots.iter().all(|root| !ends.contains(&root.label)),
        sign_on_torus0: sign,
    };
    [one(radicands.0, sf), one(radicands.1, sg)]
}

fn describe_variable(
    var: &SeparatedVariable<f64>,
    radicands: (&Radicand<f64>, &Radicand<f64>),
    first: bool,
    period: f64,
    frequency: f64,
) -> VariableDescription {
    let (lam, mu) = var.segment();
    let (start, end, through_infinity) = if first {
        // x = 1/s1 on [λ, μ]: s1 = 1/x.
        let s_of = |x: f64, lower_end: bool| {
            if x != 0.0 {
                1.0 / x
            } else if lower_end {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            }
        };
        let s_lam = SegmentEnd {
            label: var.lambda.label,
            value: s_of(lam, true),
        };
        let s_mu = SegmentEnd {
            label: var.mu.label,
            value: s_of(mu, false),
        };
        // x on one side of 0: s1 ∈ [1/μ, 1/λ]; x through 0: s1 runs from A = 1/μ > 0 up to +∞,
        // then from −∞ to B = 1/λ < 0.
        (s_mu, s_lam, lam < 0.0 && mu > 0.0)
    } else {
        (
            SegmentEnd {
                label: var.lambda.label,
                value: lam,
            },
            SegmentEnd {
                label: var.mu.label,
                value: mu,
            },
            false,
        )
    };
    let table1 = if through_infinity {
        format!("[{} (±∞) {}]", start.label, end.label)
    } else {
        format!("[{}, {}]", start.label, end.label)
    };
    VariableDescription {
        variable: if first { "s1" } else { "s2" },
        coordinate: var.name,
        coordinate_segment: [lam, mu],
        start,
        end,
        through_infinity,
        table1,
        k2: var.modulus.k2,
        kc2: var.modulus.kc2,
        period,
        frequency,
        radicals: radical_descriptions(radicands, var),
    }
}

/// Describe the point (m, h) for the fields a > b > 0: its camera and everything about the
/// motion on its tori (see [`PointDescription`]). Errors: a ≤ b or b ≤ 0 or non-finite input
/// ([`ClosedFormError::Parameters`]), a point outside the admissible region
/// ([`ClosedFormError::NotAdmissible`], naming the boundary it is beyond) or on Σ
/// ([`ClosedFormError::OnSigma`], naming the curve).
pub fn describe_point(a: f64, b: f64, m: f64, h: f64) -> Result<PointDescription, ClosedFormError> {
    check_fields(a, b)?;
    let motion = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default())?;
    let c: &IntegralConstants<f64> = &motion.constants;
    let [(t1n, t1d), (t2n, t2d)] = c.thetas();
    let periods = motion.periods();
    let freqs = motion.frequencies();
    let (f1, g1) = c.radicands_x();
    let (f2, g2) = c.radicands_s2();
    let s1 = describe_variable(&motion.first, (&f1, &g1), true, periods[0], freqs[0]);
    let s2 = describe_variable(&motion.second, (&f2, &g2), false, periods[1], freqs[1]);
    Ok(PointDescription {
        a,
        b,
        m,
        h,
        ell: c.ell,
        theta1: t1n / t1d,
        theta2: t2n / t2d,
        camera: motion.camera,
        table1_roots: motion.camera.table1_roots(),
        tori: motion.tori,
        s1,
        s2,
        rotation_number: motion.rotation_number(),
        normal: {
            let n = normal_type(c);
            NormalDescription {
                kind: n.kind,
                lambda2: n.lambda2,
            }
        },
    })
}

fn num(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x.is_infinite() {
        if x > 0.0 { "+∞" } else { "−∞" }.to_string()
    } else if x != 0.0 && (x.abs() >= 1e6 || x.abs() < 1e-4) {
        format!("{x:.6e}")
    } else {
        format!("{x:.6}")
    }
}

impl fmt::Display for PointDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Point (m, h) = ({}, {}) for a = {}, b = {}",
            self.m, self.h, self.a, self.b
        )?;
        writeln!(
            f,
            "  ℓ = {}   θ1 = {}   θ2 = {}",
            num(self.ell),
            num(self.theta1),
            num(self.theta2)
        )?;
        writeln!(
            f,
            "  camera {}   roots of Φ: {}   {}",
            self.camera,
            self.table1_roots,
            tori_text(self.tori)
        )?;
        writeln!(f)?;
        writeln!(
            f,
            "  {:<4} {:<15} {:<36} {:<10} {:<10} {:<12} {:<12} radicals",
            "var", "segment", "numeric (in s)", "k²", "k′²", "period", "frequency"
        )?;
        for v in [&self.s1, &self.s2] {
            let numeric = if v.through_infinity {
                format!("[{} (±∞) {}]", num(v.start.value), num(v.end.value))
            } else {
                format!("[{}, {}]", num(v.start.value), num(v.end.value))
            };
            let radicals: Vec<String> = v
                .radicals
                .iter()
                .map(|r| {
                    if r.constant_sign {
                        format!("{} constant sign", r.name)
                    } else {
                        format!("{} changes sign", r.name)
                    }
                })
                .collect();
            writeln!(
                f,
                "  {:<4} {:<15} {:<36} {:<10} {:<10} {:<12} {:<12} {}",
                v.variable,
                v.table1,
                numeric,
                format!("{:.6}", v.k2),
                format!("{:.6}", v.kc2),
                num(v.period),
                num(v.frequency),
                radicals.join(", ")
            )?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "  x = 1/s1 oscillates on [{}, {}]; rotation number ν1/ν2 = {}",
            num(self.s1.coordinate_segment[0]),
            num(self.s1.coordinate_segment[1]),
            num(self.rotation_number)
        )?;
        let meaning = match self.normal.kind {
            NormalType::Elliptic => "a motion started near N stays near it",
            NormalType::Hyperbolic => "a departure from N (round-off included) grows exponentially",
            NormalType::Degenerate => "degenerate (m = 0 or ℓ = 0)",
        };
        writeln!(
            f,
            "  N is normally {} here (λ² = −4r⁴mℓ² = {}): {meaning}",
            self.normal.kind,
            num(self.normal.lambda2)
        )
    }
}
