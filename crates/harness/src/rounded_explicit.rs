//! The f64 output of `rsts explicit` correctly rounded: ω, α, β, γ, Ω from the closed form in
//! double-double, each value rounded to f64 when Ziv's test decides it
//! ([`rsts_closed_form::rounded`]), the row otherwise computed in MPFR (30 digits + 64 guard
//! bits, as `rsts reference`) and rounded. The result is the MPFR row rounded, bit for bit
//! (tests/harness/rounded_explicit.rs), the cheapest scalar that is exact enough (issue 21, item 2).

use rug::Float;

use rsts_closed_form::rounded::{calibration_times, RoundingBounds};
use rsts_closed_form::{ExplicitMotion, ExplicitState};
use rsts_dynamics::scalar::{bits_for_digits, DoubleDouble};
use rsts_dynamics::Real;

use crate::case::Case;
use crate::{HarnessError, REFERENCE_GUARD_BITS};

/// Values of an explicit row: ω, α, β, γ, Ω.
pub const EXPLICIT_VALUES: usize = 15;

/// The 15 values of a closed-form state, in the order of the explicit output.
fn values<T: Clone>(s: &ExplicitState<T>) -> [T; EXPLICIT_VALUES] {
    let vs = [&s.omega, &s.alpha, &s.beta, &s.gamma, &s.omega_fixed];
    std::array::from_fn(|j| vs[j / 3][j % 3].clone())
}

/// The closed form of a case in double-double and in MPFR, for correctly rounded f64 rows.
pub struct RoundedExplicit {
    /// `None` when the motion cannot be built in double-double: every row from MPFR.
    dd: Option<ExplicitMotion<DoubleDouble>>,
    mp: ExplicitMotion<Float>,
    bounds: RoundingBounds<EXPLICIT_VALUES>,
}

impl RoundedExplicit {
    /// The motion of `case` (a, b, m, h, torus, phases) with its phase clocks built for |t| ≤
    /// `t_max`.
    pub fn new(case: &Case, t_max: f64) -> Result<Self, HarnessError> {
        case.validate()?;
        let mp = case
            .motion
            .explicit::<Float>(bits_for_digits(30) + REFERENCE_GUARD_BITS, t_max)?;
        let dd_bits = DoubleDouble::from_f64_exact(0.0).prec();
        let dd = case.motion.explicit::<DoubleDouble>(dd_bits, t_max).ok();
        let mut me = Self {
            dd,
            mp,
            bounds: RoundingBounds {
                bounds: [0.0; EXPLICIT_VALUES],
            },
        };
        if let Some(dd) = &me.dd {
            let times = calibration_times(dd.periods().map(|p| p.to_f64()));
            me.bounds =
                RoundingBounds::calibrate(&times, |t| values(&dd.at_f64(t)), |t| me.mp_values(t));
        }
        Ok(me)
    }

    fn mp_values(&self, t: f64) -> [Float; EXPLICIT_VALUES] {
        values(&self.mp.at(&Float::with_val(self.mp.constants.a.prec(), t)))
    }

    /// The row at `t` rounded from MPFR (the slow path, and what [`Self::row`] equals).
    pub fn row_mpfr(&self, t: f64) -> [f64; EXPLICIT_VALUES] {
        self.mp_values(t).map(|x| x.to_f64())
    }

    /// The row at `t` correctly rounded to f64: from double-double where Ziv's test decides
    /// every value, else from MPFR.
    pub fn row(&self, t: f64) -> [f64; EXPLICIT_VALUES] {
        self.dd
            .as_ref()
            .and_then(|dd| self.bounds.round(&values(&dd.at_f64(t))))
            .unwrap_or_else(|| self.row_mpfr(t))
    }
}
