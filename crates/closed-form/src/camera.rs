//! The cameras (chambers) of the admissible region, labelled as in the seed's Table 1, found from
//! the oscillation segments themselves.

use std::fmt;

use serde::Serialize;

use crate::roots::RootLabel::{self, *};

/// A point (m, h) well inside each camera for a = 1, b = 1/2, found by scanning the (m, h) plane
/// (`cargo run -p rsts-closed-form --example scan`); the tests check each point's camera.
pub const EXAMPLE_POINTS_A1_B05: [(Camera, f64, f64); 9] = [
    (Camera::IPlus, 0.3, -0.375),
    (Camera::IMinus, -1.9244, 0.4503),
    (Camera::IIPlus, 0.05, 1.058),
    (Camera::IIMinus, -0.5573, 1.463),
    (Camera::III, -2.9877, 1.2605),
    (Camera::IVPlus, 0.05, 2.0706),
    (Camera::IVMinus, -0.3295, 1.7668),
    (Camera::V, -0.7092, 1.5643),
    (Camera::VI, -2.9877, 3.2858),
];

/// A camera of Table 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Camera {
    #[serde(rename = "I+")]
    IPlus,
    #[serde(rename = "I-")]
    IMinus,
    #[serde(rename = "II+")]
    IIPlus,
    #[serde(rename = "II-")]
    IIMinus,
    #[serde(rename = "III")]
    III,
    #[serde(rename = "IV+")]
    IVPlus,
    #[serde(rename = "IV-")]
    IVMinus,
    #[serde(rename = "V")]
    V,
    #[serde(rename = "VI")]
    VI,
}

impl Camera {
    pub const ALL: [Camera; 9] = [
        Camera::IPlus,
        Camera::IMinus,
        Camera::IIPlus,
        Camera::IIMinus,
        Camera::III,
        Camera::IVPlus,
        Camera::IVMinus,
        Camera::V,
        Camera::VI,
    ];

    pub fn label(&self) -> &'static str {
        match self {
            Camera::IPlus => "I+",
            Camera::IMinus => "I-",
            Camera::IIPlus => "II+",
            Camera::IIMinus => "II-",
            Camera::III => "III",
            Camera::IVPlus => "IV+",
            Camera::IVMinus => "IV-",
            Camera::V => "V",
            Camera::VI => "VI",
        }
    }

    /// Table 1: the roots of Φ in order with ±a, ±b, as printed.
    pub fn table1_roots(&self) -> &'static str {
        match self {
            Camera::IPlus => "-b < θ1 < b < a < θ2",
            Camera::IMinus => "θ2 < -a < -b < θ1 < b < a",
            Camera::IIPlus => "b < θ1 < a < θ2",
            Camera::IIMinus => "θ2 < -a < -b < b < θ1 < a",
            Camera::III => "-a < θ2 < -b < θ1 < b < a",
            Camera::IVPlus => "a < θ1 < θ2",
            Camera::IVMinus => "θ2 < -a < a < θ1",
            Camera::V => "-a < θ2 < -b < b < θ1 < a",
            Camera::VI => "-a < -b < θ2 < θ1 < b < a",
        }
    }

    /// Table 1: oscillation segments of s₁ and s₂ (`A (±∞) B`: through infinity).
    pub fn table1_segments(&self) -> (&'static str, &'static str) {
        match self {
            Camera::IPlus => ("[a, θ2]", "[-b, θ1]"),
            Camera::IMinus => ("[a (±∞) θ2]", "[-b, θ1]"),
            Camera::IIPlus => ("[a, θ2]", "[-b, b]"),
            Camera::IIMinus => ("[a (±∞) θ2]", "[-b, b]"),
            Camera::III => ("[a (±∞) -a]", "[-b, θ1]"),
            Camera::IVPlus => ("[θ1, θ2]", "[-b, b]"),
            Camera::IVMinus => ("[θ1 (±∞) θ2]", "[-b, b]"),
            Camera::V => ("[a (±∞) -a]", "[-b, b]"),
            Camera::VI => ("[a (±∞) -a]", "[θ2, θ1]"),
        }
    }

    /// The camera from the turning points of s₁ and s₂ (as labels, in any order) and the sign
    /// of m (m = 0 counts as +: the cameras I±, II±, IV± join smoothly across m = 0 in x = 1/s₁).
    pub fn from_segments(s1: [RootLabel; 2], s2: [RootLabel; 2], m_negative: bool) -> Option<Self> {
        let has = |set: [RootLabel; 2], x: RootLabel, y: RootLabel| {
            (set[0] == x && set[1] == y) || (set[0] == y && set[1] == x)
        };
        let s1_a_t2 = has(s1, PlusA, Theta2);
        let s1_pm_a = has(s1, PlusA, MinusA);
        let s1_t1_t2 = has(s1, Theta1, Theta2);
        let s2_b_t1 = has(s2, MinusB, Theta1);
        let s2_pm_b = has(s2, MinusB, PlusB);
        let s2_t2_t1 = has(s2, Theta2, Theta1);
        let sign = |plus, minus| if m_negative { minus } else { plus };
        Some(match () {
            _ if s1_a_t2 && s2_b_t1 => sign(Camera::IPlus, Camera::IMinus),
            _ if s1_a_t2 && s2_pm_b => sign(Camera::IIPlus, Camera::IIMinus),
            _ if s1_t1_t2 && s2_pm_b => sign(Camera::IVPlus, Camera::IVMinus),
            _ if s1_pm_a && s2_b_t1 && m_negative => Camera::III,
            _ if s1_pm_a && s2_pm_b && m_negative => Camera::V,
            _ if s1_pm_a && s2_t2_t1 && m_negative => Camera::VI,
            _ => return None,
        })
    }
}

impl fmt::Display for Camera {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

impl std::str::FromStr for Camera {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Camera::ALL
            .into_iter()
            .find(|c| c.label() == s)
            .ok_or_else(|| format!("unknown camera '{s}' (I+, I-, II+, II-, III, IV+, IV-, V, VI)"))
    }
}
