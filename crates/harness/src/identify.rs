//! Which motion of N a state is on: the document of `rsts identify` and of the Python package's
//! `rsts.identify` (one computation and one serialisation for both).

use serde::Serialize;
use serde_json::{json, Value};

use rsts_closed_form::manifold::{distance, identify, normal_type, Identified, IdentifyError};
use rsts_closed_form::scalar::Scalar;
use rsts_closed_form::IntegralConstants;
use rsts_dynamics::{Fields, Real, State};

/// Bad input, naming the parameters it concerns (`a`, `b`; `omega`, `alpha`, `beta`): the CLI
/// writes them as options, the Python package as its arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct InputError {
    pub parameters: Vec<&'static str>,
    pub message: String,
}

impl InputError {
    fn new(parameters: &[&'static str], message: impl Into<String>) -> Self {
        Self {
            parameters: parameters.to_vec(),
            message: message.into(),
        }
    }
}

/// The state is off N: the document says so (`on_N: false`), and the CLI exits with 1.
#[derive(Clone, Debug, Serialize)]
pub struct OffN {
    #[serde(rename = "on_N")]
    pub on_n: bool,
    #[serde(rename = "distance_from_N")]
    pub distance_from_n: f64,
    #[serde(rename = "relative_distance_from_N")]
    pub relative_distance_from_n: f64,
    pub tolerance: f64,
}

impl OffN {
    /// The one-line message of a state off N.
    pub fn message(&self) -> String {
        format!(
            "not on N (distance {:.3e}, relative {:.3e} > tolerance {:e})",
            self.distance_from_n, self.relative_distance_from_n, self.tolerance
        )
    }
}

/// The normal type of N at the motion (docs/stability.md).
#[derive(Clone, Debug, Serialize)]
pub struct NormalDoc {
    #[serde(rename = "type")]
    pub kind: &'static str,
    pub lambda2: f64,
}

/// A state on N: the motion it is on. Numbers are f64 up to 17 digits, decimal strings beyond.
#[derive(Clone, Debug, Serialize)]
pub struct OnN {
    #[serde(rename = "on_N")]
    pub on_n: bool,
    pub a: Value,
    pub b: Value,
    pub m: Value,
    pub h: Value,
    pub camera: &'static str,
    pub tori: usize,
    pub torus: usize,
    pub phase1: Value,
    pub phase2: Value,
    #[serde(rename = "distance_from_N")]
    pub distance_from_n: f64,
    #[serde(rename = "relative_distance_from_N")]
    pub relative_distance_from_n: f64,
    pub residual: f64,
    pub normal: NormalDoc,
    pub digits: u32,
}

/// The answer of an identification: the document, and the identified values at their precision
/// (for a table in the same digits). Made once per call: the size of a variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Identification<T> {
    OnN(OnN, Identified<T>),
    OffN(OffN),
}

/// A number for JSON: an f64 number up to 17 digits, else a decimal string.
fn number<T: Real>(x: &T, digits: u32) -> Value {
    if digits <= 17 {
        json!(x.to_f64())
    } else {
        json!(x.to_decimal(digits))
    }
}

/// An angle in [0, 2π) for JSON: one that shows as 2π at `digits` digits (2π − ε, ε below the
/// last digit) is 0, the same angle.
fn angle<T: Real>(psi: &T, digits: u32) -> Value {
    let two_pi = T::pi(psi.prec()) * psi.lit(2.0);
    let shown = number(psi, digits);
    if shown == number(&two_pi, digits) {
        number(&psi.zero_like(), digits)
    } else {
        shown
    }
}

/// Identify the motion of N that `state` is on, in fields `a > b > 0`, computing in `T` and
/// reporting `digits` digits; a state whose relative distance from N exceeds `tolerance` is
/// [`Identification::OffN`].
pub fn identify_state<T: Scalar>(
    a: &T,
    b: &T,
    state: &State<T>,
    tolerance: f64,
    digits: u32,
) -> Result<Identification<T>, InputError> {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(InputError::new(
            &["tolerance"],
            format!("must be positive, got {tolerance}"),
        ));
    }
    if !(a.is_finite() && b.is_finite()) {
        return Err(InputError::new(
            &["a", "b"],
            format!(
                "must be finite numbers, got a = {}, b = {}",
                a.to_f64(),
                b.to_f64()
            ),
        ));
    }
    if !(*b > b.zero_like() && a > b) {
        return Err(InputError::new(
            &["a", "b"],
            format!(
                "need a > b > 0 (N exists only there), got a = {}, b = {}",
                a.to_f64(),
                b.to_f64()
            ),
        ));
    }
    // The fields' documented range (docs/closed-form.md), as for every other command.
    if let Err(rsts_closed_form::ClosedFormError::Range(name, why)) =
        rsts_closed_form::check_ranges(a, b, &a.zero_like(), &a.zero_like())
    {
        return Err(InputError {
            parameters: vec![name],
            message: why,
        });
    }
    state
        .validate()
        .map_err(|e| InputError::new(&["omega", "alpha", "beta"], e.to_string()))?;
    let fields = Fields {
        a: a.clone(),
        b: b.clone(),
    };
    let d = distance(&fields, state);
    let relative = d.relative.to_f64();
    if relative > tolerance {
        return Ok(Identification::OffN(OffN {
            on_n: false,
            distance_from_n: d.distance.to_f64(),
            relative_distance_from_n: relative,
            tolerance,
        }));
    }
    let id = identify(a, b, state).map_err(|e| match e {
        IdentifyError::Input(msg) => InputError::new(&["omega", "alpha", "beta"], msg),
        IdentifyError::NoTorus { m, h, reason, .. } => InputError::new(
            &[],
            format!("the state is on N but (m, h) = ({m}, {h}) has no torus: {reason}"),
        ),
    })?;
    let constants = IntegralConstants::unchecked(a.clone(), b.clone(), id.m.clone(), id.h.clone());
    let normal = normal_type(&constants);
    let doc = OnN {
        on_n: true,
        a: number(a, digits),
        b: number(b, digits),
        m: number(&id.m, digits),
        h: number(&id.h, digits),
        camera: id.camera.label(),
        tori: id.tori,
        torus: id.torus,
        phase1: angle(&id.phases[0], digits),
        phase2: angle(&id.phases[1], digits),
        distance_from_n: id.distance.distance.to_f64(),
        relative_distance_from_n: relative,
        residual: id.residual.to_f64(),
        normal: NormalDoc {
            kind: normal.kind.as_str(),
            lambda2: normal.lambda2.to_f64(),
        },
        digits,
    };
    Ok(Identification::OnN(doc, id))
}
