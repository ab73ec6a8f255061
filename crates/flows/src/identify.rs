//! `IdentifyRequest → identify → IdentifyOutcome`: which motion of N a state (ω, α, β) is on —
//! (m, h), camera, torus and the angles (ψ₁, ψ₂) on the torus, the inverse of `explicit` — the
//! document of `rsts identify` and of the Python package's `rsts.identify`.
//!
//! The state and the fields are decimals (or binary64 values, exactly), read at the working
//! precision: the digits asked (17 without: f64 outputs) plus 64 guard bits. Every output is
//! rounded once from there, so a state that `explicit` wrote to D digits gives back its
//! decimals m, h and phases to about D digits (the state itself carries no more).

use serde::Serialize;

use rsts_closed_form::Decimal;
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::State;
use rsts_harness::identify::{identify_state, Identification, OffN, OnN};
use rug::Float;

use crate::FlowError;

/// Digits an identification may carry (without: f64).
pub const DIGITS: std::ops::RangeInclusive<u32> = 16..=100_000;
/// Guard bits of the working precision.
pub const GUARD_BITS: u32 = 64;

/// A state and the fields it is in.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyRequest {
    /// Field strengths, a > b > 0.
    pub a: Decimal,
    pub b: Decimal,
    /// ω, α, β (body frame), in that order.
    pub state: [Decimal; 9],
    /// Largest relative distance from N (distance/|state|) of a state on N.
    pub tolerance: f64,
    /// Digits of the computation and the output (`None`: f64).
    pub digits: Option<u32>,
}

/// The motion found (`on_N: true`) or how far from N the state is (`on_N: false`). Made once
/// per call: the size of a variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum IdentifyOutcome {
    OnN(OnN),
    OffN(OffN),
}

/// The motion of N the state of `request` is on.
pub fn identify(request: &IdentifyRequest) -> Result<IdentifyOutcome, FlowError> {
    if let Some(d) = request.digits {
        if !DIGITS.contains(&d) {
            return Err(FlowError::input(
                &["digits"],
                format!(
                    "must be between {} and {}, got {d}",
                    DIGITS.start(),
                    DIGITS.end()
                ),
            ));
        }
    }
    let digits = request.digits.unwrap_or(17);
    let bits = bits_for_digits(digits) + GUARD_BITS;
    let x: [Float; 9] = std::array::from_fn(|k| request.state[k].to_float(bits));
    let state = State::from_slice(&x);
    let (a, b) = (request.a.to_float(bits), request.b.to_float(bits));
    match identify_state(&a, &b, &state, request.tolerance, digits) {
        Err(e) => Err(FlowError::input(&e.parameters, e.message)),
        Ok(Identification::OffN(off)) => Ok(IdentifyOutcome::OffN(off)),
        Ok(Identification::OnN(doc, _)) => Ok(IdentifyOutcome::OnN(doc)),
    }
}
