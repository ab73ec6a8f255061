//! Dynamics of the Kowalevski top (inertia diag(2, 2, 1)) in two constant force fields, the
//! Reyman–Semenov-Tian-Shansky problem: the Euler–Poisson equations written once over a generic
//! scalar ([`scalar::Real`]: `f64`, `rug::Float`, dual numbers), their first integrals and
//! constraints, the orientation, and integrators behind one interface ([`integrators`]).
//!
//! Small public surface: [`Fields`], [`State`], [`VectorField`], [`integrals()`],
//! [`integrators::Propagator::propagate_grid`].

pub mod dual;
pub mod equations;
pub mod error;
pub mod fields;
pub mod integrals;
pub mod integrators;
pub mod jet;
pub mod number;
pub mod scalar;
pub mod state;
pub mod vec3;

pub use equations::VectorField;
pub use error::DynamicsError;
pub use fields::Fields;
pub use integrals::{integrals, Integrals};
pub use number::{Decimal, NumberError, Times};
pub use scalar::Real;
pub use state::State;

/// A number for a message: at most 4 significant digits, in plain notation for moderate
/// magnitudes (`0.2`, `-1.15`, `3000`, `1.235e-16`, `1e308`). Messages name numbers short;
/// full precision belongs in the data (JSON, CSV).
pub fn short(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == x.trunc() && x.abs() < 1e7 {
        return format!("{}", x as i64);
    }
    let sci = format!("{x:.3e}");
    let rounded: f64 = sci.parse().unwrap_or(x);
    let (mantissa, exponent) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if (-4..7).contains(&exponent) {
        format!("{rounded}")
    } else {
        let m = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{m}e{exponent}")
    }
}

/// `x` exactly as a message shows a value the user gave: as Rust prints it (`0.1`, `2`,
/// `-1.5`) when that takes at most 24 characters, else in its shortest form with an exponent
/// (`1e300`, not 301 digits; `1e-300`, not 300 zeros). Unlike [`short`], nothing is rounded.
pub fn shown(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 24 {
        plain
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod short_tests {
    use super::short;

    #[test]
    fn values_are_shown_whole_but_never_as_hundreds_of_digits() {
        use super::shown;
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(0.1), "0.1");
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-1e-300), "-1e-300");
        assert_eq!(shown(0.30000000000000004), "0.30000000000000004");
        assert_eq!(shown(1e30), "1e30");
    }

    #[test]
    fn numbers_in_messages_are_short() {
        assert_eq!(short(0.2), "0.2");
        assert_eq!(short(0.1 + 0.2), "0.3");
        assert_eq!(short(-1.15), "-1.15");
        assert_eq!(short(2e8), "2e8");
        assert_eq!(short(3000.0), "3000");
        assert_eq!(short(1e9), "1e9");
        assert_eq!(short(1.1102230246251565e-16), "1.11e-16");
        assert_eq!(short(2.5e307), "2.5e307");
        assert_eq!(short(-0.6666666666666666), "-0.6667");
        assert_eq!(short(123456.789), "123500");
        assert_eq!(short(f64::NAN), "NaN");
        assert_eq!(short(0.0), "0");
    }
}
